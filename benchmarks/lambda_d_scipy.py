#!/usr/bin/env python3
"""lambda-d with scipy.optimize.least_squares on the same grid as fit/lambda_d.cpp (the Ceres-vs-scipy
speed comparison): Gauss-Legendre, 20 nodes per sub-panel, panels [-1, 0] and [0, 1] each split
into 4; residuals sqrt(2*pi*w_i) * (G(t_i; lambda)/A(lambda) - max(t_i, 0)/pi) with the analytic
Jacobian (a fair comparison: Ceres uses exact derivatives too), one start at 2 and tolerances 1e-15,
as sglab::fit::fit_lambda_d_like_scipy. Prints lambda_d and the wall and CPU time per fit.
Run with the system python (python3-scipy): /usr/bin/python3 benchmarks/lambda_d_scipy.py"""
import time

import numpy as np
from scipy.optimize import least_squares
from scipy.special import roots_legendre


def grid():
    x, w = roots_legendre(20)
    ts, ws = [], []
    for a0, b0 in ((-1.0, 0.0), (0.0, 1.0)):
        for s in range(4):
            a = a0 + (b0 - a0) * s / 4
            b = a0 + (b0 - a0) * (s + 1) / 4
            ts.append(0.5 * (a + b) + 0.5 * (b - a) * x)
            ws.append(0.5 * (b - a) * w)
    return np.concatenate(ts), np.concatenate(ws)


T, W = grid()
SW = np.sqrt(2 * np.pi * W)
TARGET = np.maximum(T, 0) / np.pi


def model(lam):
    a = 2 * np.pi * (-np.expm1(-2 * lam)) / lam
    g = np.exp(lam * (T - 1))
    return g, a


def residuals(p):
    g, a = model(p[0])
    return SW * (g / a - TARGET)


def jacobian(p):
    lam = p[0]
    g, a = model(lam)
    # dA/dλ = 2π(2λe^{−2λ} − (1 − e^{−2λ}))/λ²
    da = 2 * np.pi * (2 * lam * np.exp(-2 * lam) + np.expm1(-2 * lam)) / lam**2
    dg = (T - 1) * g
    return (SW * (dg / a - g * da / a**2))[:, None]


def fit():
    return least_squares(residuals, [2.0], jac=jacobian, bounds=([1e-6], [100.0]),
                         xtol=1e-15, ftol=1e-15, gtol=1e-15, method="trf")


r = fit()
n = 200
t0, c0 = time.perf_counter(), time.process_time()
for _ in range(n):
    fit()
dt, dc = (time.perf_counter() - t0) / n, (time.process_time() - c0) / n
# Compare with sglab_fit_bench --benchmark_filter=lambda-d/ceres-like-scipy (same grid, start,
# tolerances); CPU time is the fair column on a busy machine.
print(f"scipy least_squares lambda_d = {r.x[0]:.17g}  nfev={r.nfev}  "
      f"{dt * 1e6:.1f} us wall, {dc * 1e6:.1f} us CPU per fit")
