#!/usr/bin/env python3
"""The figure of Tokuyoshi 2022's poster (Fig. a-d): a sharp SG light close to a wall; panel (a) the
exact diffuse radiance, then one SMAPE map per clamped-cosine method against the exact integral, on
the poster's 0-2 scale. Reads the per-pixel dump of
`sglab near-wall --scene scenes/sg-light-near-wall-poster.json --dump FILE` (columns i, j, object,
sharpness, cosine, log_radiance_scale, then D of `reference` and of every method); computes only
the per-pixel SMAPE 2|v - r|/(|v| + |r|) and the panels' means. Panels in the order of the table
TABLE.csv (ranked by mean SMAPE) when given. --quick: PNG only.
usage: near_wall_smape.py DUMP.csv OUT_DIR [TABLE.csv] [--quick]
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from _common import argv, save_figures  # noqa: E402


def main() -> int:
    args = argv()
    if len(args) not in (2, 3):
        print(__doc__, file=sys.stderr)
        return 2
    dump, out_dir = args[0], args[1]
    with open(dump, newline="") as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0].keys())
    reference = header[6]
    methods = header[7:]
    if len(args) == 3:
        with open(args[2], newline="") as f:
            ranked = [r["method"] for r in csv.DictReader(line for line in f if not line.startswith("#"))]
        methods = [m for m in ranked if m in methods] + [m for m in methods if m not in ranked]
    w = max(int(r["i"]) for r in rows) + 1
    h = max(int(r["j"]) for r in rows) + 1
    radiance = np.full((h, w), np.nan)
    maps = {m: np.full((h, w), np.nan) for m in methods}
    for r in rows:
        i, j = int(r["i"]), int(r["j"])
        ref = float(r[reference])
        radiance[j, i] = math.exp(float(r["log_radiance_scale"])) * ref
        for m in methods:
            if r[m] == "":
                continue
            v = float(r[m])
            den = abs(v) + abs(ref)
            maps[m][j, i] = 2 * abs(v - ref) / den if den > 0 else 0.0
    n = len(methods) + 1
    cols = min(n, 4)
    rows_ = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows_, cols, figsize=(3.6 * cols, 3.0 * rows_), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    ax = axes.flat[0]
    shown = radiance / np.nanmax(radiance)
    ax.imshow(np.power(np.clip(shown, 0, 1), 1 / 2.2), cmap="gray", vmin=0, vmax=1)
    ax.set_title("exact diffuse radiance (normalized, γ 2.2)", fontsize=8)
    im = None
    for ax, m in zip(list(axes.flat)[1:], methods):
        im = ax.imshow(maps[m], cmap="jet", vmin=0, vmax=2)
        ax.set_title(f"{m}: mean SMAPE {np.nanmean(maps[m]):.3g}", fontsize=8)
    fig.colorbar(im, ax=axes.ravel().tolist(), shrink=0.8, label="SMAPE against the exact integral (0–2)")
    fig.suptitle("Sharp SG light near a wall: each clamped-cosine method against the exact SG × cosine integral", fontsize=10)
    save_figures(fig, out_dir, "near_wall_smape", dpi=130, report=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
