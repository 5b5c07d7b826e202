#!/usr/bin/env python3
"""ns per evaluation of `sglab.eval` from Python against the C++ batch evaluators, in one run.

Python: `sglab.eval(quantity, method, sharpness=…, cosine=…)` on N points (default 1e6; λ
log-uniform in [1e-3, 1e4], c uniform in [−1, 1], seeded), median of --repeats calls, ns = CPU
time of the process (all its threads) / N, the measure Google Benchmark gives the C++ side; the
wall time is shown beside it (the machine may be shared). That includes everything a caller pays: argument handling, reading the arrays, the
column and domain checks of `sglab eval`, the batch call, the finiteness check of every result
and allocating the output.
C++: build/benchmarks/sglab_core_bench (the registry's batch evaluators on 4096 seeded points of
the same ranges, no checks), run right after on the same CPUs, and again with `--points N` (N
seeded points, as many as Python's): the 4096 points stay in cache and are timed over and over, so
that the branch predictor learns a scalar method's branches on them (sg-integral/exact's λ > 1
test: 8 ns per point at 4096, 14 at 1e6, in C++ alone); at N both sides pay the same. The specular columns as the C++
bench draws them: α log-uniform in [1e-2, 1], λ as above, light_cos in [−1, 1], view_cos and f0 in
[0, 1], the azimuth over a turn.

Each method twice: `sglab.eval(...)` (the default: bit for bit `sglab eval`, the SIMD methods row
by row through their scalar definition) and `sglab.eval(..., vectorized=True)` (every method
through its batch evaluator, the one the C++ column times). "overhead" = Python ns − C++ ns.
The C++ batch runs on 4096 points that stay in cache; 1e6 points do not, so part of the overhead
is memory traffic that any numpy call on these arrays pays. The "numpy floor" column measures it
in the same run: numpy adding the method's columns into a new array (each column read once, one
new array written: what `sglab.eval` must read and write at the least).

Both are pinned to one CPU by default (--cpus 1), so that the ratio compares the same work: the
module spreads large batches over all cores with TBB, the C++ batch is single-threaded. TBB sizes
its pool from the affinity mask, which is set before sglab is imported.

Paired rounds. On a shared virtual machine the speed of a core changes in phases of a second or
more (the same C++ batch at 1e6 points: 13.1 to 17.7 ns per point in twelve runs of a minute; the
same Python call 15.4 or 21 ns in rounds of one process), so a Python median and a C++ median
taken a minute apart can differ by the phase, not by the call. The columns at N points therefore
come from --rounds rounds (default 5): in each, method by method, the Python calls (median of
--repeats) and right after them the C++ batch at N points for the same method (one Google
Benchmark run), and "overhead at N points" is the median over the rounds of the difference within
a round, with its smallest and largest value beside it. Python's columns are the medians over the
rounds. The 4096-point C++ column is one run of three repetitions after the rounds.

Run: PYTHONPATH=build/python /usr/bin/python3 benchmarks/python_eval_bench.py [--n 1000000]
     [--rounds 5] [--repeats 7] [--cpus 1|all] [--bench build/benchmarks/sglab_core_bench] [--methods specular/asg,sg-integral/exact]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

DEFAULT_METHODS = [
    ("clamped-cosine", "sglab"),
    ("clamped-cosine", "tokuyoshi2024"),
    ("clamped-cosine", "tokuyoshi2022"),
    ("clamped-cosine", "meder"),
    ("clamped-cosine", "hill-fitted"),
    ("clamped-cosine", "punctual"),
    ("sg-integral", "exact"),
    ("specular", "sg-warp"),
    ("specular", "asg"),
]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--n", type=float, default=1e6)
    p.add_argument("--repeats", type=int, default=7)
    p.add_argument("--rounds", type=int, default=5,
                   help="paired rounds of Python and the C++ batch at N points (see above)")
    p.add_argument("--cpus", default="1", help="1 (pinned to one CPU) or all")
    p.add_argument("--bench", default="build/benchmarks/sglab_core_bench")
    p.add_argument("--methods", default="",
                   help="comma-separated quantity/method pairs of the default list (default: all of them)")
    a = p.parse_args()
    methods = DEFAULT_METHODS
    if a.methods:
        wanted = a.methods.split(",")
        unknown = [w for w in wanted if tuple(w.split("/", 1)) not in DEFAULT_METHODS]
        if unknown:
            print(f"--methods: {', '.join(unknown)} not in the list "
                  f"({', '.join(q + '/' + m for q, m in DEFAULT_METHODS)})", file=sys.stderr)
            return 2
        methods = [qm for qm in DEFAULT_METHODS if "/".join(qm) in wanted]
    n = int(a.n)
    if n < 1 or n > 100_000_000:
        print(f"--n {a.n} is outside [1, 1e8]", file=sys.stderr)
        return 2
    if not 1 <= a.repeats <= 1000:
        print(f"--repeats {a.repeats} is outside [1, 1000]", file=sys.stderr)
        return 2
    if not 1 <= a.rounds <= 100:
        print(f"--rounds {a.rounds} is outside [1, 100]", file=sys.stderr)
        return 2
    if a.cpus not in ("1", "all"):
        print(f"--cpus '{a.cpus}' is not 1 or all", file=sys.stderr)
        return 2
    cpu_set = None
    if a.cpus == "1":
        cpu_set = {min(os.sched_getaffinity(0))}
        os.sched_setaffinity(0, cpu_set)

    import numpy as np
    import sglab

    rng = np.random.default_rng(20261122)
    lam = 10 ** rng.uniform(-3, 4, n)
    cos = rng.uniform(-1, 1, n)
    alpha = 10 ** rng.uniform(-2, 0, n)
    view = rng.uniform(0, 1, n)
    azimuth = rng.uniform(0, 2 * np.pi, n)
    f0 = rng.uniform(0, 1, n)
    base = (lam, cos, alpha, view, azimuth, f0)
    inputs = {np.float64: base, np.float32: tuple(a.astype(np.float32) for a in base)}
    columns = {"clamped-cosine": ("sharpness", "cosine"), "sg-integral": ("sharpness",),
               "specular": ("roughness", "light_sharpness", "light_cos", "view_cos", "light_azimuth", "f0")}
    picks = {"clamped-cosine": (0, 1), "sg-integral": (0,), "specular": (2, 0, 1, 3, 4, 5)}

    def median_ns(f):
        f()  # warm-up
        cpu, wall = [], []
        for _ in range(a.repeats):
            t, w = time.process_time(), time.perf_counter()
            f()
            cpu.append(time.process_time() - t)
            wall.append(time.perf_counter() - w)
        return 1e9 * statistics.median(cpu) / n, 1e9 * statistics.median(wall) / n

    def numpy_floor(cols):
        if len(cols) == 1:
            return np.negative(cols[0])
        out = np.add(cols[0], cols[1])
        for c in cols[2:]:
            np.add(out, c, out=out)
        return out

    def cpp(regex, points, repetitions):
        """The C++ batch's median ns per evaluation, per (quantity, method, precision)."""
        run = subprocess.run([a.bench, f"--benchmark_filter={regex}", "--benchmark_format=json",
                              f"--benchmark_repetitions={repetitions}", "--benchmark_report_aggregates_only=true"]
                             + (["--points", str(points)] if points else []),
                             capture_output=True, text=True,
                             preexec_fn=(lambda: os.sched_setaffinity(0, cpu_set)) if cpu_set else None)
        if run.returncode != 0:
            print(run.stderr, file=sys.stderr)
            return None
        out = {}
        report = run.stdout[run.stdout.index("{"):]  # after the bench's line about its inputs
        for b in json.loads(report)["benchmarks"]:
            # (one repetition reports the run itself, no aggregates)
            if b.get("aggregate_name", "median") == "median":
                q, m, precision = b["run_name"].split("/")[:3]
                out[(q, m, precision)] = 1e9 * b["ns/eval"]  # the counter is in seconds per evaluation
        return out

    def regex_of(pairs):
        return "^(" + "|".join(f"{q}/{m}/(float|double)" for q, m in pairs) + ")$"

    floor_ns = {}
    py_rounds = {}   # (q, m, precision, vectorized) -> [(CPU ns, wall ns) per round]
    cpp_rounds = {}  # (q, m, precision) -> [ns per round, at n points]
    for _ in range(a.rounds):
        for q, m in methods:
            for dtype, precision in ((np.float32, "float"), (np.float64, "double")):
                kw = dict(zip(columns[q], (inputs[dtype][i] for i in picks[q])))
                if (q, precision) not in floor_ns:
                    cols = list(kw.values())
                    floor_ns[(q, precision)] = median_ns(lambda: numpy_floor(cols))[0]
                for vectorized in (False, True):
                    extra = {"vectorized": True} if vectorized else {}
                    py_rounds.setdefault((q, m, precision, vectorized), []).append(
                        median_ns(lambda: sglab.eval(q, m, **kw, **extra)))
            got = cpp(regex_of([(q, m)]), n, 1)  # right after this method's Python calls
            if got is None:
                return 1
            for key, ns in got.items():
                cpp_rounds.setdefault(key, []).append(ns)

    cpp_ns = cpp(regex_of(methods), None, 3)
    if cpp_ns is None:
        return 1
    py_ns = {key: (statistics.median(c for c, _ in v), statistics.median(w for _, w in v))
             for key, v in py_rounds.items()}
    cpp_n_ns = {key: statistics.median(v) for key, v in cpp_rounds.items()}
    # Round by round: Python's call minus the C++ batch run right after it.
    paired = {key: [c - cn for (c, _), cn in zip(v, cpp_rounds.get(key[:3], []))] for key, v in py_rounds.items()}

    print(f"# sglab.eval from Python ({n} points, median of {a.repeats} calls in each of {a.rounds} rounds) "
          f"against the C++ batch (sglab_core_bench: on its 4096 cached points, median of 3, and with --points {n} "
          f"right after Python's calls in each round), {'one CPU' if cpu_set else 'all CPUs'}")
    print("| quantity | method | precision | vectorized | Python ns/eval (CPU) | Python ns/eval (wall) "
          "| C++ batch ns/eval (CPU, 4096 points) | overhead ns/eval (CPU) "
          f"| C++ batch ns/eval (CPU, {n} points) | overhead at {n} points "
          f"| overhead at {n} points, range over rounds | numpy floor ns/eval (CPU) | ratio (CPU) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key, (ns, wall_ns) in py_ns.items():
        c, cn, d = cpp_ns.get(key[:3]), cpp_n_ns.get(key[:3]), paired.get(key)
        cpp_cols = (f"{c:.2f} | {ns - c:.2f} | {cn:.2f} | {statistics.median(d):.2f} | {min(d):.2f} … {max(d):.2f} "
                    f"| {floor_ns[(key[0], key[2])]:.2f} | {ns / c:.2f}"
                    if c and cn and d else "- | - | - | - | - | - | -")
        print(f"| {key[0]} | {key[1]} | {key[2]} | {'yes' if key[3] else 'no'} | {ns:.2f} | {wall_ns:.2f} | {cpp_cols} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
