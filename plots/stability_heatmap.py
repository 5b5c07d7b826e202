#!/usr/bin/env python3
"""Stability atlas heat maps: one figure per method, float and double side by side.

Reads the cells CSV written by `sglab stability` (stability_cells.csv) and draws, for every
(quantity, method), the most severe verdict in each (x, y) cell of its grid: x is the quantity's
sharpness column (else its first column), y its cosine column (else its next column); other
columns are aggregated into the cell. Cells never evaluated (the reference where it is computed
on a subset only) stay blank. Writes stability_<quantity>__<method>.png and .pdf into the output
directory (--quick: PNG only, lower resolution), each written to a temporary file and renamed
(never a half-written figure). Computes nothing the CSV does not already hold.
usage: stability_heatmap.py STABILITY_CELLS.csv OUT_DIR [--quick]
"""
import csv
import multiprocessing
import os
import re
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import numpy as np  # noqa: E402
from _common import QUICK_PNG, save_canvas, save_figures  # noqa: E402

# The verdicts of experiments/stability_atlas.hpp (Flag), in increasing severity, then one more
# shade for "ok" cells that had no reference to compare against (finite and ≥ 0 only).
FLAGS = ["ok", "out-of-domain", "wrong-relative", "wrong", "throws", "negative", "inf", "nan", "ok-uncompared"]
LABELS = ["ok (within 1 %)", "outside domain (clear error)", "> 1 % of |ref| only", "> 1 % of peak", "threw",
          "negative", "Inf", "NaN", "finite, ≥ 0 (no reference here)"]
COLORS = ["#a1d99b", "#bdbdbd", "#fee391", "#fe9929", "#807dba", "#2171b5", "#cb181d", "#000000", "#f0f7ee"]
UNCOMPARED = FLAGS.index("ok-uncompared")


def tick_labels(values):
    out = []
    for v in values:
        if v == 0:
            out.append("0")
        elif abs(abs(v) - 1) < 1e-6 and v != round(v):
            # the rounding steps around ±1: show the offset from ±1 (1+1.2e-07, -1-1.2e-07)
            out.append(f"1{v - 1:+.1e}" if v > 0 else f"-1{v + 1:+.1e}")
        else:
            out.append(f"{v:.3g}")
    return out


def draw(task):
    """The figures of one (quantity, grid): (quantity, x column, y column, {x index: value}, {y index:
    value}, [(method, {precision: [(x index, y index, flag code)]})], out_dir, formats, dpi, blit). The
    methods share the grid, so the figure, its axes and ticks are built once (most of the cost of a
    figure) and only the cells, legend and title change from one method to the next. With ``blit``
    (--quick, PNG only) the shared parts are even drawn once: each method's PNG is that picture
    with its cells, the spines over them, its legend and title drawn on top (the tick marks at the
    edges stay under the cells, which a full draw puts over them)."""
    quantity, xcol, ycol, xs, ys, methods, out_dir, formats, dpi, blit = task
    cmap = ListedColormap(COLORS)
    norm = BoundaryNorm(np.arange(-0.5, len(FLAGS) + 0.5), cmap.N)
    nx, ny = max(xs) + 1, max(ys) + 1
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), sharey=True)
    # Fixed margins: tight_layout would cost a third of the run time over ~50 figures.
    fig.subplots_adjust(left=0.1, right=0.99, bottom=0.24, top=0.9, wspace=0.04)
    meshes = []
    for ax, precision in zip(axes, ("float", "double")):
        meshes.append(ax.pcolormesh(np.arange(nx + 1) - 0.5, np.arange(ny + 1) - 0.5,
                                    np.ma.masked_invalid(np.full((ny, nx), np.nan)), cmap=cmap, norm=norm,
                                    edgecolors="face", linewidth=0, rasterized=True))
        ax.set_title(f"{precision}")
        step_x = max(1, nx // 12)
        ax.set_xticks(range(0, nx, step_x))
        ax.set_xticklabels(tick_labels([xs.get(i, np.nan) for i in range(0, nx, step_x)]), rotation=60, fontsize=7)
        ax.set_xlabel(f"{xcol} (index; value shown)")
    if ycol:  # once: the two axes share y
        step_y = max(1, ny // 24)
        axes[0].set_yticks(range(0, ny, step_y))
        axes[0].set_yticklabels(tick_labels([ys.get(j, np.nan) for j in range(0, ny, step_y)]), fontsize=7)
        axes[0].set_ylabel(f"{ycol} (index; value shown)")
    background = None
    if blit:
        fig.set_dpi(dpi)
        fig.canvas.draw()  # no cells, legend or title yet
        background = fig.canvas.copy_from_bbox(fig.bbox)
    stems = []
    legend = None
    for method, cells in methods:
        present = set()
        for mesh, precision in zip(meshes, ("float", "double")):
            grid = np.full((ny, nx), np.nan)
            for i, j, code in cells.get(precision, []):
                grid[j, i] = code
                present.add(code)
            mesh.set_array(np.ma.masked_invalid(grid))
        if legend is not None:
            legend.remove()
        handles = [Patch(color=COLORS[k], label=LABELS[k]) for k in range(len(FLAGS)) if k in present]
        legend = fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 8), fontsize=8, frameon=False,
                            bbox_to_anchor=(0.5, 0.0))
        title = fig.suptitle(f"Stability atlas: {quantity} / {method} (most severe verdict per cell)")
        stem = "stability_" + re.sub(r"[^A-Za-z0-9_.-]", "_", f"{quantity}__{method}")
        if blit:
            fig.canvas.restore_region(background)
            for ax, mesh in zip(axes, meshes):
                ax.draw_artist(mesh)
                for spine in ax.spines.values():
                    ax.draw_artist(spine)
            fig.draw_artist(legend)
            fig.draw_artist(title)
            save_canvas(fig, os.path.join(out_dir, stem + ".png"), **QUICK_PNG)
        else:
            save_figures(fig, out_dir, stem, formats, dpi)
        stems.append(stem)
    plt.close(fig)
    return stems


def main() -> int:
    args = [a for a in sys.argv[1:] if a != "--quick"]
    quick = len(args) != len(sys.argv) - 1
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    src, out_dir = args
    xs = defaultdict(dict)
    ys = defaultdict(dict)
    cells = defaultdict(lambda: defaultdict(list))
    axes_of = {}
    with open(src, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        col = {name: k for k, name in enumerate(header)}
        q, m, p = col["quantity"], col["method"], col["precision"]
        xi, xv, yi, yv, fc = col["x_index"], col["x_value"], col["y_index"], col["y_value"], col["flag_code"]
        xc, yc, cmp = col["x_column"], col["y_column"], col["compared"]
        for r in reader:
            key = (r[q], r[m])
            i, j = int(r[xi]), int(r[yi])
            xs[key][i] = float(r[xv])
            ys[key][j] = float(r[yv])
            code = int(r[fc])
            if code == 0 and int(r[cmp]) == 0:
                code = UNCOMPARED
            cells[key][r[p]].append((i, j, code))
            axes_of[r[q]] = (r[xc], r[yc])
    if not cells:
        print(f"stability_heatmap: no cells in {src}", file=sys.stderr)
        return 1
    os.makedirs(out_dir, exist_ok=True)
    formats, dpi = (("png",), 80) if quick else (("png", "pdf"), 110)
    # One task per quantity and grid (methods evaluated on a subset have fewer cells: a grid of
    # their own), drawn on every core.
    groups = {}
    for k in cells:
        grid_key = (k[0], tuple(sorted(xs[k].items())), tuple(sorted(ys[k].items())))
        groups.setdefault(grid_key, []).append((k[1], dict(cells[k])))
    tasks = [(key[0], axes_of[key[0]][0], axes_of[key[0]][1], dict(key[1]), dict(key[2]), methods, out_dir, formats, dpi,
              quick)
             for key, methods in groups.items()]
    tasks.sort(key=lambda t: -len(t[5]))  # the longest first, for the balance between the workers
    # Forked workers (not spawned): they inherit _serve.py's record of the files written.
    with multiprocessing.get_context("fork").Pool(os.cpu_count() or 1) as pool:
        stems = [stem for done in pool.map(draw, tasks, chunksize=1) for stem in done]
    print(f"stability_heatmap: wrote {len(stems)} figures ({' and '.join(f.upper() for f in formats)}) into {out_dir}",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
