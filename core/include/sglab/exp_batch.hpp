// e^x over arrays, with std::exp's values bit for bit (docs/simd.md, "std::exp on lanes").
// Where the C library is glibc on a CPU with FMA and AVX2 (its __exp_fma), the values come from a
// vectorized copy of its algorithm (src/simd/simd_exp.hpp) on the active instruction set's
// registers (sglab/simd.hpp): 5.2× (AVX-512) and 3.4× (AVX2) as fast as a loop of std::exp on one
// machine (docs/simd.md). The copy is compared with std::exp at first use, on 4096 seeded points
// across exp's ranges and its edge values; if a single value differs (another C library, another exp), or the
// instruction set is sse2, exp_batch is that loop.
// Either way a caller's results do not depend on which path ran.
#pragma once

#include <cstddef>

namespace sglab {

// out[i] = std::exp(x[i]) for i < n. `out` may be `x`.
void exp_batch(const double* x, double* out, std::size_t n);

// Whether exp_batch runs the vectorized copy on the active instruction set (false: the scalar loop).
bool exp_batch_vectorized();

}  // namespace sglab
