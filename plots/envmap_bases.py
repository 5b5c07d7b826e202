#!/usr/bin/env python3
"""Environment lighting at equal storage: error against stored floats, one panel per layer.

Reads envmap_bases.csv (written by `sglab envmap bases`; lines starting with '#' are skipped)
and writes OUT_DIR/envmap_bases.png/.pdf: one row per environment, one column per layer (map,
diffuse, specular at each roughness), the relative L2 error of every basis (SH, fixed-lobe SG
per amplitude solver, vMF EM, free-lobe SG) against its stored float count (log-log), with the
5 % diffuse and 20 % specular targets drawn as dotted lines.
--quick: PNG only, minor ticks of the floats axis unlabelled. Computes nothing the CSV does not already hold.
usage: envmap_bases.py ENVMAP_BASES.csv OUT_DIR [--quick]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402
from _common import arguments, quick, read_table, save_figures, tight_layout  # noqa: E402

STYLE = {"sh": ("k", "o-"), "sg-fixed ls": ("tab:orange", "v--"), "sg-fixed nnls": ("tab:red", "^-"),
         "sg-fixed running-average": ("tab:pink", "<:"), "vmf-em": ("tab:green", "s--"), "sg-free": ("tab:blue", "D-")}


def main() -> int:
    table, out_dir = arguments(__doc__, 2)
    rows = read_table(table)
    if not rows or "floats" not in rows[0] or "layer" not in rows[0]:
        print(f"{table}: not an envmap_bases CSV", file=sys.stderr)
        return 2
    os.makedirs(out_dir, exist_ok=True)
    envs = list(dict.fromkeys(r["environment"] for r in rows))
    roughs = sorted({r["roughness"] for r in rows if r["layer"] == "specular"}, key=float)
    layers = [("map", "", "map (texel means)"), ("diffuse", "", "diffuse")] + [("specular", a, f"specular α = {a}") for a in roughs]
    fig, axes = plt.subplots(len(envs), len(layers), figsize=(3.4 * len(layers), 2.8 * len(envs)), squeeze=False)
    for i, env in enumerate(envs):
        for j, (layer, rough, title) in enumerate(layers):
            ax = axes[i][j]
            sel = [r for r in rows if r["environment"] == env and r["layer"] == layer and r["roughness"] == rough]
            labels = list(dict.fromkeys((r["basis"] + (" " + r["variant"] if r["variant"] else "")) for r in sel))
            for label in labels:
                pts = sorted((int(r["floats"]), float(r["relative_l2"])) for r in sel
                             if (r["basis"] + (" " + r["variant"] if r["variant"] else "")) == label)
                color, style = STYLE.get(label, (None, "o-"))
                ax.plot([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], style, color=color, label=label, ms=3)
            if layer == "diffuse":
                ax.axhline(0.05, color="gray", ls=":", lw=1)
            if layer == "specular" and rough == "0.3":
                ax.axhline(0.20, color="gray", ls=":", lw=1)
            ax.set_xscale("log")
            ax.set_yscale("log")
            if quick():  # the quick sizes span under a decade of floats: unlabelled minor ticks
                ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_title(f"{env}: {title}", fontsize=9)
            if i == len(envs) - 1:
                ax.set_xlabel("stored floats")
            if j == 0:
                ax.set_ylabel("relative L2")
            ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=7)
    tight_layout(fig)
    save_figures(fig, out_dir, "envmap_bases")
    return 0


if __name__ == "__main__":
    sys.exit(main())
