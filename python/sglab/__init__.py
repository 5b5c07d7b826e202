"""sglab from Python: spherical Gaussian lighting math with exact references, numpy in and out.

The same code as the ``sglab`` command (C++), not a re-implementation:

- ``quantities()``, ``methods(quantity)``: the method registry (``sglab eval --list``), with each
  method's source, known flaws and published constants.
- ``eval(quantity, method, *, precision=None, constants=None, **columns)``: a method on numpy
  arrays, with the checks and results of ``sglab eval`` (``constants=``: its ``--constants``).
- ``fits()``, ``fit(name, objective=None, precision=None)``: the Ceres fits of ``sglab fit``, the
  record as a dict (the JSON of ``sglab fit NAME --json FILE``).
- ``render(scene, **options)``: ``sglab render`` into numpy arrays and the stats dict.
- ``sglab.plots``: the figures of ``plots/`` drawn straight from these results.

Example::

    import numpy as np, sglab
    lam = np.logspace(-3, 4, 8)[:, None]          # broadcasts against the cosines
    c = np.linspace(-1, 1, 5, dtype=np.float64)
    d = sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam, cosine=c)   # shape (8, 5)
    ref = sglab.eval("clamped-cosine", "reference", sharpness=lam, cosine=c)
"""
from __future__ import annotations

import builtins
import importlib
import json
import os
import sys
import tempfile
from typing import Any, Mapping, Sequence

import numpy as np

from . import _sglab

__all__ = ["quantities", "methods", "eval", "fits", "fit", "render", "PRECISIONS"]

#: Precisions of ``eval``: float (float32), double (float64), mp50 (50 decimal digits).
PRECISIONS = ("float", "double", "mp50")


def quantities() -> list[dict[str, Any]]:
    """Every quantity of the registry, in a stable order.

    Each entry: ``name``, ``description``, ``columns`` (list of ``{name, kind, description}``: the
    keyword arguments ``eval`` takes), ``reference_method`` (the method the others are measured
    against, "" if none) and ``methods`` (names; details from ``methods(quantity)``).
    """
    return _sglab.quantities()


def methods(quantity: str) -> list[dict[str, Any]]:
    """The methods of ``quantity``: ``name``, ``source`` (paper and equation), ``flaws`` (known
    flaws as published, "" if none), ``may_be_negative`` (the published form goes negative and is
    kept so, to measure it), ``has_domain_check`` (the method rejects some inputs its columns
    accept, e.g. sharpness 0 for a 2π/λ form), ``reference`` (it is the quantity's reference) and
    ``parameters``: the method's constants (empty if none), each ``{name, fit, published, source}``
    as ``sglab eval --list --json`` lists them: the name in the fit record, the ``sglab fit`` that
    re-derives it ("" if none), the published value and its paper and equation. ``eval``'s
    ``constants=`` replaces them.

    Raises ValueError for an unknown quantity, listing the valid ones.
    """
    return _sglab.methods(quantity)


def _quantity(name: str) -> dict[str, Any]:
    for q in _sglab.quantities():
        if q["name"] == name:
            return q
    _sglab.methods(name)  # raises ValueError naming the valid quantities
    raise AssertionError("unreachable")


def _as_array(value: Any, name: str) -> np.ndarray:
    a = np.asarray(value)
    if a.dtype.kind not in "fiub" or a.dtype.itemsize > 8:
        raise ValueError(f"column '{name}': expected real numbers, got an array of dtype {a.dtype}")
    return a


class _ConstantSets:
    """``constants=`` as the arguments of ``--constants``, in order: paths (str or os.PathLike),
    "published", and fit records as dicts (``sglab.fit``'s result, or a hand-written ``{"fit": …,
    "parameters": {…}}``), each written as JSON to a temporary file for the call. Used as a
    context manager (the files are removed after the call); messages name a record as
    ``<constants record N>`` instead of its temporary path."""

    def __init__(self, constants: Any):
        self.constants = constants
        self.paths: list[str] = []
        self._dir = None
        self._names: dict[str, str] = {}

    def __enter__(self) -> list[str]:
        c = self.constants
        if c is None:
            return []
        items = [c] if isinstance(c, (str, os.PathLike, Mapping)) else c
        if not isinstance(items, (list, tuple)) or not all(isinstance(x, (str, os.PathLike, Mapping)) for x in items):
            raise ValueError("constants: expected a path (str or os.PathLike), 'published', a fit record (dict, as "
                             f"sglab.fit returns), or a list of them, got {_clip(repr(c))}")
        for k, x in enumerate(items):
            if isinstance(x, Mapping):
                if self._dir is None:
                    self._dir = tempfile.TemporaryDirectory(prefix="sglab-constants-")
                path = os.path.join(self._dir.name, f"record-{k}.json")
                try:
                    text = json.dumps(x, allow_nan=False)
                except (TypeError, ValueError) as e:
                    raise ValueError(f"constants: record {k} is not JSON: {_clip(str(e))}") from None
                with open(path, "w") as f:
                    f.write(text)
                self._names[path] = f"<constants record {k}>"
                self.paths.append(path)
            else:
                p = os.fspath(x)
                if not isinstance(p, str):
                    raise ValueError(f"constants: expected a str path, got {_clip(repr(x))}")
                self.paths.append(p)
        return self.paths

    def __exit__(self, kind, error, tb) -> bool:
        if self._dir is not None:
            self._dir.cleanup()
        if isinstance(error, ValueError) and self._names:
            text = str(error)
            for path, name in self._names.items():
                text = text.replace(path, name)
            raise ValueError(text) from None
        return False


def _clip(text: str, limit: int = 80) -> str:
    """At most ``limit`` characters of a bad value, as the command's messages quote them."""
    return text if len(text) <= limit else text[:limit] + f"… ({len(text)} characters)"


def eval(quantity: str, method: str, *, precision: str | None = None, constants: Any = None,
         vectorized: bool = False, **columns: Any) -> Any:
    """Evaluate ``method`` of ``quantity`` on numpy arrays; the checks and results of ``sglab eval``.

    Columns are keyword arguments named after the quantity's columns (``sharpness=``, ``cosine=``,
    …; see ``quantities()``): numbers, sequences or numpy arrays, which broadcast against each
    other like numpy operands. The result has the broadcast shape (a numpy scalar for scalar
    inputs).

    ``precision``:
      - None: float32 if the inputs are float32 (or float16), otherwise float64; float32 in gives
        float32 out, float64 gives float64, integers are taken as float64.
      - "float" or "double": cast the inputs to float32 or float64 first.
      - "mp50": the method in 50 significant digits. Columns may then hold decimal strings
        (parsed to 50 digits, as ``sglab eval`` reads its CSV) or floats (taken exactly); the
        result is an object array of 50-digit strings, the text ``sglab eval --precision mp50``
        prints (``float(s)`` or ``mpmath.mpf(s)`` reads them).

    Inputs whose dtype already matches are read in place through their strides (no copy, also
    for broadcast and non-contiguous views; float32 stays float32, evaluated in float); the batch
    loop runs with the GIL released, on all cores. The column checks run once per chunk of
    contiguous inputs (the chunk's extremes against the column's domain), not per value.

    ``vectorized``: False (default): every value equals ``sglab eval``'s to the last bit (the
    methods with a vectorized batch evaluator (docs/simd.md lists them) run row by row
    through their scalar definition, as ``sglab eval`` does; the others through their batch
    evaluator, the same definition). True: every method through its batch evaluator, the
    registry's vectorized kernels where it has one (docs/simd.md: within a few ulp of the scalar
    definition, not bit for bit); the checks and errors are the same. Ignored for "mp50".

    ``constants``: a constant set replacing the method's published constants (see ``methods()``:
    ``parameters``), as ``sglab eval --constants``: a fit record (the JSON of ``sglab fit NAME
    --json FILE``, or a hand-written ``{"fit": "tokuyoshi2024-t", "parameters": {"A": …, …}}``),
    a directory of them (``sglab fit all --json-dir DIR``), or "published" (every constant back to
    its published value); a path (str or os.PathLike) or a list of them, later sets overriding
    earlier ones. Constants of other methods in the set are ignored. None: the published values.

    Raises:
      ValueError: an unknown quantity, method or precision; a bad constant set (unreadable file,
        not a fit record, unknown fit or parameter, a value missing, not a number or outside its
        domain: the message names the file and the key); a missing or unknown column; shapes
        that do not broadcast; a value outside its column's domain (a negative sharpness,
        |cosine| > 1 + 1e-6, NaN, …) or outside the method's domain (e.g. sharpness 0 for a 2π/λ
        form). The message names the column, the index (in the broadcast shape) and the value.
      FloatingPointError: the method returned NaN or an infinity (never returned silently).
      RuntimeError: the method failed (e.g. a quadrature did not converge), naming the index.
    """
    _check_name("quantity", quantity)
    _check_name("method", method)
    if not isinstance(vectorized, bool):
        raise ValueError(f"vectorized: expected True or False, got {_clip(repr(vectorized))}")
    with _ConstantSets(constants) as sets:
        return _eval(quantity, method, precision, sets, columns, vectorized)


def _check_name(what: str, value: Any) -> None:
    """A name argument must be a str: anything else is a ValueError naming it (not a TypeError
    from deep inside)."""
    if not isinstance(value, str):
        raise ValueError(f"{what}: expected a name (str), got {_clip(repr(value))}")


def _mp50_value(x: Any, name: str, index: int) -> Any:
    """One element of an mp50 column: a decimal string as it is, a Python int as its exact
    decimal text, a real number as a float; anything else is a ValueError naming the column."""
    if isinstance(x, str):
        return x
    if not isinstance(x, (int, builtins.float, np.integer, np.floating, np.bool_)):
        raise ValueError(f"column '{name}', flat index {index}: expected a real number or a decimal string, got "
                         f"{_clip(repr(x))}")
    return str(int(x)) if isinstance(x, (int, np.integer)) else builtins.float(x)


def _eval(quantity: str, method: str, precision: str | None, sets: list[str], columns: Mapping[str, Any],
          vectorized: bool = False) -> Any:
    q = _quantity(quantity)
    names = [c["name"] for c in q["columns"]]
    missing = [n for n in names if n not in columns]
    unknown = [n for n in columns if n not in names]
    if missing or unknown:
        problem = "; ".join(
            ([f"missing column(s) {', '.join(missing)}"] if missing else [])
            + ([f"unknown column(s) {', '.join(unknown)}"] if unknown else []))
        raise ValueError(f"sglab.eval('{quantity}', '{method}'): {problem}; quantity '{quantity}' takes the "
                         f"columns {', '.join(names)}")
    if precision is not None and (not isinstance(precision, str) or precision not in PRECISIONS):
        raise ValueError(f"unknown precision '{precision}'; valid precisions: {', '.join(PRECISIONS)}")
    values = [columns[n] for n in names]

    if precision == "mp50":
        arrays = [np.asarray(v, dtype=object) for v in values]
        try:
            arrays = np.broadcast_arrays(*arrays)
        except ValueError:
            shapes = ", ".join(f"{n} {a.shape}" for n, a in zip(names, arrays))
            raise ValueError(f"sglab.eval('{quantity}', '{method}'): the columns do not broadcast: {shapes}") from None
        shape = arrays[0].shape if arrays else ()
        flat = [[_mp50_value(x, n, i) for i, x in enumerate(a.ravel().tolist())] for n, a in zip(names, arrays)]
        text = _sglab.eval_mp50(quantity, method, flat, list(shape), sets)
        out = np.empty(len(text), dtype=object)
        out[:] = text
        out = out.reshape(shape)
        return out[()] if out.ndim == 0 else out

    arrays = [_as_array(v, n) for n, v in zip(names, values)]
    if precision == "float":
        dtype = np.dtype(np.float32)
    elif precision == "double":
        dtype = np.dtype(np.float64)
    else:
        # Scalars (Python numbers) do not widen float32 arrays, as in numpy arithmetic.
        kind = np.result_type(*[v if np.isscalar(v) else a for v, a in zip(values, arrays)])
        dtype = np.dtype(np.float32) if kind.kind == "f" and kind.itemsize <= 4 else np.dtype(np.float64)
    arrays = [np.asarray(a, dtype=dtype) for a in arrays]  # no copy when the dtype matches
    try:
        arrays = np.broadcast_arrays(*arrays)  # views: broadcast axes get stride 0
    except ValueError:
        shapes = ", ".join(f"{n} {a.shape}" for n, a in zip(names, arrays))
        raise ValueError(f"sglab.eval('{quantity}', '{method}'): the columns do not broadcast: {shapes}") from None
    native = _sglab.eval_float if dtype == np.float32 else _sglab.eval_double
    out = native(quantity, method, arrays, sets, vectorized)
    return out[()] if out.ndim == 0 else out


def fits() -> list[dict[str, Any]]:
    """Every fitter of ``sglab fit``: ``name``, ``description``, ``objectives`` (the first is the
    default)."""
    return _sglab.fits()


def fit(name: str, objective: str | None = None, precision: str | None = None, *, verbose: bool = False) -> dict[str, Any]:
    """Run one Ceres fit (``sglab fit NAME``) and return its record, the same dict as the JSON of
    ``sglab fit NAME --json FILE``: fit, objective, domain, parameters, published,
    relative_difference (None where nothing is published), final_cost, iterations, converged,
    seconds, objective_at_published, objective_at_fit, singular_values, cost_range_1pct,
    precision and, when a registry method reads the fit's constants, standard_grid_error (that
    method's error on ``sglab error-vs-time``'s grid with the published and the fitted values).
    The record is a constant set: ``eval(..., constants=record)`` and ``render(...,
    constants=record)`` take it as it is (or saved as JSON, by path).

    ``objective``: one of ``fits()``'s objectives for ``name`` (default: its first).
    ``precision``: half, float or double (default float): the precision of the rounding terms of
    the cosine-sharpness and cosine-sg l2-rounding objectives.
    ``verbose``: a line on stderr when the fit is done (default: nothing on stderr).
    Raises ValueError for an unknown fit, objective or precision (or one that is not a str).
    """
    _check_name("fit", name)
    for what, value in (("objective", objective), ("precision", precision)):
        if value is not None:
            _check_name(what, value)
    record = json.loads(_sglab.fit(name, objective or "", precision or "float"))
    if verbose:
        print(f"sglab.fit: {record['fit']} [{record['objective']}]: {'converged' if record['converged'] else 'NOT converged'} "
              f"after {record['iterations']} iterations, {record['seconds']:.3f} s", file=sys.stderr)
    return record


#: ``render()``'s keyword arguments for the options of ``sglab render`` (the CLI word without its
#: dashes, '-' as '_'), and the one whose name differs: ``overrides`` is ``--set``.
_RENDER_OPTION_NAMES = {"set": "overrides"}


def render(scene: str | os.PathLike | Mapping[str, Any], *, vsgl: str | None = None, count: int | None = None,
           diffuse: str | None = None, specular: str | None = None, rsm: int | None = None,
           shadow_map: int | None = None, width: int | None = None, height: int | None = None,
           seed: int | None = None, overrides: Sequence[str] | Mapping[str, Any] = (),
           kmeans_space: str | None = None, visibility: bool = False, sg_cosine_a_pi: bool = False,
           precision: str | None = None, reference_precision: str | None = None, constants: Any = None,
           verbose: bool = False) -> dict[str, Any]:
    """Render a scene as ``sglab render`` does and return the images and stats.

    ``scene``: a scene JSON file (schema: scenes/README.md) or the scene as a dict (an
    environment's relative paths are then taken from the working directory).
    Options: every option of ``sglab render`` (``sglab render --help``), with the same names,
    values, defaults and checks (they are parsed by the command's own option parser): ``vsgl``
    (two, two-shared, fis, kmeans), ``count``, ``diffuse`` (a clamped-cosine method),
    ``specular`` (a specular method, or vsgl-asg), ``rsm``, ``shadow_map``, ``width``/``height``
    (override the camera), ``seed``, ``overrides`` ("KEY=VALUE" strings or a {KEY: VALUE} dict,
    as ``--set``: e.g. {"floor.roughness": 0.1}), ``kmeans_space`` (world, image),
    ``visibility``, ``sg_cosine_a_pi``, ``precision`` and ``reference_precision`` (double,
    float), ``constants`` (as ``eval``'s: paths, "published", fit records as dicts).
    ``verbose``: progress on stderr (default: nothing on stderr).

    Returns a dict: ``direct``, ``indirect``, ``indirect_reference`` (the exact VPL sum) and
    ``error`` (indirect − reference) as (height, width, 3) float64 arrays (row 0 is the top of the
    image; the EXR of ``sglab render`` stores the same values in float32), for a scene with an
    environment also its layers (``environment_map`` when it has a map, ``environment_mixture``,
    ``environment_approx``), ``hit`` (height, width) bool (pixels that see geometry), and
    ``stats`` (the stats JSON of ``sglab render --stats``, as a dict, with ``environment`` for
    such a scene).
    Raises ValueError for a bad scene (a missing or unreadable environment map, an unknown
    method, …) or option, naming the field and the value, as the command exits with status 2.
    """
    if isinstance(overrides, Mapping):
        overrides = [f"{k}={json.dumps(v) if not isinstance(v, str) else v}" for k, v in overrides.items()]
    elif isinstance(overrides, (str, bytes)) or not isinstance(overrides, Sequence):
        raise ValueError(f"overrides: expected KEY=VALUE strings or a dict, got {_clip(repr(overrides))}")
    else:
        overrides = [str(o) for o in overrides]
    words: list[str] = []
    values = {"vsgl": vsgl, "count": count, "diffuse": diffuse, "specular": specular, "rsm": rsm,
              "shadow-map": shadow_map, "width": width, "height": height, "seed": seed,
              "kmeans-space": kmeans_space, "precision": precision, "reference-precision": reference_precision}
    for option, value in values.items():
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (str, int, np.integer)):
            raise ValueError(f"{option.replace('-', '_')}: expected a {'name' if option in ('vsgl', 'diffuse', 'specular') else 'value'}, "
                             f"got {_clip(repr(value))}")
        words += [f"--{option}", str(value)]
    for o in overrides:
        words += ["--set", o]
    if visibility:
        words.append("--visibility")
    if sg_cosine_a_pi:
        words.append("--sg-cosine-a-pi")
    if isinstance(scene, Mapping):
        try:
            text, is_text, source = json.dumps(scene, allow_nan=False), True, "<scene dict>"
        except (TypeError, ValueError) as e:
            raise ValueError(f"scene: the dict is not JSON: {_clip(str(e))}") from None
    elif isinstance(scene, (str, os.PathLike)):
        text, is_text, source = os.fspath(scene), False, os.fspath(scene)
        if not isinstance(text, str):
            raise ValueError(f"scene: expected a str path or a dict, got {_clip(repr(scene))}")
    else:
        raise ValueError(f"scene: expected a path or a dict, got {_clip(repr(scene))}")
    with _ConstantSets(constants) as sets:
        for path in sets:
            words += ["--constants", path]
        return _sglab.render(text, is_text, source, words, bool(verbose))


def __getattr__(name: str) -> Any:
    """``sglab.plots`` without an explicit import (matplotlib is loaded on first use only)."""
    if name == "plots":
        return importlib.import_module(".plots", __name__)
    raise AttributeError(f"module 'sglab' has no attribute '{name}'")
