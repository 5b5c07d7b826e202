#!/usr/bin/env bash
# Every performance figure of sglab in one run, printed as a table and written as a CSV
# (docs/testing.md, "Performance report"). Run from anywhere; it works in the checkout it sits in.
#
#   bash benchmarks/perf_report.sh [--skip-cold] [--skip-tests] [--skip-reproduce-full]
#        [--skip-reproduce-quick] [--quick-runs N] [--skip-python] [--skip-render] [--render-rounds N]
#        [--touch FILE]... [--jobs N]
#        [--csv FILE] [--keep] [--tu-times] [--baseline REV | --tree DIR]
#
# --baseline REV: before and after in one sitting. REV (a commit of this repository, checked out
# into a scratch git worktree) is measured first, then this checkout, each with every row below
# by this script; the CSV has one line per row with both and after/before (wall, else CPU).
# --tree DIR: measure the checkout at DIR instead of this one (its sources, its Python bench),
# configured as DIR's scripts/setup.sh does (Ninja where it says -G Ninja, else CMake's default).
#
# Rows (wall and CPU seconds of the process tree, bash's `time`; CPU = user + system):
#   configure           cmake configure of a scratch build dir (Release, SGLAB_WERROR=ON, setup.sh's generator
#                       and vector kernel sets)
#   build-sglab         cold build of what the main job (`sglab reproduce`) needs: `sglab`, ccache off
#   build-python        then the Python module (`sglab_python`), which setup.sh --python and --tests build
#   rebuild-touch       the same targets after touching one method's file (--touch, default
#                       core/src/registry_core.cpp: the diffuse registry, which includes every
#                       diffuse method's header; a method's formula header, such as
#                       core/include/sglab/clamped_cosine.hpp, rebuilds every unit that includes it:
#                       docs/testing.md, "Rebuilding after a method's header"); --touch repeated:
#                       one row rebuild-touch/FILE per file, each touched and rebuilt in turn
#   build-tests         the rest of the tree (test executables, benchmarks), cold, ccache off
#   build-benchmarks    with --skip-tests instead: only the two benchmarks the Python and render rows run
#   ctest               `ctest -j2` over the whole suite (wall; CPU = the tests' summed seconds)
#   reproduce-quick     `sglab reproduce --quick` into an empty scratch --out (--quick-runs N: N runs,
#                       each into an empty --out; the row gives the median wall and CPU, the note every run)
#   reproduce-full      `sglab reproduce` into an empty scratch --out/--tables-dir (paper_tables/ untouched)
#   reproduce-full-alone  the timed steps of that run, which run alone (its reproduce_times.csv,
#                       row steps-run-alone): the part of its wall time no scheduling could hide
#   python-eval/...     ns per point of `sglab.eval` from Python, its C++ batch, their ratio
#                       (benchmarks/python_eval_bench.py, 1e6 points, one CPU)
#   render-specular/M   ns per (pixel, lobe) of the specular VSGL shading by M (`sglab render
#                       --specular M`): the built-in vsgl-asg and the registry methods asg, sg-warp,
#                       sglab, in --render-rounds rounds (default 5), each one run of sglab_render_bench's
#                       BM_SpecularMethod (3 repetitions of every method, in random order); the median
#                       over the rounds of each method's ns and of its ratio to vsgl-asg in the same
#                       round, with the ratio's range (asg is the same formula as vsgl-asg)
#   render-visibility   ns per (pixel, lobe) of VSGL shading with --visibility (fis 64, the cube-map
#                       lookups included: BM_ShadingVisibility), median of 5, against each pixel
#                       shaded alone with scalar lookups in the same run
#   render-cube-shadow-maps  ns per ray of the cube shadow maps of --visibility (BM_CubeShadowMaps,
#                       one thread), median of 5, against cast_ray texel by texel in the same run
#   render-vpl-sum/P    ns per (pixel, VPL) of the exact VPL sum (the renderer's reference) in
#                       double and float, against the arithmetic bound the benchmark derives from this
#                       core's peak rates, measured in the same process: --render-rounds processes of
#                       one repetition of BM_Reference each; the median over them of the ns and of
#                       the ratio, with the ratio's range
#   render-vpl-sum-rsm128/P  the same with the render sweeps' 128² RSM (SGLAB_RENDER_BENCH_RSM=128)
#   tu/PATH             with --tu-times: the ten heaviest translation units of build-sglab and
#                       build-python (CPU seconds each, benchmarks/tu_time.sh as the compiler launcher)
# Rounds: on a shared virtual machine a core's speed changes in phases of seconds (the float VPL sum
# 2.3 or 2.8 ns in consecutive repetitions of one process), so the specular and VPL-sum rows run one
# short process per round (the VPL sum one repetition, the specular methods three each, interleaved),
# rounds apart in time, and give the median and range over the rounds (docs/testing.md).
# --skip-cold uses ./build as it is (no configure/builds timed; ctest, reproduce and Python run on it).
# The machine may be shared: the load average at the start and end goes into the CSV's header, and
# CPU seconds are the steadier figure. Nothing is written into the checkout but the CSV
# (default: results/perf_report.csv); the scratch build and results are removed unless --keep.
set -euo pipefail
self=$(cd "$(dirname "$0")" && pwd)/$(basename "$0")
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

cold=1 tests=1 full=1 quick=1 quick_runs=1 python=1 render=1 render_rounds=5 keep=0 jobs=2 tu_times=0
touch_files=()
csv=results/perf_report.csv
baseline='' tree=''
args=("$@")
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --skip-cold) cold=0 ;;
    --skip-tests) tests=0 ;;
    --skip-reproduce-full) full=0 ;;
    --skip-reproduce-quick) quick=0 ;;
    --quick-runs) quick_runs=${2:?--quick-runs needs a number}; shift ;;
    --skip-python) python=0 ;;
    --skip-render) render=0 ;;
    --render-rounds) render_rounds=${2:?--render-rounds needs a number}; shift ;;
    --keep) keep=1 ;;
    --tu-times) tu_times=1 ;;
    --touch) touch_files+=("${2:?--touch needs a file}"); shift ;;
    --jobs) jobs=${2:?--jobs needs a number}; shift ;;
    --csv) csv=${2:?--csv needs a file}; shift ;;
    --baseline) baseline=${2:?--baseline needs a commit}; shift ;;
    --tree) tree=${2:?--tree needs a directory}; shift ;;
    -h | --help) usage; exit 0 ;;
    *) echo "perf_report: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
case "$jobs" in '' | *[!0-9]* | 0) echo "perf_report: --jobs '$jobs' is not a positive integer" >&2; exit 2 ;; esac
case "$quick_runs" in '' | *[!0-9]* | 0)
  echo "perf_report: --quick-runs '$quick_runs' is not a positive integer" >&2; exit 2 ;; esac
case "$render_rounds" in '' | *[!0-9]* | 0)
  echo "perf_report: --render-rounds '$render_rounds' is not a positive integer" >&2; exit 2 ;; esac
[ -n "$baseline" ] && [ -n "$tree" ] && { echo "perf_report: --baseline and --tree exclude each other" >&2; exit 2; }
[ -n "$baseline" ] && [ "$cold" = 0 ] &&
  { echo "perf_report: --baseline builds the commit it checks out: it cannot take --skip-cold" >&2; exit 2; }
case "$csv" in /*) ;; *) csv=$root/$csv ;; esac  # relative to this checkout, also with --tree
if [ -n "$tree" ]; then
  [ -f "$tree/CMakeLists.txt" ] && [ -f "$tree/scripts/setup.sh" ] ||
    { echo "perf_report: --tree '$tree' is not an sglab checkout (no CMakeLists.txt and scripts/setup.sh)" >&2; exit 2; }
  root=$(cd "$tree" && pwd)
  cd "$root"
fi
((${#touch_files[@]})) || touch_files=(core/src/registry_core.cpp)
for f in "${touch_files[@]}"; do
  [ -f "$f" ] || { echo "perf_report: --touch '$f' is not a file of the checkout" >&2; exit 2; }
done

if [ -n "$baseline" ]; then
  rev=$(git -C "$root" rev-parse --verify --quiet "$baseline^{commit}") ||
    { echo "perf_report: --baseline '$baseline' is not a commit of this repository" >&2; exit 2; }
  # The same options for both runs, without --baseline and --csv.
  pass=()
  for ((k = 0; k < ${#args[@]}; k++)); do
    case "${args[k]}" in --baseline | --csv) k=$((k + 1)) ;; *) pass+=("${args[k]}") ;; esac
  done
  work=$(mktemp -d "${TMPDIR:-/tmp}/sglab-perf-versus-XXXXXX")
  trap 'git -C "$root" worktree remove --force "$work/tree" 2> /dev/null; rm -rf "$work"' EXIT
  git -C "$root" worktree add --detach --quiet "$work/tree" "$rev"
  echo "== baseline $rev (before)" >&2
  bash "$self" "${pass[@]}" --tree "$work/tree" --csv "$work/before.csv"
  echo "== this checkout, $(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet HEAD || echo ' with uncommitted changes') (after)" >&2
  bash "$self" "${pass[@]}" --csv "$work/after.csv"
  mkdir -p "$(dirname "$csv")"
  head_rev=$(git -C "$root" rev-parse HEAD)$(git -C "$root" diff --quiet HEAD || echo ' with uncommitted changes')
  python3 - "$work/before.csv" "$work/after.csv" "$rev" "$head_rev" "bash benchmarks/perf_report.sh ${args[*]}" > "$csv.tmp" << 'PY'
import csv, sys
def read(path):
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    head = [l for l in lines if l.startswith("#")]
    return head, {r["measure"]: r for r in csv.DictReader(l for l in lines if not l.startswith("#"))}
(hb, before), (ha, after), rev, head, command = read(sys.argv[1]), read(sys.argv[2]), *sys.argv[3:]
print(f"# Generated by `{command}`: before = {rev}, after = {head} (this checkout), measured one after the other")
print("# before:" + hb[0][1:] if hb else "# before: -")
print("# after:" + ha[0][1:] if ha else "# after: -")
w = csv.writer(sys.stdout, lineterminator="\n")
w.writerow(["measure", "before_wall_seconds", "before_cpu_seconds", "after_wall_seconds", "after_cpu_seconds",
            "after_over_before", "before_note", "after_note"])
for name in list(before) + [n for n in after if n not in before]:
    b, a = before.get(name, {}), after.get(name, {})
    ratio = ""
    for key in ("wall_seconds", "cpu_seconds"):
        try:
            ratio = f"{float(a[key]) / float(b[key]):.3f}"
            break
        except (KeyError, ValueError, ZeroDivisionError):
            pass
    w.writerow([name, b.get("wall_seconds", ""), b.get("cpu_seconds", ""), a.get("wall_seconds", ""),
                a.get("cpu_seconds", ""), ratio, b.get("note", ""), a.get("note", "")])
PY
  mv "$csv.tmp" "$csv"
  python3 - "$csv" << 'PY'
import csv, sys
with open(sys.argv[1], newline="") as f:
    rows = list(csv.reader(l for l in f if not l.startswith("#")))
print("| measure | before wall s | before CPU s | after wall s | after CPU s | after/before |")
print("|---|---|---|---|---|---|")
for r in rows[1:]:
    print("| " + " | ".join(r[:6]) + " |")
PY
  echo "(CSV: $csv)"
  exit 0
fi

scratch=$(mktemp -d "${TMPDIR:-/tmp}/sglab-perf-XXXXXX")
cleanup() { if [ "$keep" = 1 ]; then echo "kept $scratch" >&2; else rm -rf "$scratch"; fi; }
trap cleanup EXIT

rows=()  # "name|wall|cpu|note"
load() { cut -d' ' -f1-3 /proc/loadavg; }
load_start=$(load)

# timed NAME NOTE COMMAND…: runs COMMAND (output to $scratch/NAME.log), records its wall and CPU
# seconds (children included). A failing command stops the report with its log's tail.
timed() {
  local name=$1 note=$2
  shift 2
  local TIMEFORMAT='%R %U %S' t
  echo "== $name: $*" >&2
  if ! t=$({ time "$@" > "$scratch/$name.log" 2>&1; } 2>&1); then
    tail -n 30 "$scratch/$name.log" >&2
    echo "perf_report: $name failed (log above)" >&2
    exit 1
  fi
  read -r wall user sys <<< "$t"
  rows+=("$name|$wall|$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')|$note")
}

# rounds N CMD...: CMD N times, one after the other (the render rows' rounds: "Rounds" above).
rounds() {
  local n=$1 r
  shift
  for ((r = 1; r <= n; r++)); do "$@" || return 1; done
}

# render_rows KIND PREFIX LOG: the rows of the rounds of sglab_render_bench in LOG (one JSON report
# per round, --benchmark_format=json). KIND vpl: BM_Reference, one row per precision,
# PREFIX/double and PREFIX/float: the median over the rounds of the ns per (pixel, VPL) and of its
# ratio to the arithmetic bound of the same process (bound_ns_per_pixel_vpl: the term's operations
# over this core's peak rates, render_bench.cpp), the ratio's range and the VPL count; a checkout
# whose benchmark predates the bound prints "-" for it, and one that predates
# SGLAB_RENDER_BENCH_RSM runs its 64² RSM (the VPL count says so). KIND specular:
# BM_SpecularMethod, one row per method, PREFIX/METHOD: per round the median of its repetitions,
# and the median over the rounds of that ns per (pixel, lobe) and of its ratio to vsgl-asg's in the
# same round, and that ratio's range.
render_rows() {
  python3 - "$@" << 'PY'
import json, statistics, sys
kind, prefix, log = sys.argv[1:4]
text, decoder, reports, k = open(log).read(), json.JSONDecoder(), [], 0
while (k := text.find("{\n", k)) >= 0:  # each round's report, among the bench's other lines
    report, k = decoder.raw_decode(text, k)
    reports.append([b for b in report.get("benchmarks", []) if b.get("run_type", "iteration") == "iteration"])
def spread(v, digits):
    return f"{min(v):.{digits}f} … {max(v):.{digits}f}"
if kind == "vpl":
    runs = {}
    for report in reports:
        for b in report:
            precision = "float" if b["name"].endswith("float:1") else "double"
            runs.setdefault(precision, []).append(b)
    for precision in ("double", "float"):
        v = runs.get(precision)
        if not v:
            continue
        ns = [1e9 * b["ns_per_pixel_vpl"] for b in v]  # (the counter is in seconds per pair)
        note = f"{statistics.median(ns):.3f} ns per (pixel, VPL), median of {len(v)} rounds ({spread(ns, 3)}), {int(v[0].get('vpls', 0))} VPLs"
        if all(b.get("bound_ns_per_pixel_vpl") for b in v):
            ratios = [x / b["bound_ns_per_pixel_vpl"] for x, b in zip(ns, v)]
            note += (f"; arithmetic bound {statistics.median(b['bound_ns_per_pixel_vpl'] for b in v):.3f} ns, "
                     f"{statistics.median(ratios):.2f}× the bound (rounds: {spread(ratios, 2)})")
        else:
            note += "; arithmetic bound -"
        print(f"{prefix}/{precision}|||{note}")
else:
    ns, ratios, order = {}, {}, {}
    for report in reports:
        runs = {}
        for b in report:  # label "specular NAME (…)"; the counter is in seconds per pair
            runs.setdefault(b["label"].split()[1], []).append(1e9 * b["ns_per_pixel_lobe"])
            order.setdefault(b["label"].split()[1], b["name"])  # rows in the benchmark's order
        by = {method: statistics.median(v) for method, v in runs.items()}  # the round's median
        for method, x in by.items():
            ns.setdefault(method, []).append(x)
            if "vsgl-asg" in by:
                ratios.setdefault(method, []).append(x / by["vsgl-asg"])
    for method, v in sorted(ns.items(), key=lambda kv: order[kv[0]]):
        r = ratios.get(method, [])
        note = f"{statistics.median(v):.2f} ns per (pixel, lobe), median of {len(v)} rounds"
        if r:
            note += f"; {statistics.median(r):.2f} × vsgl-asg (built in) of the same round, median (rounds: {spread(r, 2)})"
        print(f"{prefix}/{method}|||{note}")
PY
}

# vpl_sum_rows PREFIX N: BM_Reference (the library's VPL sum) with an N² RSM
# (SGLAB_RENDER_BENCH_RSM), one repetition in each of --render-rounds processes (render_rows vpl).
vpl_sum_rows() {
  local prefix=$1 n=$2
  timed "$prefix-bench" "sglab_render_bench BM_Reference (the library's VPL sum, $n² RSM), $render_rounds rounds of one repetition" \
    rounds "$render_rounds" env SGLAB_RENDER_BENCH_RSM="$n" "$bench" --benchmark_filter='BM_Reference/peer:0' \
    --benchmark_repetitions=1 --benchmark_format=json
  while IFS= read -r row; do rows+=("$row"); done < <(render_rows vpl "$prefix" "$scratch/$prefix-bench.log")
}

if [ "$cold" = 1 ]; then
  build=$scratch/build
  export CCACHE_DISABLE=1
  launcher=()
  if [ "$tu_times" = 1 ]; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER="$(dirname "$self")/tu_time.sh")
    export SGLAB_TU_TIMES=$scratch/tu_times.txt
    : > "$SGLAB_TU_TIMES"
  fi
  generator=()  # as the checkout's setup.sh configures a new build directory
  grep -q -- '-G Ninja' scripts/setup.sh && generator=(-G Ninja)
  # The main job's vector kernel sets, as the checkout's setup.sh configures them (the widest set
  # alone where it says kernels=best); build-tests then reconfigures as setup.sh --tests does.
  kernels=()
  grep -q '^kernels=best' scripts/setup.sh && kernels=(-DSGLAB_SIMD_KERNELS=best)
  timed configure "scratch dir, Release, SGLAB_WERROR=ON${generator[*]:+, ${generator[*]}}${kernels[*]:+, ${kernels[*]#-D}}" \
    cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSGLAB_WERROR=ON "${kernels[@]}" "${launcher[@]}"
  timed build-sglab "sglab, cold, ccache off, -j$jobs" cmake --build "$build" -j"$jobs" --target sglab
  timed build-python "then sglab_python, cold, ccache off, -j$jobs" cmake --build "$build" -j"$jobs" --target sglab_python
  if [ "$tu_times" = 1 ]; then
    cp "$SGLAB_TU_TIMES" "$scratch/tu_times_main.txt"
    while read -r cpu wall out; do
      out=${out#"$build"/}  # a unity batch lies in the build directory
      rows+=("tu/${out#"$root"/}|$wall|$cpu|one translation unit of build-sglab or build-python")
    done < <(sort -rn "$scratch/tu_times_main.txt" | head -n 10)
    tu_total=$(awk '{ s += $1 } END { printf "%.2f", s }' "$scratch/tu_times_main.txt")
    rows+=("tu/all-of-build-sglab-and-python||$tu_total|$(wc -l < "$scratch/tu_times_main.txt") translation units, summed CPU")
  fi
  for f in "${touch_files[@]}"; do
    name=rebuild-touch
    ((${#touch_files[@]} == 1)) || name=rebuild-touch/$f
    touch "$f"
    timed "${name//\//_}" "after touching $f" cmake --build "$build" -j"$jobs" --target sglab sglab_python
    rows[${#rows[@]} - 1]="$name|${rows[${#rows[@]} - 1]#*|}"
  done
  if [ "$tests" = 1 ] && ((${#kernels[@]})); then
    timed build-tests "the rest of the tree (tests, benchmarks; reconfigured with SGLAB_SIMD_KERNELS=host, its narrower kernel sets included), cold, ccache off" \
      bash -c 'cmake -S . -B "$1" -DSGLAB_SIMD_KERNELS=host && cmake --build "$1" -j"$2"' build-tests "$build" "$jobs"
  elif [ "$tests" = 1 ]; then
    timed build-tests "the rest of the tree (tests, benchmarks), cold, ccache off" cmake --build "$build" -j"$jobs"
  elif [ "$render" = 1 ] || [ "$python" = 1 ]; then
    # Without the test build, the benchmarks that the Python and render rows run, and nothing else.
    timed build-benchmarks "sglab_core_bench and sglab_render_bench only (--skip-tests), cold, ccache off" \
      cmake --build "$build" -j"$jobs" --target sglab_core_bench sglab_render_bench
  fi
  unset CCACHE_DISABLE
else
  build=$root/build
fi
sglab=$build/bin/sglab
[ -x "$sglab" ] || sglab=$build/experiments/sglab  # where checkouts before 2026-12-03 put it
[ -x "$sglab" ] || { echo "perf_report: no sglab in $build (--skip-cold needs a built ./build: bash scripts/setup.sh --tests)" >&2; exit 2; }

if [ "$tests" = 1 ]; then
  # A failing test does not stop the report (a baseline may fail here for reasons of its own): the
  # note says how many passed.
  timed ctest "whole suite, -j2; CPU column: the tests' summed seconds" \
    bash -c 'ctest --test-dir "$1" -j2 || true' ctest "$build"
  passed=$(grep -E '% tests passed' "$scratch/ctest.log" || echo "no summary line")
  # ctest's own CPU figure is the children's; the tests' summed seconds say more on a shared machine.
  summed=$(awk '/Total Test time/ {next} / sec$/ && /Test +#/ {for (i = 1; i <= NF; i++) if ($i == "sec") s += $(i - 1)} END {printf "%.2f", s}' \
    "$scratch/ctest.log")
  last=${rows[-1]}
  rows[-1]="$(cut -d'|' -f1-2 <<< "$last")|$summed|$(cut -d'|' -f4 <<< "$last"): $passed"
fi
if [ "$quick" = 1 ] && [ "$quick_runs" = 1 ]; then
  timed reproduce-quick "sglab reproduce --quick, empty --out" "$sglab" reproduce --quick --out "$scratch/quick"
elif [ "$quick" = 1 ]; then
  runs=()  # "wall|cpu" of each run
  for ((k = 1; k <= quick_runs; k++)); do
    timed reproduce-quick "" "$sglab" reproduce --quick --out "$scratch/quick-$k"
    runs+=("$(cut -d'|' -f2-3 <<< "${rows[-1]}")")
    unset 'rows[-1]'
  done
  median() { sort -g | awk '{ v[NR] = $1 } END { printf "%s", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
  wall=$(printf '%s\n' "${runs[@]}" | cut -d'|' -f1 | median)
  cpu=$(printf '%s\n' "${runs[@]}" | cut -d'|' -f2 | median)
  each=$(printf '%s\n' "${runs[@]}" | awk -F'|' '{ printf "%s%s s (%s)", (NR > 1 ? ", " : ""), $1, $2 }')
  rows+=("reproduce-quick|$wall|$cpu|sglab reproduce --quick, empty --out; median of $quick_runs runs, wall (CPU): $each")
fi
if [ "$full" = 1 ]; then
  timed reproduce-full "sglab reproduce, empty --out and --tables-dir" \
    "$sglab" reproduce --out "$scratch/full" --tables-dir "$scratch/full/tables"
  # Its timed steps, which run alone: the part of its wall time no scheduling could hide (an
  # older checkout's reproduce_times.csv, under --baseline, has no such row).
  alone=$(awk -F, '$1 == "steps-run-alone" { print $3 "|" $4 }' "$scratch/full/reproduce_times.csv" 2>/dev/null)
  missing=""
  [ -n "$alone" ] || missing=": no such row in this checkout"
  rows+=("reproduce-full-alone|${alone:-|}|the timed steps of reproduce-full, run alone (its reproduce_times.csv)$missing")
fi
if [ "$python" = 1 ]; then
  bench=$build/benchmarks/sglab_core_bench
  if [ -x "$bench" ] && [ -d "$build/python/sglab" ]; then
    timed python-eval-bench "benchmarks/python_eval_bench.py, 1e6 points, one CPU" \
      env PYTHONPATH="$build/python" /usr/bin/python3 benchmarks/python_eval_bench.py --bench "$bench"
    # One row per method, precision and path (default: the scalar definition row by row;
    # vectorized: the batch evaluators): Python ns/point (CPU), the C++ batch's on its 4096 cached
    # points, how far above it Python is (the cost of the call from Python per point) and their
    # ratio, and the C++ batch at as many points as Python's (the same memory traffic and branches),
    # timed right after Python's calls in each of the bench's paired rounds (the difference: the
    # median over the rounds, and its range), read by column name (an older checkout's bench,
    # under --tree, prints fewer columns).
    while IFS= read -r row; do rows+=("$row"); done < <(python3 - "$scratch/python-eval-bench.log" << 'PY'
import re, sys
# Rows of benchmarks/python_eval_bench.py's table, by column name (older benches have fewer columns).
lines = [l.strip() for l in open(sys.argv[1]) if l.startswith("|")]
head = next((l for l in lines if l.startswith("| quantity |")), None)
if head is None:
    sys.exit(0)
names = [c.strip() for c in head.strip("|").split("|")]
def col(prefix, exclude=None):
    for k, n in enumerate(names):
        if n.startswith(prefix) and not (exclude and exclude in n):
            return k
    return None
py, cpp, over, ratio = col("Python ns/eval (CPU)"), col("C++ batch ns/eval (CPU"), col("overhead ns/eval"), col("ratio")
cpp_n = next((k for k, n in enumerate(names) if n.startswith("C++ batch ns/eval (CPU, ") and "4096" not in n), None)
over_n = col("overhead at ", exclude="range")
over_range = next((k for k, n in enumerate(names) if n.startswith("overhead at ") and "range" in n), None)
for l in lines:
    c = [x.strip() for x in l.strip("|").split("|")]
    if len(c) != len(names) or c[0] not in ("clamped-cosine", "sg-integral", "specular"):
        continue
    path = "vectorized" if c[3] == "yes" else "default"
    note = f"Python {c[py]} ns/point (CPU), C++ batch {c[cpp]}: {c[over]} ns/point above it, ratio {c[ratio]}"
    if cpp_n is not None and over_n is not None:
        m = re.search(r"\((?:CPU, )?(\d+) points\)", names[cpp_n])
        note += f"; C++ batch at {m.group(1) if m else 'as many'} points {c[cpp_n]}: {c[over_n]} above it"
        if over_range is not None:
            note += f" (paired rounds: {c[over_range]})"
    print(f"python-eval/{c[0]}/{c[1]}/{c[2]}/{path}|||{note}")
PY
    )
  else
    echo "perf_report: no $bench or $build/python: Python row skipped (build the benchmarks and sglab_python)" >&2
  fi
fi
if [ "$render" = 1 ]; then
  bench=$build/benchmarks/sglab_render_bench
  if [ -x "$bench" ]; then
    # Each round: 3 repetitions of every method of 0.2 s each, in random order (Google Benchmark's
    # random interleaving), so that a method and vsgl-asg are timed across the same seconds.
    timed render-bench "sglab_render_bench BM_SpecularMethod, $render_rounds rounds of 3 repetitions, interleaved" \
      rounds "$render_rounds" "$bench" --benchmark_filter='BM_SpecularMethod' --benchmark_repetitions=3 \
      --benchmark_enable_random_interleaving=true --benchmark_min_time=0.2 --benchmark_format=json
    while IFS= read -r row; do rows+=("$row"); done < <(render_rows specular render-specular "$scratch/render-bench.log")
    timed render-visibility-bench "sglab_render_bench BM_ShadingVisibility, BM_CubeShadowMaps, 5 repetitions" \
      "$bench" --benchmark_filter='BM_ShadingVisibility|BM_CubeShadowMaps' --benchmark_repetitions=5 \
      --benchmark_report_aggregates_only=true
    # One row per benchmark: the library's median and its ratio to the peer's (the old loop).
    while read -r name unit mine peer; do
      rows+=("$name|||$mine ns per $unit, median of 5; the old loop $peer ($(awk -v a="$peer" -v b="$mine" 'BEGIN { printf "%.2f", a / b }')× faster)")
    done < <(awk '/_median/ && /ns_per_(pixel_lobe|ray)=/ {
        for (i = 1; i <= NF; i++) if ($i ~ /^ns_per_(pixel_lobe|ray)=/) { v = $i; unit = v; sub(/=.*/, "", unit); sub(/^ns_per_/, "", unit); sub(/^[a-z_]*=/, "", v); sub(/ns$/, "", v) }
        name = $1; peer = name ~ /peer:1/; sub(/\/peer:.*/, "", name)
        row = name == "BM_CubeShadowMaps" ? "render-cube-shadow-maps" : "render-visibility"
        if (peer) old[row] = v; else { lib[row] = v; units[row] = unit == "ray" ? "ray" : "(pixel, lobe)" } }
      END { for (r in lib) print r, units[r] == "ray" ? "ray" : "pixel·lobe", lib[r], old[r] }' "$scratch/render-visibility-bench.log")
    # The VPL sum at the benchmark's 64² RSM (3 332 VPLs) and at the render sweeps' 128² (13 104,
    # whose arrays exceed a core's second-level cache: docs/testing.md).
    vpl_sum_rows render-vpl-sum 64
    vpl_sum_rows render-vpl-sum-rsm128 128
  else
    echo "perf_report: no $bench: render rows skipped (build the benchmarks)" >&2
  fi
fi

load_end=$(load)
mkdir -p "$(dirname "$csv")"
{
  echo "# Generated by \`${SGLAB_SIMD:+SGLAB_SIMD=$SGLAB_SIMD }bash benchmarks/perf_report.sh${args[*]:+ ${args[*]}}\` on $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) CPUs, load average $load_start at the start, $load_end at the end"
  echo "measure,wall_seconds,cpu_seconds,note"
  for r in "${rows[@]}"; do
    IFS='|' read -r name wall cpu note <<< "$r"
    printf '%s,%s,%s,"%s"\n' "$name" "$wall" "$cpu" "${note//\"/\"\"}"
  done
} > "$csv.tmp"
mv "$csv.tmp" "$csv"

printf '| %-48s | %9s | %9s | %s\n' measure "wall s" "CPU s" note
printf '|%s|%s|%s|%s\n' "$(printf -- '-%.0s' {1..50})" "-----------" "-----------" "------"
for r in "${rows[@]}"; do
  IFS='|' read -r name wall cpu note <<< "$r"
  printf '| %-48s | %9s | %9s | %s\n' "$name" "$wall" "$cpu" "$note"
done
echo "(CSV: $csv; load average $load_start → $load_end)"
