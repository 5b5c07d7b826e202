#!/usr/bin/env python3
"""The VSGL renderer on the spotlight-near-a-wall scene: one SMAPE map of the one-VSGL pipeline
against the exact VPL sum per diffuse shading method. NOT the 2022 poster's figure (that one
compares each method with the exact SG integral: plots/near_wall_smape.py): here the VSGL's own
approximation (wall pixels, where the VPL sum is 0 but the VSGL is not, score 2) dominates. Each input is a pixel dump written by
`sglab render scenes/sg-light-near-wall.json --diffuse METHOD … --dump-csv FILE`; the panel shows
the per-pixel SMAPE of the VSGL indirect light against the exact VPL sum,
2|v − r| / (|v| + |r|) on the channel mean (0 where both are 0), on one colour scale for all
panels, with the mean over the pixels that see light in the title. Computes nothing else.
--quick: PNG only.
usage: near_wall_vsgl_vs_vpl_sum.py OUT_DIR METHOD=DUMP.csv [METHOD=DUMP.csv …] [--quick]
"""
import os
import sys

import matplotlib
import matplotlib.pyplot as plt
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import argv, save_figures  # noqa: E402
from render_images import read_dump  # noqa: E402


def smape_map(im):
    v = im["indirect"].mean(axis=2)
    r = im["indirect_reference"].mean(axis=2)
    den = np.abs(v) + np.abs(r)
    out = np.zeros_like(v)
    nz = den > 0
    out[nz] = 2 * np.abs(v[nz] - r[nz]) / den[nz]
    return out, nz


def figure(renders):
    """One SMAPE panel per (method, images) pair, on one colour scale, as a matplotlib figure."""
    n = len(renders)
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.5 * cols, 3.8 * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, (method, im) in zip(axes.flat, renders):
        s, lit = smape_map(im)
        shown = ax.imshow(s, cmap="magma", vmin=0, vmax=2)
        ax.set_title(f"{method}: mean SMAPE {s[lit].mean():.3f}", fontsize=9)
    fig.colorbar(shown, ax=axes.ravel().tolist(), shrink=0.8, label="SMAPE (0–2)")
    fig.suptitle("sg-light-near-wall: one-VSGL indirect light vs the exact VPL sum, per diffuse method")
    return fig


def main() -> int:
    args = argv()
    if len(args) < 2 or any("=" not in a for a in args[1:]):
        print(__doc__, file=sys.stderr)
        return 2
    out_dir = args[0]
    os.makedirs(out_dir, exist_ok=True)
    inputs = [a.split("=", 1) for a in args[1:]]
    fig = figure([(method, read_dump(path)[0]) for method, path in inputs])
    save_figures(fig, out_dir, "near_wall_vsgl_vs_vpl_sum", dpi=150, report=True)
    return 0


if __name__ == "__main__":
    matplotlib.use("Agg")  # files only; not on import, so that notebooks keep their backend
    sys.exit(main())
