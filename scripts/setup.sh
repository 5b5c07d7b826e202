#!/usr/bin/env bash
# Installs the Debian 12 packages sglab needs (only those missing), then configures ./build
# (Release) and builds what the job needs. Run as root on a fresh machine; safe to re-run.
#   bash scripts/setup.sh          the `sglab` binary: what the main job (`sglab reproduce`) needs
#   bash scripts/setup.sh --python the `sglab` binary and the Python module (build/python)
#   bash scripts/setup.sh --tests  everything: sglab, the Python module, the test executables CTest
#                                  runs, benchmarks (and slurm-wlm + munge for the suite's Slurm round trip)
#   bash scripts/setup.sh --fuzz   also clang: the libFuzzer targets in ./build-fuzz (docs/testing.md)
set -euo pipefail
cd "$(dirname "$0")/.."

targets=(--target sglab)
# The vector kernels (core/CMakeLists.txt): the main job runs only the widest set this CPU runs, so
# it builds only that one; the suite compares every set this CPU runs, so --tests builds them all.
kernels=best
fuzz=0
tests=0
case "${1:-}" in
  "") ;;
  --python) targets=(--target sglab sglab_python) ;;
  --tests) targets=(); tests=1; kernels=host ;;
  --fuzz) fuzz=1 ;;
  *) echo "setup: unknown option '$1' (expected nothing, --python, --tests or --fuzz)" >&2; exit 2 ;;
esac

packages=(
  build-essential cmake pkg-config
  lld  # the linker CMakeLists.txt prefers (SGLAB_LLD): a quarter of GNU ld's time per link
  ninja-build  # the build tool: starts a target's units before the libraries they link are linked
  libceres-dev libgoogle-glog-dev libeigen3-dev libboost-dev libboost-math-dev
  libopenexr-dev libfmt-dev libgtest-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libtbb-dev libxsimd-dev
  python3 python3-matplotlib python3-numpy python3-scipy
  python3-dev pybind11-dev python3-pybind11 python3-pytest python3-pyflakes
  # `sglab export` and `sglab shader-export` (a reproduce step): glslang and SPIRV-Tools (libraries,
  # linked in), the Vulkan loader to build against, and Mesa's lavapipe to run compute shaders
  # without a GPU. glslang-tools only because Debian 12's glslang-dev CMake package checks that the
  # glslangValidator program it lists exists (find_package(glslang) fails without it); sglab never runs it.
  glslang-dev glslang-tools spirv-tools libvulkan-dev mesa-vulkan-drivers
)
if ((fuzz)); then packages+=(clang-14 libclang-rt-14-dev); fi
# The Slurm round trip of the suite (tests/slurm_test.sh) starts its own munged, slurmctld and slurmd.
if ((tests)); then packages+=(slurm-wlm munge); fi
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
if ((fuzz)); then
  CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DSGLAB_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >&2
  cmake --build build-fuzz -j"$jobs" --target fuzz_csv fuzz_scene fuzz_manifest fuzz_exr fuzz_mixture >&2
  exit 0
fi
# Warnings are errors here (GCC 12 on Debian 12 builds warning-free), so a change that adds one fails
# CI; a plain `cmake` build leaves SGLAB_WERROR off. Both modes pass it, so --tests after the first
# command reuses the objects.
# Ninja for a new build directory (an existing one keeps the generator it was made with: CMake refuses
# another). Its scheduler keeps both cores busy where make's target-by-target order leaves one idle
# (docs/testing.md, "Build time").
generator=()
[ -f build/CMakeCache.txt ] || generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSGLAB_WERROR=ON -DSGLAB_SIMD_KERNELS="$kernels" >&2
cmake --build build -j"$jobs" "${targets[@]}" >&2
