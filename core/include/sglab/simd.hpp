// Run-time choice of the instruction set of the vectorized batch evaluators (docs/simd.md).
// The diffuse methods' registry batch evaluators (batch_float, batch_double, and those of their
// bound versions) run xsimd kernels compiled once per instruction set (those the building machine
// runs, only the widest of them, or all three: SGLAB_SIMD_KERNELS, core/CMakeLists.txt); the widest
// one compiled that the CPU supports is selected at first use. The environment variable SGLAB_SIMD (sse2, avx2, avx512)
// or force_isa() selects a narrower one, so every compiled path can be checked on one machine.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sglab::simd {

enum class Isa { sse2, avx2, avx512 };

std::string_view isa_name(Isa isa);
std::optional<Isa> parse_isa(std::string_view name);
// Whether this binary has kernels for `isa` and this CPU (and OS) can run them.
bool isa_supported(Isa isa);
// Every compiled instruction set this CPU can run, narrowest first.
std::vector<Isa> supported_isas();
// The instruction set the batch evaluators use now (the widest supported one, or SGLAB_SIMD's).
// Throws std::invalid_argument naming the value when SGLAB_SIMD is not a known name or names an
// instruction set this CPU cannot run or this build has no kernels for, and std::runtime_error when
// this CPU runs none of the build's sets (SGLAB_SIMD_KERNELS=best on a wider machine).
Isa active_isa();
// Use `isa` from now on (for tests and benchmarks). Throws std::invalid_argument if unsupported.
void force_isa(Isa isa);

// The (quantity, method) pairs whose batch evaluators are vectorized, as "quantity/method" (their
// registry entries have Method::batch_path == BatchPath::vectorized).
const std::vector<std::string>& vectorized_methods();

// Calls of a vectorized batch evaluator made on this thread so far: a test calls a method's batch
// evaluator and sees whether a kernel ran.
std::uint64_t vectorized_batch_calls();

}  // namespace sglab::simd
