#!/usr/bin/env python3
"""Pareto figure: each method's max error against its cost, one point per method and precision.

Reads the CSV written by `sglab error-vs-time` and writes error_vs_time.png and .pdf into the
output directory. Computes nothing the CSV does not already hold.
usage: error_vs_time.py RESULTS.csv OUT_DIR
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    src, out_dir = sys.argv[1], sys.argv[2]
    with open(src, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["max_error"] not in ("", "nan", "0.000000e+00")]
    os.makedirs(out_dir, exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    methods = sorted({r["method"] for r in rows})
    colors = {m: plt.cm.tab10(i % 10) for i, m in enumerate(methods)}
    markers = {"float": "o", "double": "s"}
    for ax, column, title in ((axes[0], "max_error", "all λ ∈ [1e-3, 1e4]"),
                              (axes[1], "max_error_sharpness_ge_1", "λ ≥ 1")):
        for r in rows:
            ax.scatter(float(r["ns_per_eval"]), float(r[column]), marker=markers.get(r["precision"], "x"),
                       color=colors[r["method"]], s=40,
                       label=f'{r["method"]} ({r["precision"]})')
        ax.set_title(f"Diffuse SG lighting: error against run time, {title}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("ns per evaluation (median)")
        ax.set_ylabel("max |error| / D(λ, 1)")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    for ext in ("png", "pdf"):
        path = os.path.join(out_dir, f"error_vs_time.{ext}")
        tmp = path + ".tmp"
        fig.savefig(tmp, format=ext, dpi=150)
        os.replace(tmp, path)  # never a half-written figure
    print(f"wrote {out_dir}/error_vs_time.png and .pdf", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
