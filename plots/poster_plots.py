#!/usr/bin/env python3
"""The two plots of Tokuyoshi 2022's poster (§3), from the CSVs of `sglab poster-plots`:
cosine_term_error.png (left: the difference alpha(e^{lambda t} - 1) - t over t for lambda around the
optimum, exact and computed in float; right: the approximation error and the float numerical-error
bound against lambda, their sum, and the measured float error) and hemispherical_rmse.png (RMSE of
each hemispherical method against the exact integral, per lambda). Computes nothing.
usage: poster_plots.py TABLES_DIR OUT_DIR
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from _common import arguments, read_table, save_figure, tight_layout  # noqa: E402

LAMBDA_STAR = 0.0008456087  # the poster's printed optimum (for the marker only)


def save(fig, out_dir, name):
    path = save_figure(fig, os.path.join(out_dir, name), dpi=140)
    print(f"wrote {path}", file=sys.stderr)


def main() -> int:
    tables, out_dir = arguments(__doc__, 2)

    curves = read_table(os.path.join(tables, "cosine_term_error_curves.csv"))
    per_lambda = read_table(os.path.join(tables, "cosine_term_error.csv"))
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
    for lam in sorted({r["lambda"] for r in curves}, key=float):
        rows = [r for r in curves if r["lambda"] == lam]
        t = [float(r["t"]) for r in rows]
        line, = a.plot(t, [float(r["approximation_error"]) for r in rows], label=f"λ = {float(lam):.3g} (exact)")
        a.plot(t, [float(r["float_difference"]) for r in rows], lw=0.5, alpha=0.6, color=line.get_color(),
               label=f"λ = {float(lam):.3g} (float)")
    a.axhline(0, color="k", lw=0.5)
    a.set_xlabel("t = ω·n")
    a.set_ylabel("α(e^{λt} − 1) − t")
    a.set_title("error of the cosine-term approximation", fontsize=9)
    a.legend(fontsize=7)
    lam = [float(r["lambda"]) for r in per_lambda]
    for key, label in (("approximation_error", "approximation error max_t |α(e^{λt}−1) − t|"),
                       ("float_error_bound", "float numerical-error bound α·u·(e^λ + 1)"),
                       ("sum", "sum (minimized by λ*)"),
                       ("measured_float_error", "measured float error (max over t)")):
        b.loglog(lam, [float(r[key]) for r in per_lambda], label=label)
    b.axvline(LAMBDA_STAR, color="k", ls=":", lw=0.8, label="λ* = 0.0008456087 (poster)")
    b.set_xlabel("λ")
    b.set_ylabel("error")
    b.set_title("approximation error against numerical error", fontsize=9)
    b.legend(fontsize=7)
    fig.suptitle("Tokuyoshi 2022: SG approximation of the cosine term (sglab poster-plots)", fontsize=10)
    tight_layout(fig)
    save(fig, out_dir, "cosine_term_error.png")

    rmse = read_table(os.path.join(tables, "hemispherical_rmse.csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    # Normalized by A(λ), the vMF form of Tokuyoshi et al. 2024 is the 2022 form exactly: dashed, so
    # that both curves show where they coincide.
    for k, m in enumerate(dict.fromkeys(r["method"] for r in rmse)):
        rows = [r for r in rmse if r["method"] == m]
        ax.loglog([float(r["lambda"]) for r in rows], [float(r["rmse_normalized"]) for r in rows], label=m,
                  ls=("-", "--", ":", "-.")[k % 4], lw=2.5 - 0.5 * (k % 3))
    ax.set_xlabel("λ")
    ax.set_ylabel("RMSE of H/A(λ) over c ∈ [−1, 1]")
    ax.set_title("Hemispherical integral of an SG: RMSE against the exact integral", fontsize=9)
    ax.legend(fontsize=8)
    tight_layout(fig)
    save(fig, out_dir, "hemispherical_rmse.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
