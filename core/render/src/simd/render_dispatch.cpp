// The renderer's kernel table: the one of the instruction set the whole program uses
// (sglab/simd.hpp active_isa(), which also reads SGLAB_SIMD and is what force_isa changes).
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "render_table.hpp"
#include "sglab/render/visibility.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/sg.hpp"
#include "sglab/simd.hpp"
#include "sglab/vsgl.hpp"

namespace sglab::render {
namespace simd_detail {

static_assert(kPi == std::numbers::pi);
static_assert(kCap == kMaxPositionalSharpness);
static_assert(kProductScale == kProductScaleSharpness);
static_assert(kRayLift == kVplRayLift && kRayReach == kVplRayReach);

double scaled_by_exp_direct_limit() {
  static const double limit = std::log(std::numeric_limits<double>::max()) / 2;
  return limit;
}

const RenderKernelTable& render_kernels() {
  switch (const simd::Isa isa = simd::active_isa()) {
#if SGLAB_KERNELS_SSE2
    case simd::Isa::sse2: return render_kernels_sse2();
#endif
#if SGLAB_KERNELS_AVX2
    case simd::Isa::avx2: return render_kernels_avx2();
#endif
#if SGLAB_KERNELS_AVX512
    case simd::Isa::avx512: return render_kernels_avx512();
#endif
    default:  // not built (SGLAB_SIMD_KERNELS): active_isa never names it
      throw std::logic_error("sglab: no " + std::string(simd::isa_name(isa)) + " render kernels in this build");
  }
}

}  // namespace simd_detail

std::string_view kernel_isa() { return simd_detail::render_kernels().isa; }

}  // namespace sglab::render
