#!/usr/bin/env python3
"""Pareto figure: each method's max error against its cost, one point per method and precision.

Reads the CSV written by `sglab error-vs-time` and writes error_vs_time.png and .pdf into the
output directory (--quick: PNG only). Computes nothing the CSV does not already hold.
usage: error_vs_time.py RESULTS.csv OUT_DIR [--quick]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from _common import arguments, read_table, save_figures, tight_layout  # noqa: E402


def main() -> int:
    src, out_dir = arguments(__doc__, 2)
    rows = [r for r in read_table(src) if r["max_error"] not in ("", "nan", "0.000000e+00")]
    os.makedirs(out_dir, exist_ok=True)
    quantities = list(dict.fromkeys(r["quantity"] for r in rows))
    titles = {"clamped-cosine": ("Diffuse SG lighting", "all λ ∈ [1e-3, 1e4]", "λ ≥ 1", "max |error| / D(λ, 1)"),
              "specular": ("Glossy SG lighting", "all α ∈ [0.02, 1]", "α ≥ 0.1", "max |error| / L at the mirror direction")}
    fig, axes = plt.subplots(len(quantities), 2, figsize=(12, 5 * len(quantities)), squeeze=False)
    markers = {"float": "o", "double": "s"}
    for row, q in zip(axes, quantities):
        qrows = [r for r in rows if r["quantity"] == q]
        methods = sorted({r["method"] for r in qrows})
        colors = {m: plt.cm.tab10(i % 10) for i, m in enumerate(methods)}
        name, all_label, subset_label, ylabel = titles.get(q, (q, "all", "subset", "max error"))
        for ax, column, title in ((row[0], "max_error", all_label), (row[1], "max_error_subset", subset_label)):
            for r in qrows:
                ax.scatter(float(r["ns_per_eval"]), float(r[column]), marker=markers.get(r["precision"], "x"),
                           color=colors[r["method"]], s=40, label=f'{r["method"]} ({r["precision"]})')
            ax.set_title(f"{name}: error against run time, {title}")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("ns per evaluation (median)")
            ax.set_ylabel(ylabel)
            ax.grid(True, which="both", alpha=0.3)
        row[1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    tight_layout(fig)
    save_figures(fig, out_dir, "error_vs_time", dpi=150, report=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
