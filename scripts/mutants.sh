#!/usr/bin/env bash
# Mutation check: applies each small, plausible edit ("mutant") of scripts/mutants/list.sh to a
# scratch copy of this checkout, one at a time, rebuilds only the tests that own the edited code,
# runs them, and reports whether they failed (killed) or passed (survived), as a Markdown table.
#
#   scripts/mutants.sh                 # every mutant
#   scripts/mutants.sh hill-c0 csv-*   # the named ones (shell patterns)
#   scripts/mutants.sh --list          # the list, without running anything
#   scripts/mutants.sh --check         # that every edit still matches the code (seconds; no build)
#   scripts/mutants.sh --no-baseline … # skip the unmutated run of the owning tests (a rerun)
#
# The scratch copy is a detached git worktree of HEAD plus the checkout's uncommitted changes to
# tracked files, in $SGLAB_MUTANTS_DIR/src (default /tmp/sglab-mutants-$USER); its build directory
# (src/build) is kept between runs, so a second run rebuilds incrementally (ccache is used when it is installed).
# The report goes to stdout and to $SGLAB_MUTANTS_DIR/report.md; the exit status is 1 when a
# mutant survived, 2 when a mutant could not be applied, built, or the unmutated tests fail.
# Environment: SGLAB_MUTANTS_JOBS (build jobs, default 2), SGLAB_MUTANTS_TIMEOUT (seconds per
# test command, default 600), SGLAB_MUTANTS_MEMORY_KB (address space per test command, default
# 6 GiB: a mutant that loops appending fails there, not in the machine's OOM killer). Run it niced
# on a shared machine: `nice -n 10 scripts/mutants.sh`.
set -uo pipefail
# The whole script is one compound command, read before it runs: editing this file or the list
# while a run is in progress (it takes an hour) cannot change or break that run.
{

src=$(cd "$(dirname "$0")/.." && pwd)
work=${SGLAB_MUTANTS_DIR:-/tmp/sglab-mutants-${USER:-$(id -un)}}
jobs=${SGLAB_MUTANTS_JOBS:-2}
timeout_s=${SGLAB_MUTANTS_TIMEOUT:-600}
memory_kb=${SGLAB_MUTANTS_MEMORY_KB:-6291456}  # a mutant that loops allocating stops at 6 GiB
scratch=$work/src
build=$scratch/build  # inside the copy, as in a checkout: the compiler cache sees the same relative paths
log=$work/log

# ---- the list ------------------------------------------------------------------------------------
# mutant ID FILE SED-SCRIPT TEST...: TEST is a test executable of tests/ (`name` or
# `name:gtest-filter`) or `ctest:REGEX` (a CTest test, e.g. the Python module's pytest run, whose
# executables are listed with `build:TARGET`).
ids=() files=() seds=() tests=()
mutant() {
  ids+=("$1") files+=("$2") seds+=("$3")
  shift 3
  tests+=("$*")
}
# shellcheck source=mutants/list.sh
. "$src/scripts/mutants/list.sh"

selected=()
baseline=1
if [[ ${1:-} == --no-baseline ]]; then baseline=0; shift; fi
if [[ ${1:-} == --list ]]; then
  for i in "${!ids[@]}"; do printf '%-28s %-48s %s\n' "${ids[i]}" "${files[i]}" "${tests[i]}"; done
  exit 0
fi
if [[ ${1:-} == --check ]]; then  # each edit against this checkout's files, without building
  stale=0
  for i in "${!ids[@]}"; do
    n=$(sed -e "${seds[i]}" "$src/${files[i]}" | diff "$src/${files[i]}" - | grep -c '^>')
    if ((n == 0)); then
      echo "mutants.sh: ${ids[i]} matches nothing in ${files[i]}" >&2
      stale=1
    fi
  done
  ((stale)) && exit 2
  echo "mutants.sh: all ${#ids[@]} edits apply" >&2
  exit 0
fi
if (($# == 0)); then
  selected=("${!ids[@]}")
else  # in the order of the patterns, each mutant once
  for pattern in "$@"; do
    for i in "${!ids[@]}"; do
      # shellcheck disable=SC2053
      if [[ ${ids[i]} == $pattern && " ${selected[*]} " != *" $i "* ]]; then selected+=("$i"); fi
    done
  done
fi
((${#selected[@]})) || { echo "mutants.sh: no mutant matches: $*" >&2; exit 2; }

# ---- the scratch copy ----------------------------------------------------------------------------
mkdir -p "$work" "$log"
head=$(git -C "$src" rev-parse HEAD) || exit 2
if [[ ! -d $scratch/.git && ! -f $scratch/.git ]]; then
  git -C "$src" worktree add --detach "$scratch" "$head" >/dev/null || exit 2
fi
git -C "$scratch" checkout -q --detach --force "$head" && git -C "$scratch" clean -qfd || exit 2
git -C "$src" diff HEAD --binary >"$work/uncommitted.diff"
if [[ -s $work/uncommitted.diff ]]; then
  git -C "$scratch" apply --whitespace=nowarn "$work/uncommitted.diff" || { echo "mutants.sh: cannot apply the uncommitted changes" >&2; exit 2; }
fi
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
cmake -S "$scratch" -B "$build" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >"$log/configure.txt" 2>&1 ||
  { echo "mutants.sh: configure failed, see $log/configure.txt" >&2; exit 2; }

# The build targets and test commands of one mutant's TEST list.
targets_of() {
  local t out=()
  for t in $1; do
    case $t in
      ctest:*) ;;
      build:*) out+=("${t#build:}") ;;
      *) out+=("${t%%:*}") ;;
    esac
  done
  printf '%s\n' "${out[@]}" | sort -u
}
# Runs the owning tests; status 0 when all pass. Output in $2. Called as ( run_tests … ).
run_tests() {
  local t status=0
  : >"$2"
  ulimit -v "$memory_kb"  # run_tests runs in a subshell (below): the limit stays there
  for t in $1; do
    case $t in
      build:*) continue ;;
      ctest:*)
        timeout "$timeout_s" ctest --test-dir "$build" -R "${t#ctest:}" --output-on-failure --stop-on-failure >>"$2" 2>&1 || status=1 ;;
      *:*)
        timeout "$timeout_s" "$build/tests/${t%%:*}" --gtest_brief=1 --gtest_fail_fast --gtest_filter="${t#*:}" >>"$2" 2>&1 || status=1 ;;
      *)
        timeout "$timeout_s" "$build/tests/$t" --gtest_brief=1 --gtest_fail_fast >>"$2" 2>&1 || status=1 ;;
    esac
    ((status == 0)) || break
  done
  return $status
}
# The first failed test named in a test log.
first_failure() {
  local name
  name=$(grep -m1 -oE '\[  FAILED  \] [A-Za-z0-9_/.]+|[0-9]+ - [A-Za-z0-9_.]+ \(Failed\)|Timeout|FAILED [^ ]+' "$1" | head -1)
  echo "${name:-the test command failed}" | sed -E 's/^\[  FAILED  \] //; s/^[0-9]+ - //; s/ \(Failed\)//'
}

# ---- baseline: the owning tests pass unmutated -------------------------------------------------
all_tests=$(for i in "${selected[@]}"; do printf '%s\n' ${tests[i]}; done | sort -u | tr '\n' ' ')
mapfile -t all_targets < <(targets_of "$all_tests")
echo "mutants.sh: building ${#all_targets[@]} test targets in $build" >&2
cmake --build "$build" -j"$jobs" --target "${all_targets[@]}" >"$log/baseline-build.txt" 2>&1 ||
  { echo "mutants.sh: the unmutated build failed, see $log/baseline-build.txt" >&2; exit 2; }
echo "mutants.sh: unmutated owning tests" >&2
((baseline == 0)) || (run_tests "$all_tests" "$log/baseline-tests.txt") ||
  { echo "mutants.sh: the owning tests fail without a mutant ($(first_failure "$log/baseline-tests.txt")), see $log/baseline-tests.txt" >&2; exit 2; }

# ---- each mutant ---------------------------------------------------------------------------------
report=$work/report.md
{
  echo "| mutant | file | edit | result | caught by | seconds |"
  echo "|---|---|---|---|---|---|"
} >"$report"
killed=0 survived=0 broken=0
start_all=$SECONDS
for i in "${selected[@]}"; do
  id=${ids[i]} file=${files[i]} edit=${seds[i]}
  target=$scratch/$file
  start=$SECONDS
  cp "$target" "$work/original"
  sed -i -e "$edit" "$target"
  changed=$(diff "$work/original" "$target" | grep -c '^>')
  result="" by=""
  if [[ $changed -eq 0 ]]; then
    result="not applied" by="the edit matched nothing"
  else
    mapfile -t targets < <(targets_of "${tests[i]}")
    if ! cmake --build "$build" -j"$jobs" --target "${targets[@]}" >"$log/$id-build.txt" 2>&1; then
      result="build error" by="see log/$id-build.txt"
    elif (run_tests "${tests[i]}" "$log/$id-tests.txt"); then
      result="**survived**" by="${tests[i]}"
    else
      result="killed" by=$(first_failure "$log/$id-tests.txt")
    fi
  fi
  # Restore the original (a fresh mtime: the next build recompiles it, from the cache).
  cat "$work/original" >"$target"
  case $result in
    killed) ((killed++)) ;;
    "**survived**") ((survived++)) ;;
    *) ((broken++)) ;;
  esac
  shown_edit=$(printf '%s' "$edit" | sed 's/|/\\|/g; s/`/'"'"'/g')
  printf '| %s | %s | `%s` | %s | %s | %d |\n' "$id" "$file" "$shown_edit" "$result" "$by" $((SECONDS - start)) >>"$report"
  printf 'mutants.sh: %-28s %-12s %4ds  %s\n' "$id" "$result" $((SECONDS - start)) "$by" >&2
done
# Leave the build matching the unmutated sources.
cmake --build "$build" -j"$jobs" --target "${all_targets[@]}" >"$log/final-build.txt" 2>&1
total=$((killed + survived))
{
  echo
  printf '%d mutants: %d killed, %d survived, %d not applied or not built; kill ratio %s; %d min.\n' \
    "${#selected[@]}" "$killed" "$survived" "$broken" \
    "$( ((total)) && awk -v k="$killed" -v t="$total" 'BEGIN { printf "%.1f %%", 100 * k / t }' || echo n/a)" \
    $(((SECONDS - start_all + 59) / 60))
  echo "Commit $(git -C "$src" rev-parse --short "$head")$([[ -s $work/uncommitted.diff ]] && echo ' + uncommitted changes')."
} >>"$report"
cat "$report"
((broken)) && exit 2
((survived)) && exit 1
exit 0
}
