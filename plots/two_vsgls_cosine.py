#!/usr/bin/env python3
"""In the spirit of Fig. 1 of Tokuyoshi 2015's two-VSGL poster supplement: the same two VSGLs
shaded with the receiver's cosine pulled out of the integral (left of the paper's figure) and with
the cosine approximated by an SG (right), beside the exact VPL sum. Inputs: pixel dumps of
`sglab render … --vsgl two --diffuse punctual --dump-csv A` and `… --diffuse sg-cosine
--sg-cosine-a-pi --dump-csv B`. Panels: indirect light only, one tone scale (the 99th percentile of
the reference), gamma 1/2.2. Computes nothing else.
usage: two_vsgls_cosine.py OUT_DIR PULLED_OUT.csv SG_COSINE.csv
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import save_figure, tight_layout  # noqa: E402
from render_images import read_dump  # noqa: E402


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    out_dir, pulled, sg = sys.argv[1:]
    a, _ = read_dump(pulled)
    b, _ = read_dump(sg)
    ref = a["indirect_reference"]
    scale = np.percentile(ref, 99) or 1.0
    show = lambda im: np.power(np.clip(im / scale, 0, 1), 1 / 2.2)  # noqa: E731
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.3))
    for ax, im, title in zip(axes, (a["indirect"], b["indirect"], ref),
                             ("two VSGLs, cosine pulled out (punctual)", "two VSGLs, cosine as an SG (sg-cosine, A(λ_d) ≈ π)",
                              "exact VPL sum")):
        ax.imshow(show(im))
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.suptitle("Shading two VSGLs: the receiver's cosine pulled out vs approximated by an SG (after Tokuyoshi 2015, Fig. 1)",
                 fontsize=10)
    tight_layout(fig)
    path = save_figure(fig, os.path.join(out_dir, "two_vsgls_cosine.png"), dpi=130)
    print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
