# Type stubs of the sglab module (signatures for editors; the docstrings are in __init__.py).
import os
from typing import Any, Literal, Mapping, Sequence, TypedDict

import numpy as np
import numpy.typing as npt


PRECISIONS: tuple[str, str, str]

class ColumnInfo(TypedDict):
    name: str
    kind: str
    description: str

class QuantityInfo(TypedDict):
    name: str
    description: str
    columns: list[ColumnInfo]
    reference_method: str
    methods: list[str]

class ParameterInfo(TypedDict):
    name: str
    fit: str
    published: float
    source: str

class MethodInfo(TypedDict):
    name: str
    source: str
    flaws: str
    may_be_negative: bool
    has_domain_check: bool
    reference: bool
    parameters: list[ParameterInfo]

class FitInfo(TypedDict):
    name: str
    description: str
    objectives: list[str]

ConstantSet = str | os.PathLike[str] | Mapping[str, Any]

def quantities() -> list[QuantityInfo]: ...
def methods(quantity: str) -> list[MethodInfo]: ...
def eval(
    quantity: str,
    method: str,
    *,
    precision: Literal["float", "double", "mp50"] | None = None,
    constants: ConstantSet | Sequence[ConstantSet] | None = None,
    vectorized: bool = False,
    **columns: npt.ArrayLike,
) -> np.ndarray | np.floating[Any] | str: ...
def fits() -> list[FitInfo]: ...
def fit(
    name: str,
    objective: str | None = None,
    precision: Literal["half", "float", "double"] | None = None,
    *,
    verbose: bool = False,
) -> dict[str, Any]: ...
def render(
    scene: str | os.PathLike[str] | Mapping[str, Any],
    *,
    vsgl: Literal["two", "two-shared", "fis", "kmeans"] | None = None,
    count: int | None = None,
    diffuse: str | None = None,
    specular: str | None = None,
    rsm: int | None = None,
    shadow_map: int | None = None,
    width: int | None = None,
    height: int | None = None,
    seed: int | None = None,
    overrides: Sequence[str] | Mapping[str, Any] = (),
    kmeans_space: Literal["world", "image"] | None = None,
    visibility: bool = False,
    sg_cosine_a_pi: bool = False,
    precision: Literal["double", "float"] | None = None,
    reference_precision: Literal["double", "float"] | None = None,
    constants: ConstantSet | Sequence[ConstantSet] | None = None,
    verbose: bool = False,
) -> dict[str, Any]: ...

from . import plots as plots
