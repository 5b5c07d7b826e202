#!/usr/bin/env bash
# Installs the Debian 12 packages sglab needs (only those missing), then configures ./build
# (Release) and builds what the job needs. Run as root on a fresh machine; safe to re-run.
#   bash scripts/setup.sh          the `sglab` binary and the Python module (build/python)
#   bash scripts/setup.sh --tests  everything: sglab, the test executables CTest runs, benchmarks
set -euo pipefail
cd "$(dirname "$0")/.."

targets=(--target sglab sglab_python)
case "${1:-}" in
  "") ;;
  --tests) targets=() ;;
  *) echo "setup: unknown option '$1' (expected nothing or --tests)" >&2; exit 2 ;;
esac

packages=(
  build-essential cmake pkg-config
  libceres-dev libeigen3-dev libboost-dev libboost-math-dev
  libopenexr-dev libfmt-dev libgtest-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libtbb-dev libxsimd-dev
  python3 python3-matplotlib python3-numpy python3-scipy
  python3-dev pybind11-dev python3-pybind11 python3-pytest
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >&2
cmake --build build -j"$jobs" "${targets[@]}" >&2
