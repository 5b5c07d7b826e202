"""What the tests of the Python module share (test_sglab.py, test_sglab_records.py): the `sglab`
binary and source tree CTest names, the seed, `sglab eval` run on columns, and the error grids of
`sglab error-vs-time`."""
import csv
import io
import math
import os
import subprocess
import sys

import numpy as np

import sglab

SGLAB_EXE = os.environ.get("SGLAB_EXE", "build/bin/sglab")
SOURCE_DIR = os.environ.get("SGLAB_SOURCE_DIR", os.getcwd())
SEED = 20261201
print(f"sglab tests: seed {SEED}, sglab {SGLAB_EXE}", file=sys.stderr)


def decimal(x, dtype):
    """Shortest text that reads back to the same value of dtype."""
    return np.format_float_scientific(dtype(x), unique=True)


def cli_eval(quantity, method, columns, precision, constants=()):
    """`sglab eval` on the rows of `columns` (name → 1-D array or list of strings), with `--constants
    PATH` for each of `constants`; the value texts."""
    names = list(columns)
    n = len(columns[names[0]])
    dtype = np.float32 if precision == "float" else np.float64
    text = io.StringIO()
    w = csv.writer(text, lineterminator="\n")
    w.writerow(names)
    for i in range(n):
        w.writerow([columns[c][i] if isinstance(columns[c][i], str) else decimal(columns[c][i], dtype) for c in names])
    sets = [a for c in constants for a in ("--constants", os.fspath(c))]
    run = subprocess.run([SGLAB_EXE, "eval", quantity, "--method", method, "--precision", precision, *sets],
                         input=text.getvalue(), capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    rows = list(csv.DictReader(io.StringIO(run.stdout)))
    assert len(rows) == n
    return [r["value"] for r in rows]


def assert_bits_equal(py, cli_text, dtype):
    expected = np.array([dtype(t) for t in cli_text], dtype=dtype)
    got = np.asarray(py, dtype=dtype).ravel()
    itype = np.uint32 if dtype == np.float32 else np.uint64
    bad = np.nonzero(got.view(itype) != expected.view(itype))[0]
    assert bad.size == 0, f"{bad.size} values differ from `sglab eval`, first at {bad[0]}: {got[bad[0]]!r} vs {cli_text[bad[0]]}"


# Valid values per column kind (inside every method's domain: sharpness > 0, bandwidths > 0).
POOLS = {
    "sharpness": [1e-3, 0.05, 0.5, 1, 3, 20, 100, 1e3, 1e4],
    "cosine": [-1, -0.7, -0.2, 0, 0.3, 0.8, 1],
    "mean_length": [0, 0.2, 0.5, 0.9, 0.999],
    "positive": [0.05, 0.2, 0.5, 1],
    "nonnegative": [0.5, 2, 10, 100],
    "angle": [0, 1, 2.5, 3.141592653589793],
    "unit_interval": [0.1, 0.5, 0.9, 1],
}


def sample_columns(q, n, seed):
    rng = np.random.default_rng(seed)
    return {c["name"]: rng.choice(POOLS[c["kind"]], size=n) for c in q["columns"]}


def diffuse_error_grid():
    """The (λ, c) grid of `sglab error-vs-time` for clamped-cosine: λ log-spaced over [1e-3, 1e4],
    4 per decade, × c ∈ [−1, 1] in 40 steps (experiments/error_vs_time.cpp: diffuse_grid)."""
    lam = np.array([10.0 ** (-3 + i / 4) for i in range(7 * 4 + 1)])
    cos = np.array([-1 + 2.0 * j / 40 for j in range(41)])
    L, C = np.meshgrid(lam, cos, indexing="ij")
    return {"sharpness": L.ravel(), "cosine": C.ravel()}


def specular_error_grid():
    """The specular grid of `sglab error-vs-time` (error_vs_time.cpp: specular_grid)."""
    rows = []
    for a in (0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1):
        for lam in (1, 10, 100, 1000):
            for v in (0.9, 0.5, 0.2):
                for d in (0, 0.1, 0.3, 0.6):
                    theta = math.acos(v) - d
                    rows.append((a, lam, math.cos(theta), v, math.pi if theta >= 0 else 0.0, 0.04))
    names = ("roughness", "light_sharpness", "light_cos", "view_cos", "light_azimuth", "f0")
    return {n: np.array([r[i] for r in rows]) for i, n in enumerate(names)}


def quantity(name):
    return next(q for q in sglab.quantities() if q["name"] == name)
