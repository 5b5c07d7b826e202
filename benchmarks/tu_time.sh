#!/usr/bin/env bash
# A compiler launcher (CMAKE_CXX_COMPILER_LAUNCHER) that times each translation unit: runs the
# compiler command as given and appends "CPU_SECONDS WALL_SECONDS SOURCE" (CPU = user + system; the
# source is the word after -c) to the file $SGLAB_TU_TIMES. Used by benchmarks/perf_report.sh --tu-times.
# Also a linker launcher (CMAKE_CXX_LINKER_LAUNCHER): a command without -c is recorded as "link:OUTPUT"
# (the word after -o).
out=
target=
prev=
for a in "$@"; do
  [ "$prev" = -c ] && out=$a
  [ "$prev" = -o ] && target=$a
  prev=$a
done
[ -z "$out" ] && out=link:$target
TIMEFORMAT='%U %S %R'
exec 3>&2
t=$({ time "$@" 2>&3; } 2>&1)
status=${PIPESTATUS[0]}
read -r user sys wall <<< "$(tail -n 1 <<< "$t")"
# Compilers print nothing to standard output here; anything before the timing line is passed on.
[ "$(wc -l <<< "$t")" -gt 1 ] && head -n -1 <<< "$t"
awk -v u="$user" -v s="$sys" -v w="$wall" -v o="$out" 'BEGIN { printf "%.2f %.2f %s\n", u + s, w, o }' >> "${SGLAB_TU_TIMES:?}"
exit "$status"
