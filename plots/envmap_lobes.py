#!/usr/bin/env python3
"""SG environment maps: error against the lobe count N, and each map beside its reconstructions.

Reads paper_tables/envmap_lobes.csv and DIR/envmap_images.csv (both written by
`sglab envmap lobes`; lines starting with '#' are skipped) and writes into OUT_DIR:
  envmap_error_vs_lobes.png/.pdf  one column per environment: the fit error (Ceres and vMF EM)
      and, for the sphere, the diffuse and specular (roughness 0.3, or the middle roughness)
      fit part and approximation part (relative L2) of each method, all against N (log-log);
  envmap_reconstructions.png      per environment, the map and the reconstructions by N lobes
      (tone-mapped x/(1 + x) per channel, the same exposure within a row).
--quick: PNG only. Computes nothing the CSVs do not already hold.
usage: envmap_lobes.py ENVMAP_LOBES.csv ENVMAP_IMAGES.csv OUT_DIR [--quick]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from _common import arguments, read_table, save_figure, save_figures, tight_layout  # noqa: E402


def main() -> int:
    table, images, out_dir = arguments(__doc__, 3)
    rows = read_table(table)
    if not rows or "ceres_relative_error" not in rows[0]:
        print(f"{table}: not an envmap_lobes CSV", file=sys.stderr)
        return 2
    os.makedirs(out_dir, exist_ok=True)
    envs = list(dict.fromkeys(r["environment"] for r in rows))
    roughs = sorted({float(r["roughness"]) for r in rows if r["roughness"]})
    rough = roughs[len(roughs) // 2] if roughs else None

    fig, axes = plt.subplots(3, len(envs), figsize=(4.2 * len(envs), 10), squeeze=False)
    for col, env in enumerate(envs):
        er = [r for r in rows if r["environment"] == env]
        ns = sorted({int(r["lobes"]) for r in er})
        first = {int(r["lobes"]): r for r in er}
        ax = axes[0][col]
        ax.plot(ns, [float(first[n]["ceres_relative_error"]) for n in ns], "o-", label="Ceres LM")
        ax.plot(ns, [float(first[n]["vmf_em_relative_error"]) for n in ns], "s--", label="vMF EM")
        ax.set_title(f"{env}: environment fit")
        ax.set_ylabel("relative L2 of the map")
        for row, (component, title) in enumerate((("diffuse", "diffuse, sphere"), ("specular", f"specular α={rough}, sphere")), start=1):
            ax = axes[row][col]
            sel = [r for r in er if r["geometry"] == "sphere" and r["component"] == component and
                   (component == "diffuse" or float(r["roughness"]) == rough)]
            fit = {int(r["lobes"]): float(r["relative_l2"]) for r in sel if r["part"] == "fit"}
            ax.plot(ns, [fit[n] for n in ns], "k-", lw=2.5, label="fit part")
            methods = list(dict.fromkeys(r["method"] for r in sel if r["part"] == "approximation"))
            for m in methods:
                v = {int(r["lobes"]): float(r["relative_l2"]) for r in sel if r["part"] == "approximation" and r["method"] == m}
                ax.plot(ns, [v[n] for n in ns], ".--", lw=1, label=m)
            ax.set_title(f"{env}: {title}")
            ax.set_ylabel("relative L2 of the shading")
        for ax in (axes[0][col], axes[1][col], axes[2][col]):
            ax.set_xscale("log", base=2)
            ax.set_yscale("log")
            ax.set_xlabel("lobes N")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=6)
    tight_layout(fig)
    lobes_paths = save_figures(fig, out_dir, "envmap_error_vs_lobes", dpi=110)
    plt.close(fig)

    pix = read_table(images)
    envs_i = list(dict.fromkeys(r["environment"] for r in pix))
    panels = {e: sorted({int(r["lobes"]) for r in pix if r["environment"] == e}) for e in envs_i}
    ncol = max(len(v) for v in panels.values())
    fig, axes = plt.subplots(len(envs_i), ncol, figsize=(3.2 * ncol, 1.9 * len(envs_i)), squeeze=False)
    for i, env in enumerate(envs_i):
        er = [r for r in pix if r["environment"] == env]
        w = max(int(r["x"]) for r in er) + 1
        h = max(int(r["y"]) for r in er) + 1
        # One exposure per row: the map's mean radiance maps to 0.5.
        base = [r for r in er if int(r["lobes"]) == 0]
        mean = sum(float(r["r"]) + float(r["g"]) + float(r["b"]) for r in base) / (3 * len(base)) or 1.0
        for j in range(ncol):
            ax = axes[i][j]
            ax.axis("off")
            if j >= len(panels[env]):
                continue
            n = panels[env][j]
            img = [[[0.0] * 3 for _ in range(w)] for _ in range(h)]
            for r in er:
                if int(r["lobes"]) == n:
                    px = [float(r[c]) / mean for c in "rgb"]
                    img[int(r["y"])][int(r["x"])] = [x / (1 + x) for x in px]
            ax.imshow(img, interpolation="nearest")
            ax.set_title(f"{env}: " + ("map" if n == 0 else f"{n} lobes"), fontsize=8)
    tight_layout(fig)
    save_figure(fig, os.path.join(out_dir, "envmap_reconstructions.png"), dpi=110)
    plt.close(fig)
    print(f"wrote {' and '.join(lobes_paths)} and {out_dir}/envmap_reconstructions.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
