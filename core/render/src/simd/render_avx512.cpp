// The renderer's loops of render_kernels.hpp for avx512 (compiled with the flags core/render/CMakeLists.txt
// gives this file). Run only when sglab::simd::active_isa() names it (render_dispatch.cpp).
#include "render_kernels.hpp"

namespace sglab::render::simd_detail {

const RenderKernelTable& render_kernels_avx512() {
  static const RenderKernelTable table = make_render_table("avx512");
  return table;
}

}  // namespace sglab::render::simd_detail
