#!/usr/bin/env python3
"""Filtering noisy indirect light: crops of the glossy floor and of a diffuse wall, for each
roughness in the images CSV written by `sglab filter-sweep --noisy …` (OUT/filtering_denoise_images.csv):
the noisy interleaved image, the image filtered with normal/depth-aware weights, the image filtered
with lobe-aware weights, and the exact VPL sum. Each panel's title gives the crop's relative L2
against the exact sum.

Crops (fractions of the image, for scenes/cornell-glossy.json's camera): the floor's front band (with
the box's and the sphere's reflections in it), and the left (red) wall. Tone mapping (display only): the four panels of a crop
share one scale, the 99th percentile of the exact crop; clipped to [0, 1], gamma 1/2.2. Computes
nothing else. Writes filtering_denoise.png and .pdf (--quick: PNG only).
usage: filtering_denoise.py IMAGES.csv OUT_DIR [--quick]
"""
import os
import sys

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import arguments, read_table, save_figures, tight_layout  # noqa: E402

# (name, x0, x1, y0, y1) as fractions of the width and height (y down).
CROPS = (("glossy floor", 0.1, 0.9, 0.83, 1.0), ("diffuse wall (left)", 0.02, 0.19, 0.15, 0.75))
LAYERS = (("noisy", "noisy"), ("normal", "normal-filtered"), ("lobe", "lobe-filtered"), ("exact", "exact VPL sum"))


def images(rows):
    """{(roughness, noisy): {layer: (h, w, 3) array}} from the CSV rows."""
    out = {}
    for key in sorted({(float(r["floor_roughness"]), r["noisy"]) for r in rows}):
        sel = [r for r in rows if float(r["floor_roughness"]) == key[0] and r["noisy"] == key[1]]
        w = max(int(r["x"]) for r in sel) + 1
        h = max(int(r["y"]) for r in sel) + 1
        layers = {name: np.zeros((h, w, 3)) for name, _ in LAYERS}
        for r in sel:
            x, y = int(r["x"]), int(r["y"])
            for name, _ in LAYERS:
                layers[name][y, x] = [float(r[f"{name}_{c}"]) for c in "rgb"]
        out[key] = layers
    return out


def crop(a, box):
    _, x0, x1, y0, y1 = box
    h, w = a.shape[:2]
    return a[int(y0 * h):int(np.ceil(y1 * h)), int(x0 * w):int(np.ceil(x1 * w))]


def relative_l2(v, r):
    d = np.sqrt(np.sum(r * r))
    return np.sqrt(np.sum((v - r) ** 2)) / d if d > 0 else float("nan")


def main() -> int:
    path, out_dir = arguments(__doc__, 2)
    data = images(read_table(path))
    if not data:
        print(f"{path}: no images", file=sys.stderr)
        return 1
    rows = [(key, box) for key in data for box in CROPS]
    fig, axes = plt.subplots(len(rows), len(LAYERS), figsize=(3.2 * len(LAYERS), 2.6 * len(rows)), squeeze=False)
    for i, ((roughness, noisy), box) in enumerate(rows):
        layers = data[(roughness, noisy)]
        exact = crop(layers["exact"], box)
        s = np.percentile(exact, 99)
        s = s if s > 0 else 1.0
        for j, (name, title) in enumerate(LAYERS):
            c = crop(layers[name], box)
            ax = axes[i][j]
            ax.imshow(np.clip(c / s, 0, 1) ** (1 / 2.2), interpolation="nearest")
            label = title if name == "exact" else f"{title}: rel. L2 {relative_l2(c, exact):.3f}"
            ax.set_title(label, fontsize=8)
            ax.set_xticks([])
            ax.set_yticks([])
            if j == 0:
                ax.set_ylabel(f"{box[0]}\nfloor α = {roughness:g}, {noisy}", fontsize=8)
    fig.suptitle("Filtering noisy interleaved VPL images (cornell-glossy): normal/depth- vs lobe-aware weights", fontsize=10)
    tight_layout(fig)
    save_figures(fig, out_dir, "filtering_denoise", report=True)
    return 0


if __name__ == "__main__":
    matplotlib.use("Agg")
    sys.exit(main())
