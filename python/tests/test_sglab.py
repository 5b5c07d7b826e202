"""Tests of the Python module `sglab` (python/): the registry and evaluation (test_sglab_records.py:
constant sets, fit records, renders, plots, the stub). Run by CTest (tests/CMakeLists.txt: python_sglab)
with PYTHONPATH=build/python, SGLAB_EXE (the `sglab` binary) and SGLAB_SOURCE_DIR set.

The module must give what the `sglab` command gives: its values are compared with `sglab eval`
bit for bit (float and double, on the error grids of `sglab error-vs-time`, and on every method of
every quantity), its fit records with `sglab fit --json`, its renders with `sglab render
--dump-csv`. Exact references of their own: closed forms (the SG integral 2π(1 − e^{−2λ})/λ), the
scalar call for broadcasting, and the published constants for the fit.
"""
import json
import subprocess
import threading
import time
import tracemalloc

import numpy as np
import pytest

import sglab
from sglab_cli import (
    SGLAB_EXE,
    SEED,
    cli_eval,
    assert_bits_equal,
    sample_columns,
    diffuse_error_grid,
    specular_error_grid,
    quantity,
)


# ---- registry ------------------------------------------------------------------------------

def test_registry_matches_cli_list():
    listed = json.loads(subprocess.run([SGLAB_EXE, "eval", "--list", "--json"], capture_output=True, text=True,
                                       check=True).stdout)
    assert [q["name"] for q in sglab.quantities()] == [q["name"] for q in listed["quantities"]]
    for jq in listed["quantities"]:
        q = quantity(jq["name"])
        assert q["columns"] == jq["columns"]
        assert q["reference_method"] == jq["reference_method"]
        ms = sglab.methods(jq["name"])
        assert [(m["name"], m["source"], m["flaws"], m["may_be_negative"]) for m in ms] == \
               [(m["name"], m["source"], m["flaws"], m["may_be_negative"]) for m in jq["methods"]]
        assert sum(m["reference"] for m in ms) == (1 if jq["reference_method"] else 0)
        # The constants, field for field (the published values exactly: JSON prints 17 digits).
        assert [m["parameters"] for m in ms] == [m["parameters"] for m in jq["methods"]]
    tokuyoshi = next(m for m in sglab.methods("clamped-cosine") if m["name"] == "tokuyoshi2024")
    listed_tokuyoshi = next(m for q in listed["quantities"] if q["name"] == "clamped-cosine"
                            for m in q["methods"] if m["name"] == "tokuyoshi2024")
    assert [p["name"] for p in tokuyoshi["parameters"]] == ["A", "B", "C", "D", "E"]
    assert all(p["fit"] == "tokuyoshi2024-t" and "Tokuyoshi" in p["source"] for p in tokuyoshi["parameters"])
    assert [p["published"] for p in tokuyoshi["parameters"]] == [p["published"] for p in listed_tokuyoshi["parameters"]]
    # A method without constants lists none.
    assert next(m for m in sglab.methods("sg-integral") if m["name"] == "exact")["parameters"] == []


def test_unknown_quantity_lists_valid_ones():
    with pytest.raises(ValueError, match="unknown quantity 'nope'.*clamped-cosine"):
        sglab.methods("nope")


# ---- eval against `sglab eval`, bit for bit ------------------------------------------------------

@pytest.mark.parametrize("precision,dtype", [("float", np.float32), ("double", np.float64)])
@pytest.mark.parametrize("method", [m["name"] for m in sglab.methods("clamped-cosine")])
def test_diffuse_error_grid_matches_cli(method, precision, dtype):
    grid = diffuse_error_grid()
    cols = {k: v.astype(dtype) for k, v in grid.items()}
    py = sglab.eval("clamped-cosine", method, **cols)
    assert py.dtype == dtype and py.shape == cols["sharpness"].shape
    assert_bits_equal(py, cli_eval("clamped-cosine", method, cols, precision), dtype)


@pytest.mark.parametrize("precision,dtype", [("float", np.float32), ("double", np.float64)])
@pytest.mark.parametrize("method", [m["name"] for m in sglab.methods("specular")])
def test_specular_error_grid_matches_cli(method, precision, dtype):
    grid = specular_error_grid()
    if method == "reference":
        # The reference is a quadrature (about 15 s a precision on the whole grid, Python and CLI): 16
        # rows, every roughness at the extreme light sharpnesses 1 and 1000 (the sharp lights are the
        # quadrature's costly, stiff rows), whose (view, tilt) walks through all 12 pairs (row
        # 48a + 12l + 4v + d is taken where 4v + d = (2a + [l = 3]) mod 12). The 32 rows of every
        # (roughness, light sharpness) took about 1.5 times as long.
        keep = [48 * a + 12 * l + (2 * a + (l == 3)) % 12 for a in range(8) for l in (0, 3)]
        grid = {k: v[keep] for k, v in grid.items()}
    cols = {k: v.astype(dtype) for k, v in grid.items()}
    py = sglab.eval("specular", method, **cols)
    assert py.dtype == dtype
    assert_bits_equal(py, cli_eval("specular", method, cols, precision), dtype)


EVERY_METHOD = [(q["name"], m) for q in sglab.quantities() for m in q["methods"]]


@pytest.mark.parametrize("quantity_name,method", EVERY_METHOD)
def test_every_method_matches_cli(quantity_name, method):
    q = quantity(quantity_name)
    # 24 rows; 4 of a quadrature reference (up to 0.5 s a row: the specular ones took 9 s with 24,
    # 2.4 s with 8).
    n = 4 if method == q["reference_method"] else 24
    cols = sample_columns(q, n, SEED + len(quantity_name) + len(method))
    for precision, dtype in (("float", np.float32), ("double", np.float64)):
        typed = {k: v.astype(dtype) for k, v in cols.items()}
        py = sglab.eval(quantity_name, method, **typed)
        assert py.dtype == dtype and py.shape == (n,)
        assert np.all(np.isfinite(py))
        assert_bits_equal(py, cli_eval(quantity_name, method, typed, precision), dtype)


@pytest.mark.parametrize("quantity_name,method", [("clamped-cosine", "tokuyoshi2024"), ("clamped-cosine", "reference"),
                                                  ("sg-integral", "exact"), ("product-integral", "exact"),
                                                  ("vmf-mean-length", "banerjee")])
def test_mp50_matches_cli(quantity_name, method):
    q = quantity(quantity_name)
    texts = {"sharpness": ["0.001", "0.1", "2.5", "1e3"], "cosine": ["-1", "-0.3", "0.1", "1"],
             "sharpness1": ["0.1", "1", "10", "1e4"], "sharpness2": ["3", "0.5", "1e-3", "7"]}
    cols = {c["name"]: texts[c["name"]] for c in q["columns"]}
    py = sglab.eval(quantity_name, method, precision="mp50", **cols)
    assert py.dtype == object and all(isinstance(s, str) for s in py)
    assert list(py) == cli_eval(quantity_name, method, cols, "mp50")
    # Floats are taken exactly: 0.5 and "0.5" are the same number.
    if quantity_name == "sg-integral":
        assert sglab.eval(quantity_name, method, precision="mp50", sharpness=2.5) == py[2]


# ---- vectorized=True: the registry's SIMD batch evaluators ---------------------------------------

@pytest.mark.parametrize("precision,dtype,rtol", [("float", np.float32, 2e-5), ("double", np.float64, 1e-12)])
@pytest.mark.parametrize("quantity_name,method", [("clamped-cosine", "tokuyoshi2024"), ("clamped-cosine", "sglab"),
                                                  ("specular", "sg-warp")])
def test_vectorized_agrees_with_cli_to_rounding(quantity_name, method, precision, dtype, rtol):
    """The SIMD kernels against `sglab eval` (the scalar definition, an independent code path):
    equal to a few ulp relative to the grid's scale (docs/simd.md: not bit for bit)."""
    grid = diffuse_error_grid() if quantity_name == "clamped-cosine" else specular_error_grid()
    cols = {k: v.astype(dtype) for k, v in grid.items()}
    py = sglab.eval(quantity_name, method, vectorized=True, **cols)
    assert py.dtype == dtype
    ref = np.array([float(t) for t in cli_eval(quantity_name, method, cols, precision)])
    got = py.ravel().astype(np.float64)
    scale = np.maximum(np.abs(ref), 1e-6 * np.max(np.abs(ref)))
    worst = np.max(np.abs(got - ref) / scale)
    assert worst <= rtol, f"{quantity_name}/{method} {precision}: largest relative difference {worst:.3g}"


def test_vectorized_checks_and_strides():
    """vectorized=True keeps every check (same message), reads broadcast and strided views, and
    refuses anything but a bool."""
    lam = np.array([0.5, 2.0, np.nan, 4.0])
    with pytest.raises(ValueError, match=r"column 'sharpness', index 2, value nan"):
        sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam, cosine=0.5, vectorized=True)
    grid = np.logspace(-3, 4, 40)[::2]  # strided
    c = np.linspace(-1, 1, 7)[:, None]  # broadcast
    a = sglab.eval("clamped-cosine", "hill-fitted", sharpness=grid, cosine=c, vectorized=True)
    b = sglab.eval("clamped-cosine", "hill-fitted", sharpness=np.ascontiguousarray(np.broadcast_to(grid, (7, 20))),
                   cosine=np.ascontiguousarray(np.broadcast_to(c, (7, 20))), vectorized=True)
    assert a.shape == (7, 20) and np.array_equal(a, b)
    with pytest.raises(ValueError, match="vectorized"):
        sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=1.0, cosine=0.5, vectorized="yes")


def test_domain_bounds_still_refuse_a_row_inside_a_large_chunk():
    # hill-fitted states its domain (lambda > 0) as a column bound, checked per chunk by the chunk's
    # least value: one zero deep inside a contiguous array must still be refused, named by its index.
    for dt in (np.float64, np.float32):
        lam = np.ones(100000, dtype=dt)
        lam[77777] = 0
        with pytest.raises(ValueError, match=r"index 77777 \(sharpness 0"):
            sglab.eval("clamped-cosine", "hill-fitted", sharpness=lam, cosine=np.full(100000, 0.5, dtype=dt))


def test_closed_form_sg_integral():
    lam = np.logspace(-3, 4, 50)
    exact = 2 * np.pi * -np.expm1(-2 * lam) / lam
    got = sglab.eval("sg-integral", "exact", sharpness=lam)
    np.testing.assert_allclose(got, exact, rtol=4e-16)


# ---- dtypes, broadcasting, no copy, GIL ----------------------------------------------------

def test_dtype_preservation():
    lam32 = np.array([0.5, 2, 30], dtype=np.float32)
    c32 = np.array([-0.5, 0.2, 1], dtype=np.float32)
    assert sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam32, cosine=c32).dtype == np.float32
    # A Python number does not widen float32 arrays (as in numpy arithmetic).
    assert sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam32, cosine=0.5).dtype == np.float32
    assert sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam32.astype(np.float64), cosine=c32).dtype == np.float64
    assert sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=[1, 2, 3], cosine=0).dtype == np.float64
    forced = sglab.eval("clamped-cosine", "tokuyoshi2024", precision="float", sharpness=[1.0, 2.0], cosine=0.5)
    assert forced.dtype == np.float32
    assert sglab.eval("clamped-cosine", "tokuyoshi2024", precision="double", sharpness=lam32, cosine=c32).dtype == np.float64
    s = sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=2.0, cosine=0.5)
    assert isinstance(s, np.float64)
    assert isinstance(sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=np.float32(2), cosine=np.float32(0.5)), np.float32)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_broadcasting_matches_scalar_calls(dtype):
    lam = np.logspace(-2, 3, 7).astype(dtype)[:, None]
    cos = np.linspace(-1, 1, 5).astype(dtype)
    grid = sglab.eval("clamped-cosine", "tokuyoshi2022", sharpness=lam, cosine=cos)
    assert grid.shape == (7, 5) and grid.dtype == dtype
    for i in range(7):
        for j in range(5):
            assert grid[i, j] == sglab.eval("clamped-cosine", "tokuyoshi2022", sharpness=lam[i, 0], cosine=cos[j])
    # Non-contiguous views and a 3-D broadcast give the same values.
    wide = np.linspace(-1, 1, 10).astype(dtype)[::2]
    assert np.array_equal(sglab.eval("clamped-cosine", "tokuyoshi2022", sharpness=lam, cosine=wide[None, :]),
                          sglab.eval("clamped-cosine", "tokuyoshi2022", sharpness=lam, cosine=np.ascontiguousarray(wide)))
    three = sglab.eval("product-integral", "exact", sharpness1=lam, sharpness2=lam.reshape(7, 1, 1), cosine=cos)
    assert three.shape == (7, 7, 5)
    assert three[4, 2, 3] == sglab.eval("product-integral", "exact", sharpness1=lam[2, 0], sharpness2=lam[4, 0], cosine=cos[3])
    with pytest.raises(ValueError, match="do not broadcast"):
        sglab.eval("clamped-cosine", "tokuyoshi2022", sharpness=np.ones(3), cosine=np.ones(4))


def test_no_copy_of_the_input():
    n = 1_000_000
    rng = np.random.default_rng(SEED)
    lam = 10 ** rng.uniform(-3, 4, n)
    cos = rng.uniform(-1, 1, n)
    tracemalloc.start()
    tracemalloc.reset_peak()
    before = tracemalloc.get_traced_memory()[0]
    out = sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam, cosine=cos)
    peak = tracemalloc.get_traced_memory()[1] - before
    tracemalloc.stop()
    # numpy reports its allocations to tracemalloc: only the 8 MB output, no copy of the 16 MB input.
    assert out.nbytes <= peak < out.nbytes + 1_000_000, peak


def test_gil_released_during_the_batch():
    rng = np.random.default_rng(SEED)
    lam = 10 ** rng.uniform(-3, 4, 3000)
    cos = rng.uniform(-1, 1, 3000)
    t0 = time.perf_counter()
    sglab.eval("clamped-cosine", "reference", sharpness=lam[:300], cosine=cos[:300])
    per_point = (time.perf_counter() - t0) / 300
    n = max(300, min(200_000, int(1.0 / per_point)))  # about a second of work
    lam, cos = 10 ** rng.uniform(-3, 4, n), rng.uniform(-1, 1, n)
    done = threading.Event()
    elapsed = []

    def work():
        t = time.perf_counter()
        sglab.eval("clamped-cosine", "reference", sharpness=lam, cosine=cos)
        elapsed.append(time.perf_counter() - t)
        done.set()

    thread = threading.Thread(target=work)
    last, gap = time.perf_counter(), 0.0
    thread.start()
    while not done.is_set():
        now = time.perf_counter()
        gap, last = max(gap, now - last), now
    thread.join()
    # With the GIL held, this loop would stop for the whole evaluation.
    assert gap < 0.5 * elapsed[0], (gap, elapsed[0])


# ---- bad input -------------------------------------------------------------------------------

def test_bad_input_names_column_index_and_value():
    cos = np.array([0.1, 0.2, 1.5, 0.3])
    with pytest.raises(ValueError, match=r"column 'cosine', index 2, value 1\.5: a cosine must lie in \[-1, 1\]"):
        sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=1.0, cosine=cos)
    lam = np.array([[1.0, 2.0], [3.0, -4.0]], dtype=np.float32)
    with pytest.raises(ValueError, match=r"column 'sharpness', index \(1, 1\), value -4: a sharpness must be >= 0"):
        sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=lam, cosine=0.5)
    with pytest.raises(ValueError, match=r"column 'sharpness', index 1, value nan: must be a finite number"):
        sglab.eval("clamped-cosine", "meder", sharpness=[1.0, np.nan], cosine=0.5)
    with pytest.raises(ValueError, match=r"column 'cosine', index 0, value inf"):
        sglab.eval("clamped-cosine", "meder", sharpness=1.0, cosine=[np.inf])
    # The method's own domain: 2π/λ at λ = 0.
    with pytest.raises(ValueError, match=r"index 3 \(sharpness 0, cosine 0.5\): outside the method's domain: undefined at sharpness 0"):
        sglab.eval("clamped-cosine", "punctual-approx", sharpness=[1.0, 2.0, 3.0, 0.0], cosine=0.5)
    with pytest.raises(ValueError, match=r"column 'sharpness', index 0, value '-1'"):
        sglab.eval("sg-integral", "exact", precision="mp50", sharpness=["-1"])
    with pytest.raises(ValueError, match=r"column 'sharpness', index 1, value '1x': .*not a number"):
        sglab.eval("sg-integral", "exact", precision="mp50", sharpness=["1", "1x"])


def test_mp50_beyond_double_range():
    # mp50 reads "1e-400" into its own range: 2π⟨c⟩/λ = π·1e400 at c = 0.5 (a 50-digit closed form).
    from decimal import Decimal, getcontext
    getcontext().prec = 60
    pi = Decimal("3.14159265358979323846264338327950288419716939937510582097494")
    got = sglab.eval("clamped-cosine", "punctual-approx", precision="mp50", sharpness=["1e-400", "1e400"], cosine="0.5")
    assert abs(Decimal(got[0]) / (pi * Decimal("1e400")) - 1) < Decimal("1e-45")
    assert abs(Decimal(got[1]) / (pi * Decimal("1e-400")) - 1) < Decimal("1e-45")
    # A method that evaluates in double refuses it by name rather than rounding it to 0 or inf.
    with pytest.raises(ValueError, match=r"value '1e400': is outside double's range, and method 'reference' evaluates in double"):
        sglab.eval("specular", "reference", precision="mp50", roughness="0.3", light_sharpness="1e400", light_cos="0.5",
                   view_cos="0.5", light_azimuth="3", f0="0.04")
    # Outside mp50's own range: refused.
    with pytest.raises(ValueError, match=r"out of the range of mp50 \(too large\)"):
        sglab.eval("clamped-cosine", "punctual-approx", precision="mp50", sharpness=["1e999999999999"], cosine="0.5")


def test_bad_call_raises():
    with pytest.raises(ValueError, match="missing column.*cosine"):
        sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=1.0)
    with pytest.raises(ValueError, match="unknown column.*cosin"):
        sglab.eval("clamped-cosine", "tokuyoshi2024", sharpness=1.0, cosine=0.5, cosin=0.5)
    with pytest.raises(ValueError, match="unknown method 'x'.*tokuyoshi2024"):
        sglab.eval("clamped-cosine", "x", sharpness=1.0, cosine=0.5)
    with pytest.raises(ValueError, match="unknown quantity"):
        sglab.eval("x", "y", sharpness=1.0)
    with pytest.raises(ValueError, match="unknown precision 'half'"):
        sglab.eval("sg-integral", "exact", precision="half", sharpness=1.0)
    with pytest.raises(ValueError, match="<constants record 0>: key 'fit'"):  # a dict is a fit record
        sglab.eval("sg-integral", "exact", constants={"x": 1}, sharpness=1.0)
    with pytest.raises(ValueError, match="constants: expected a path"):
        sglab.eval("sg-integral", "exact", constants=3, sharpness=1.0)
    with pytest.raises(ValueError, match="expected real numbers"):
        sglab.eval("sg-integral", "exact", sharpness=np.array([1 + 1j]))


def test_non_finite_result_is_never_returned():
    # 2π/λ overflows float at a λ just above the smallest normal float (> 0, so inside the domain;
    # a subnormal λ is refused as input, as `sglab eval` refuses it).
    with pytest.raises(FloatingPointError, match=r"index 1 \(sharpness 1.2e-38\).*returned inf in float"):
        sglab.eval("sg-integral", "approx", sharpness=np.array([1, 1.2e-38], dtype=np.float32))
