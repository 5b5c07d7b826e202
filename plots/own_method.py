#!/usr/bin/env python3
"""sglab's own diffuse approximation against tokuyoshi2024 (paper_tables/own_method.md).

Reads the long-format CSV of `sglab error-map` (error_map.csv: method, sharpness, cosine,
reference, value, error, smape), plots/own_method_forms.csv (the forms tried: name, max error,
the measured method whose cost each has) and error_vs_time.csv (`sglab error-vs-time`: each
method's ns/eval, the one place costs are measured) and draws
  own_method_error_maps.{png,pdf}: the signed error (method − reference)/D(λ, 1) of tokuyoshi2024
      and of sglab over (λ, c) on one linear colour scale (so sglab's map shows how much smaller
      its error is), then sglab again on its own scale, λ on a log axis;
  own_method_frontier.{png,pdf}: max error against ns/eval of the forms tried, the 0.05 % target
      as a line.
Each file is written to a temporary name and renamed (--quick: PNG only). Computes nothing the CSVs
do not hold.
usage: own_method.py ERROR_MAP.csv FORMS.csv ERROR_VS_TIME.csv OUT_DIR [--quick]
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from _common import argv, save_figures  # noqa: E402

METHODS = ["tokuyoshi2024", "sglab"]


def save(fig, out_dir, stem):
    save_figures(fig, out_dir, stem, dpi=120)


def read_maps(path):
    rows = {m: [] for m in METHODS}
    with open(path, newline="") as f:
        for r in csv.DictReader(line for line in f if not line.startswith("#")):
            if r["method"] in rows:
                rows[r["method"]].append((float(r["sharpness"]), float(r["cosine"]), float(r["error"])))
    maps = {}
    for m, v in rows.items():
        if not v:
            sys.exit(f"own_method.py: no rows for method {m} in {path}")
        a = np.array(v)
        ls, cs = np.unique(a[:, 0]), np.unique(a[:, 1])
        grid = np.full((len(cs), len(ls)), np.nan)
        li = {x: i for i, x in enumerate(ls)}
        ci = {x: i for i, x in enumerate(cs)}
        for l, c, e in v:
            grid[ci[c], li[l]] = e
        maps[m] = (ls, cs, grid)
    return maps


def main():
    args = argv()
    if len(args) != 4:
        sys.exit(__doc__)
    csv_path, forms_path, costs_path, out_dir = args
    os.makedirs(out_dir, exist_ok=True)
    maps = read_maps(csv_path)
    vmax = max(np.nanmax(np.abs(g)) for _, _, g in maps.values())
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.2), sharey=True, constrained_layout=True)
    panels = [(m, vmax) for m in METHODS] + [("sglab", np.nanmax(np.abs(maps["sglab"][2])))]
    for k, (ax, (m, v)) in enumerate(zip(axes, panels)):
        ls, cs, g = maps[m]
        pc = ax.pcolormesh(ls, cs, g, cmap="RdBu_r", vmin=-v, vmax=v, shading="nearest", rasterized=True)
        ax.set_xscale("log")
        ax.set_xlabel("sharpness λ")
        scale = "common scale" if k < 2 else "own scale"
        ax.set_title(f"{m} ({scale}): max |error| {np.nanmax(np.abs(g)) * 100:.4f} %", fontsize=10)
        if k >= 1:
            fig.colorbar(pc, ax=axes[:2].tolist() if k == 1 else ax,
                         label="(method − reference) / D(λ, 1)" if k == 1 else None)
    axes[0].set_ylabel("c = ξ·n")
    save(fig, out_dir, "own_method_error_maps")
    plt.close(fig)

    if not os.path.exists(costs_path):  # `sglab reproduce --only` without the error-vs-time step
        print(f"own_method.py: no {costs_path}; the frontier figure needs its costs and is left out", file=sys.stderr)
        return
    ns = {}
    with open(costs_path, newline="") as f:
        for r in csv.DictReader(line for line in f if not line.startswith("#")):
            if r["quantity"] == "clamped-cosine" and r["precision"] == "double":
                ns[r["method"]] = float(r["ns_per_eval"])
    forms = []
    with open(forms_path, newline="") as f:
        for r in csv.DictReader(line for line in f if not line.startswith("#")):
            if r["costs_as"] not in ns:
                sys.exit(f"own_method.py: no double clamped-cosine row for {r['costs_as']} in {costs_path}")
            forms.append((r["form"], float(r["max_error"]), ns[r["costs_as"]], r["shipped"] == "yes"))
    fig, ax = plt.subplots(figsize=(6.4, 4.2), constrained_layout=True)
    for i, (name, e, ns, shipped) in enumerate(forms):
        ax.scatter(ns, e, s=60 if shipped else 30, marker="*" if shipped else "o")
        ax.annotate(name, (ns, e), textcoords="offset points", xytext=(6, 3 if i % 2 else -9), fontsize=8)
    ax.margins(x=0.4)
    ax.axhline(5e-4, color="k", lw=0.8, ls="--")
    ax.text(ax.get_xlim()[0], 5e-4, " target 0.05 %", va="bottom", fontsize=8)
    ax.set_yscale("log")
    ax.set_xlabel("ns per evaluation (double, batch)")
    ax.set_ylabel("max |error| / D(λ, 1)")
    ax.set_title("Forms tried: error against cost")
    save(fig, out_dir, "own_method_frontier")
    plt.close(fig)


if __name__ == "__main__":
    main()
