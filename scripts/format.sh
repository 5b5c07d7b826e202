#!/usr/bin/env bash
# Formats the tracked C++ files (*.cpp, *.hpp, *.h) with clang-format-14 and the root .clang-format.
#   bash scripts/format.sh           rewrite the files in place
#   bash scripts/format.sh --check   change nothing; list the files that would change, exit 1 if any
#   bash scripts/format.sh [--check] PATH…   only these files (tracked C++ files under PATH)
set -euo pipefail
cd "$(dirname "$0")/.."

check=0
if [[ "${1:-}" == --check ]]; then
  check=1
  shift
fi
for a in "$@"; do
  if [[ "$a" == -* ]]; then
    echo "format: unknown option '$a' (expected --check, then paths)" >&2
    exit 2
  fi
done
clang_format=${CLANG_FORMAT:-clang-format-14}
if ! command -v "$clang_format" >/dev/null; then
  echo "format: $clang_format not found (Debian package clang-format-14)" >&2
  exit 2
fi

mapfile -d '' files < <(git ls-files -z -- "${@:-.}" | grep -zE '\.(cpp|hpp|h)$' || true)
if ((${#files[@]} == 0)); then
  echo "format: no tracked C++ files under ${*:-.}" >&2
  exit 2
fi

if ((check)); then
  changed=()
  for f in "${files[@]}"; do
    "$clang_format" --style=file "$f" | cmp -s - "$f" || changed+=("$f")
  done
  if ((${#changed[@]})); then
    printf '%s\n' "${changed[@]}"
    echo "format: ${#changed[@]} of ${#files[@]} files would change (bash scripts/format.sh to apply)" >&2
    exit 1
  fi
  exit 0
fi
printf '%s\0' "${files[@]}" | xargs -0 -n 50 "$clang_format" --style=file -i
