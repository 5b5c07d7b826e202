#!/usr/bin/env python3
"""Specular error against roughness: one line per method, log axes.

Reads the summary CSV written by `sglab sweep specular` (DIR/specular_summary.csv, or
paper_tables/specular_vs_roughness.csv: lines starting with '#' are skipped) and writes
specular_vs_roughness.png and .pdf into the output directory. Columns: SMAPE, the maximum relative
error, and the RMSE of the error scaled by each point's largest reference; top row over every
light position (rows with by = roughness), bottom row only the positions near the highlight
(by = roughness_near_lobe). --quick: PNG only. Computes nothing the CSV does not already hold.
usage: specular_vs_roughness.py SUMMARY.csv OUT_DIR [--quick]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402
from _common import arguments, read_table, save_figures, tight_layout  # noqa: E402

PANELS = (
    ("smape", "SMAPE (%)", "mean 2|v − r|/(|v| + |r|)"),
    ("max_relative", "max relative error (%)", "max |v − r|/r"),
    ("rmse_scaled", "RMSE of the scaled error (%)", "|v − r| / the point's largest reference"),
)


def main() -> int:
    src, out_dir = arguments(__doc__, 2)
    rows = read_table(src)
    groups = (("roughness", "all light positions"), ("roughness_near_lobe", "light within one width of the mirror direction"))
    if not any(r["by"] == "roughness" for r in rows):
        print(f"{src}: no rows with by = roughness (not a specular sweep summary?)", file=sys.stderr)
        return 2
    methods = list(dict.fromkeys(r["method"] for r in rows))
    os.makedirs(out_dir, exist_ok=True)
    fig, axes = plt.subplots(len(groups), len(PANELS), figsize=(16, 9), squeeze=False)
    markers = "osD^vP*X"
    for row_axes, (by, where) in zip(axes, groups):
        for ax, (column, label, definition) in zip(row_axes, PANELS):
            for i, m in enumerate(methods):
                pts = [(float(r["group"]), 100 * float(r[column])) for r in rows
                       if r["by"] == by and r["method"] == m and r[column] != ""]
                pts = [(a, e) for a, e in pts if e > 0]  # log axis: an exact 0 cannot be drawn
                if not pts:
                    continue
                ax.plot([a for a, _ in pts], [e for _, e in pts], marker=markers[i % len(markers)], label=m,
                        color=plt.cm.tab10(i % 10))
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("GGX roughness α")
            ax.set_ylabel(label)
            ax.set_title(f"{label}, {where}\n{definition}", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
            plain = FuncFormatter(lambda y, _: f"{y:g}")  # 20 rather than 2×10^1
            ax.yaxis.set_major_formatter(plain)
            ax.yaxis.set_minor_formatter(plain)
            ax.tick_params(axis="y", which="minor", labelsize=7)
    axes[0][-1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Specular reflection of an SG light off GGX: each method against the reference "
                 "(all light sharpnesses and views of the sweep)", fontsize=10)
    tight_layout(fig)
    save_figures(fig, out_dir, "specular_vs_roughness", dpi=150, report=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
