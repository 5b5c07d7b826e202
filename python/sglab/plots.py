"""Figures straight from ``sglab`` results, without the CSV round trip of ``plots/``.

The drawing code is that of the scripts in ``plots/`` (``render_images.py``,
``near_wall_vsgl_vs_vpl_sum.py``), which ``sglab reproduce`` runs on the CSV dumps of ``sglab render``;
here it takes the arrays of ``sglab.render`` and ``sglab.eval`` directly. The CSV and JSON outputs
of the ``sglab`` command stay as they are, for other languages.

Figures are returned (matplotlib), shown by a notebook as usual; ``save(fig, path)`` writes one
atomically.
"""
from __future__ import annotations

import os
from typing import Any, Mapping, Sequence

import numpy as np

from ._plots import _common
from ._plots import near_wall_vsgl_vs_vpl_sum as _near_wall_vsgl_vs_vpl_sum
from ._plots import render_images as _render_images

__all__ = ["render_figure", "smape_map", "smape_figure", "method_error", "save"]


def render_figure(result: Mapping[str, Any], title: str | None = None):
    """The five panels of ``plots/render_images.py`` for one ``sglab.render`` result: direct +
    VSGL indirect, direct + exact VPL sum, the two indirect layers, and the signed error."""
    if title is None:
        stats = result.get("stats", {})
        title = f"{stats.get('scene', '')}  ({stats.get('command', '')})"
    return _render_images.figure(result, title)


def smape_map(result: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """Per-pixel SMAPE of the VSGL indirect light against the exact VPL sum (channel mean), and
    the mask of pixels where either is non-zero (``plots/near_wall_vsgl_vs_vpl_sum.py``)."""
    return _near_wall_vsgl_vs_vpl_sum.smape_map(result)


def smape_figure(results: Mapping[str, Mapping[str, Any]] | Sequence[tuple[str, Mapping[str, Any]]]):
    """The near-wall figure of ``plots/near_wall_vsgl_vs_vpl_sum.py``: one SMAPE map per label (a diffuse
    method), from ``sglab.render`` results, e.g. ``{m: sglab.render(scene, diffuse=m) for m in …}``."""
    items = list(results.items()) if isinstance(results, Mapping) else list(results)
    return _near_wall_vsgl_vs_vpl_sum.figure(items)


def method_error(quantity: str, methods: Sequence[str], *, relative_to: float | np.ndarray | None = None,
                 precision: str | None = None, **columns: Any) -> dict[str, np.ndarray]:
    """Each method's error against the quantity's reference method on the same points (the
    comparison ``sglab error-vs-time`` and ``sglab error-map`` tabulate from CSV), as arrays:
    ``{method: value − reference}``, divided by ``relative_to`` when given. Columns broadcast as in
    ``sglab.eval``; the reference is evaluated once, in double (or in ``precision``)."""
    from . import eval as sg_eval, quantities

    q = next((q for q in quantities() if q["name"] == quantity), None)
    if q is None or not q["reference_method"]:
        raise ValueError(f"quantity '{quantity}' has no reference method")
    ref = np.asarray(sg_eval(quantity, q["reference_method"], precision=precision or "double", **columns), dtype=float)
    out = {}
    for m in methods:
        err = np.asarray(sg_eval(quantity, m, precision=precision, **columns), dtype=float) - ref
        out[m] = err / relative_to if relative_to is not None else err
    return out


def save(fig, path: str | os.PathLike, **savefig_args) -> None:
    """Write ``fig`` to ``path`` (format from the extension) via a temporary file and a rename, so
    that a figure is never half-written."""
    _common.save_figure(fig, path, **savefig_args)
