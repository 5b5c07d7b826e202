#!/usr/bin/env python3
"""Error maps of the diffuse methods over (λ, c), like the error plots of the Tokuyoshi 2022
poster (Tokuyoshi 2022).

Reads the long-format CSV written by `sglab error-map` (error_map.csv: method, sharpness, cosine,
reference, value, error, smape) and draws, per method, the signed error (method − reference)/D(λ, 1)
on a diverging, symmetric-log colour scale with the ±1 % contour, λ on a log axis; then one combined
figure of every method on a common scale, and one of the poster's SMAPE. Writes
error_map_<method>.{png,pdf}, error_maps.{png,pdf} and error_maps_smape.{png,pdf} into the output
directory (--quick: PNG only), each through a temporary file and a rename. Computes nothing the
CSV does not hold.
usage: error_maps.py ERROR_MAP.csv OUT_DIR [--quick]
"""
import csv
import math
import os
import re
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LogNorm, SymLogNorm  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402
import numpy as np  # noqa: E402
from _common import save_figures  # noqa: E402

LINTHRESH = 1e-4  # below 0.01 % the colour scale is linear


FORMATS = ["png", "pdf"]  # --quick: PNG only


def save(fig, out_dir, stem):
    save_figures(fig, out_dir, stem, FORMATS, dpi=120)


def plain_log_x(ax):
    """Log λ axis with plain labels (1e-3, 0.1, 10, …): mathtext labels cost seconds per figure."""
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(LogLocator(base=10, numticks=8))
    ax.xaxis.set_major_formatter(FuncFormatter(
        lambda v, _: f"{v:g}" if 0.01 <= v < 1000 else f"1e{int(round(math.log10(v)))}" if v > 0 else ""))
    ax.xaxis.set_minor_formatter(NullFormatter())


def percent(v):
    return "0" if v == 0 else f"{100 * v:+.3g} %"


def signed_colorbar(fig, mappable, vmax, **kw):
    """A colour bar for the symmetric-log scale with ticks at ±decades, labelled in percent."""
    decades = [10.0 ** k for k in range(int(math.floor(math.log10(LINTHRESH))), int(math.ceil(math.log10(vmax))) + 1)
               if 10.0 ** k <= vmax * 1.0001]
    ticks = [-d for d in reversed(decades)] + [0.0] + decades
    cb = fig.colorbar(mappable, ticks=ticks, **kw)
    cb.ax.set_yticklabels([percent(t) for t in ticks])
    cb.ax.yaxis.set_minor_formatter(NullFormatter())
    cb.set_label("signed error / D(λ, 1)")
    return cb


def to_float(s):
    return float(s) if s not in ("",) else math.nan


def load(src):
    """{method: (lambdas, cosines, error[c, λ], smape[c, λ])} from the long CSV."""
    raw = OrderedDict()
    with open(src, newline="") as f:
        # By column index (DictReader costs seconds on the 360k rows); provenance lines skipped.
        reader = csv.reader(line for line in f if not line.startswith("#"))
        col = {name: k for k, name in enumerate(next(reader))}
        km, kl, kc, ke, ks = (col[c] for c in ("method", "sharpness", "cosine", "error", "smape"))
        for r in reader:
            raw.setdefault(r[km], []).append((float(r[kl]), float(r[kc]), to_float(r[ke]), to_float(r[ks])))
    out = OrderedDict()
    for method, rows in raw.items():
        ls = sorted({r[0] for r in rows})
        cs = sorted({r[1] for r in rows})
        li = {v: i for i, v in enumerate(ls)}
        ci = {v: j for j, v in enumerate(cs)}
        err = np.full((len(cs), len(ls)), np.nan)
        sm = np.full((len(cs), len(ls)), np.nan)
        for l, c, e, s in rows:
            err[ci[c], li[l]] = e
            sm[ci[c], li[l]] = s
        out[method] = (np.array(ls), np.array(cs), err, sm)
    return out


def edges(v, log):
    """Cell edges around sorted centres (geometric midpoints on a log axis)."""
    v = np.asarray(v, dtype=float)
    if log:
        lv = np.log10(v)
        mid = (lv[1:] + lv[:-1]) / 2
        return 10 ** np.concatenate(([lv[0] - (mid[0] - lv[0])], mid, [lv[-1] + (lv[-1] - mid[-1])]))
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate(([v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]))


def draw_signed(ax, ls, cs, err, vmax, title):
    norm = SymLogNorm(linthresh=LINTHRESH, vmin=-vmax, vmax=vmax, base=10)
    m = ax.pcolormesh(edges(ls, True), edges(cs, False), np.ma.masked_invalid(err), cmap="RdBu_r", norm=norm,
                      shading="flat", rasterized=True)
    finite = np.isfinite(err)
    if finite.any() and np.nanmax(np.abs(err)) > 0.01:
        ax.contour(ls, cs, np.where(finite, np.abs(err), 0), levels=[0.01], colors="k", linewidths=0.6)
    plain_log_x(ax)
    ax.set_xlabel("sharpness λ")
    ax.set_ylabel("cosine c = ξ·n")
    ax.set_title(title, fontsize=9)
    return m


def draw_method(data, out_dir, method):
    """One figure per method, its own symmetric range."""
    ls, cs, err, _ = data[method]
    vmax = float(np.nanmax(np.abs(err))) if np.isfinite(err).any() else 1.0
    vmax = max(vmax, 10 * LINTHRESH)
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    fig.subplots_adjust(left=0.12, right=0.9, bottom=0.12, top=0.92)
    m = draw_signed(ax, ls, cs, err, vmax, f"{method}: (method − reference)/D(λ, 1); black: |error| = 1 %")
    signed_colorbar(fig, m, vmax, ax=ax)
    save(fig, out_dir, "error_map_" + re.sub(r"[^A-Za-z0-9_.-]", "_", method))
    plt.close(fig)


def grid_shape(data):
    n = len(data)
    cols = min(4, n)
    return cols, (n + cols - 1) // cols


def draw_combined(data, out_dir):
    """Every method on one common scale (clipped at ±100 %)."""
    n = len(data)
    cols, rows = grid_shape(data)
    vmax = min(1.0, max(float(np.nanmax(np.abs(e[2]))) for e in data.values() if np.isfinite(e[2]).any()))
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    mappable = None
    for ax, (method, (ls, cs, err, _)) in zip(axes.flat, data.items()):
        mappable = draw_signed(ax, ls, cs, np.clip(err, -vmax, vmax), vmax,
                               f"{method} (max |e| {np.nanmax(np.abs(err)):.2g})")
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle("Diffuse SG lighting: signed error (method − reference)/D(λ, 1), common scale; black: 1 %")
    fig.subplots_adjust(left=0.05, right=0.9, bottom=0.08, top=0.9, wspace=0.3, hspace=0.45)
    signed_colorbar(fig, mappable, vmax, ax=axes.ravel().tolist(), fraction=0.02, pad=0.01)
    save(fig, out_dir, "error_maps")
    plt.close(fig)


def draw_smape(data, out_dir):
    """The poster's SMAPE of every method."""
    n = len(data)
    cols, rows = grid_shape(data)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    norm = LogNorm(vmin=1e-5, vmax=2)
    mappable = None
    for ax, (method, (ls, cs, _, sm)) in zip(axes.flat, data.items()):
        mappable = ax.pcolormesh(edges(ls, True), edges(cs, False), np.ma.masked_invalid(np.clip(sm, 1e-5, 2)),
                                 cmap="magma", norm=norm, shading="flat", rasterized=True)
        plain_log_x(ax)
        ax.set_xlabel("sharpness λ")
        ax.set_ylabel("cosine c")
        ax.set_title(f"{method} (median {np.nanmedian(sm):.2g})", fontsize=9)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle("Diffuse SG lighting: SMAPE 2|m − r|/(|m| + |r|) (the poster's measure; 2 where one side is 0)")
    fig.subplots_adjust(left=0.05, right=0.9, bottom=0.08, top=0.9, wspace=0.3, hspace=0.45)
    cb = fig.colorbar(mappable, ax=axes.ravel().tolist(), fraction=0.02, pad=0.01, label="SMAPE",
                      ticks=[1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1, 2])
    cb.ax.set_yticklabels(["1e-5", "1e-4", "1e-3", "0.01", "0.1", "1", "2"])
    cb.ax.yaxis.set_minor_formatter(NullFormatter())
    save(fig, out_dir, "error_maps_smape")
    plt.close(fig)


def main() -> int:
    args = [a for a in sys.argv[1:] if a != "--quick"]
    if len(args) != len(sys.argv) - 1:
        FORMATS[:] = ["png"]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    src, out_dir = args
    data = load(src)
    if not data:
        print(f"error_maps: no rows in {src}", file=sys.stderr)
        return 1
    os.makedirs(out_dir, exist_ok=True)
    # One process: `sglab reproduce` runs the plots beside its untimed steps, whose cores a pool
    # would take (a pool of two measured no faster on a busy machine, and took 0.3 s more CPU).
    for method in data:
        draw_method(data, out_dir, method)
    draw_combined(data, out_dir)
    draw_smape(data, out_dir)
    print(f"error_maps: wrote {len(data)} per-method maps, error_maps and error_maps_smape "
          f"({' and '.join(f.upper() for f in FORMATS)}) into {out_dir}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
