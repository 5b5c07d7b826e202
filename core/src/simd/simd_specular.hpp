// Vectorized batch evaluators of the `specular` methods (GGX, core/include/sglab/specular.hpp and
// specular_sglab.hpp; docs/simd.md) and their pair drivers. Compiled once per instruction set in a
// unit of its own (simd_specular_isa.hpp, included by simd_specular_sse2.cpp, …), apart from the
// diffuse kernels (simd_kernels.hpp) and the `specular-gaussian-ndf` ones (simd_gaussian_ndf.hpp),
// so that an edit of one kind's method header recompiles only its kernels.
//
// Every kernel IS the method's scalar template instantiated on Lanes (simd_lanes.hpp; its Eigen
// 3-vectors Vec3<Lanes>): the template's `_at` form on the frame's vectors (specular_view,
// specular_light_axis), with the row's f0 or the pair f0 = 0 and 1 (simd_fresnel_pair.hpp), or,
// for the renderer's columns, its two parts, `_receiver` and `specular_from` (the light's axis as
// the columns give it). There is no second copy of a formula. Of the
// constants registry_simd.cpp passes, only specular/sglab's fitted six (p[2…7]) are read: the
// floors (p[0], p[1]), sglab's roughness ceiling and exponent cap (p[8], p[9]) and sg-warp-meder's
// Meder constants are the templates' own, from their single definitions.
// Everything here has internal linkage or is a template (see simd_kernels.hpp).
#pragma once

#include <cstddef>
#include <iterator>
#include <limits>
#include <tuple>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "sglab/specular.hpp"
#include "sglab/specular_sglab.hpp"
#include "simd_specular_drivers.hpp"
#include "simd_fresnel_pair.hpp"

namespace sglab::simd_detail {
namespace {

// A row's scalar-template arguments on lanes: roughness, light sharpness, ξ and ωo.
template <class B>
struct LaneRow {
  Lanes<B> roughness, light_sharpness;
  Vec3<Lanes<B>> xi, wo;
};
template <class B>
inline LaneRow<B> lane_row(const B* a) {
  return {a[0], a[1], sglab::specular_light_axis(Lanes<B>(a[2]), Lanes<B>(a[4])), sglab::specular_view(Lanes<B>(a[3]))};
}
// A light's columns in the receiver driver (run_specular_pair_receivers, below): light
// sharpness, light_cos, axis_t, axis_b; its axis ξ = (axis_t, axis_b, light_cos clamped to [−1, 1])
// (sglab/simd_specular_pair.hpp SpecularPairColumns).
template <class B>
inline Vec3<Lanes<B>> light_axis(const B* light) {
  return Vec3<Lanes<B>>(Lanes<B>(light[2]), Lanes<B>(light[3]), sglab::clamp_cosine(Lanes<B>(light[1])));
}

// A `specular` kernel of a method in two parts (specular.hpp): eval_f0 is its `_at` form
// (specular_parts_at), and for the receiver driver the same two parts apart: receiver(roughness,
// view_cos), computed once per receiver, and eval_light(receiver, light, p, f0) per light
// (specular_from); the same operations as eval_f0, so the same values. Method names the receiver
// part (`receiver<T>()`, a callable on (roughness, ωo)) and the method's own options
// (`from_options()`, a tuple of specular_from's arguments after f0).
template <class Method>
struct SpecParts : RowF0<SpecParts<Method>> {
  template <class A, class B, class F0>
  static auto eval_f0(const A& a, const B* /*p*/, const F0& f0) {
    const LaneRow<B> r = lane_row(a);
    return std::apply(
        [&](const auto&... options) {
          return batch_of(sglab::specular_parts_at(Method::template receiver<Lanes<B>>(), r.roughness,
                                                   r.light_sharpness, r.xi, r.wo, lanes_f0<B>(f0), options...));
        },
        Method::from_options());
  }
  template <class B>
  static auto receiver(const B& roughness, const B& view_cos) {
    return Method::template receiver<Lanes<B>>()(Lanes<B>(roughness), sglab::specular_view(Lanes<B>(view_cos)));
  }
  template <class R, class B, class F0>
  static auto eval_light(const R& r, const B* light, const B* /*p*/, const F0& f0) {
    return std::apply(
        [&](const auto&... options) {
          return batch_of(sglab::specular_from(r, Lanes<B>(light[0]), light_axis(light), lanes_f0<B>(f0), options...));
        },
        Method::from_options());
  }
};
// sg-warp(…, form, tokuyoshi_harada_sharpness, factor_at).
template <bool kIwasaki, bool kTokuyoshiHarada, bool kProductAxis>
struct SgWarpMethod {
  template <class T>
  static SgWarpReceiverOf<T> receiver() {
    return {kTokuyoshiHarada, kProductAxis ? FactorAt::product_axis : FactorAt::lobe_axis};
  }
  static auto from_options() {
    return std::tuple(kIwasaki ? SgProductForm::iwasaki : SgProductForm::exact,
                      kProductAxis ? FactorAt::product_axis : FactorAt::lobe_axis);
  }
};
template <bool kIwasaki, bool kTokuyoshiHarada, bool kProductAxis>
using SpecSgWarp = SpecParts<SgWarpMethod<kIwasaki, kTokuyoshiHarada, kProductAxis>>;
// asg and sg-warp-dvn: specular_from without options.
struct NoOptions {
  static std::tuple<> from_options() { return {}; }
};
struct AsgMethod : NoOptions {
  template <class T>
  static auto receiver() {
    return sglab::specular_asg_receiver<T>;
  }
};
struct SgWarpDvnMethod : NoOptions {
  template <class T>
  static auto receiver() {
    return sglab::specular_sg_warp_dvn_receiver<T>;
  }
};
using SpecAsg = SpecParts<AsgMethod>;
using SpecSgWarpDvn = SpecParts<SgWarpDvnMethod>;

// specular_sglab_with; p[2…7] = nu_slope, inflation, light_weight, light_floor, horizon_depth,
// horizon_rate (bound like the diffuse methods' constants).
// Its receiver part is the row's roughness and ωo alone (specular_sglab_with is not split).
template <class B>
struct RoughnessAndView {
  Lanes<B> roughness;
  Vec3<Lanes<B>> wo;
};
struct SpecSglab : RowF0<SpecSglab> {
  template <class A, class B, class F0>
  static auto eval_f0(const A& a, const B* p, const F0& f0) {
    const LaneRow<B> r = lane_row(a);
    const SglabSpecularParams<Lanes<B>> q{p[2], p[3], p[4], p[5], p[6], p[7]};
    return batch_of(sglab::specular_sglab_with(r.roughness, r.light_sharpness, r.xi, r.wo, lanes_f0<B>(f0), q));
  }
  template <class B>
  static RoughnessAndView<B> receiver(const B& roughness, const B& view_cos) {
    return {Lanes<B>(roughness), sglab::specular_view(Lanes<B>(view_cos))};
  }
  template <class B, class F0>
  static auto eval_light(const RoughnessAndView<B>& r, const B* light, const B* p, const F0& f0) {
    const SglabSpecularParams<Lanes<B>> q{p[2], p[3], p[4], p[5], p[6], p[7]};
    return batch_of(
        sglab::specular_sglab_with(r.roughness, Lanes<B>(light[0]), light_axis(light), r.wo, lanes_f0<B>(f0), q));
  }
};

}  // namespace
}  // namespace sglab::simd_detail

// specular_sglab.hpp's two functions with a vectorized form, found by argument-dependent lookup
// from the template on Lanes (more specialized than the templates).
namespace sglab::simd_lanes {
namespace {
// sglab_inverse_scale: 2^{1−⌊log2 s⌋} for a positive normal s, 0 for s = ∞, as +∞'s exponent field
// minus s's (no division).
template <class B>
inline Lanes<B> sglab_inverse_scale(const Lanes<B>& s) {
  using T = typename B::value_type;
  using BI = xsimd::batch<std::conditional_t<sizeof(T) == 8, std::int64_t, std::int32_t>, typename B::arch_type>;
  const BI field = xsimd::bitwise_cast<BI>(B(std::numeric_limits<T>::infinity()));
  return {xsimd::bitwise_cast<B>(BI(field - (xsimd::bitwise_cast<BI>(s.v) & field)))};
}
// exp_keeping_subnormals: libmvec's exp without its flush of subnormal results (simd_math.hpp).
template <class B>
inline Lanes<B> exp_keeping_subnormals(const Lanes<B>& x) {
  return {simd_detail::vm_exp_subnormal(x.v)};
}
}  // namespace
}  // namespace sglab::simd_lanes

namespace sglab::simd_detail {
namespace {

// The pair driver (simd_fresnel_pair.hpp): rows of the first kSpecularPairArity columns (no f0),
// the same padding; K::eval_f0 with F0Pair. Flattened: the kernel's helpers inlined (measured:
// their calls, with batches passed through memory, cost a few per cent of the pass).
template <class Arch, class T, class K>
__attribute__((flatten)) void run_specular_pair(const T* args, T* at_f0_zero, T* at_f0_one, std::size_t n,
                                                const T* params) {
  using B = xsimd::batch<T, Arch>;
  constexpr T kPad[kSpecularPairArity] = {T(0.5), T(1), T(0.5), T(0.5), T(0)};
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for_each_specular_batch<B>(args, n, kPad, [&](const B* a, std::size_t i, std::size_t rest) {
    const FresnelPair<B> r = K::eval_f0(a, p, F0Pair{});
    store_lanes(r.at_f0_zero, at_f0_zero + i, rest);
    store_lanes(r.at_f0_one, at_f0_one + i, rest);
  });
}
// The receiver pair driver (sglab/simd_specular_pair.hpp SpecularPairColumns): the receivers'
// columns (roughness, view_cos; one value per receiver) and the lights' (light_sharpness, light_cos,
// and the axis' tangent components axis_t, axis_b; row j·receivers + g is light j at receiver g),
// loaded as they are (no transposition; a partial last batch of receivers from padded copies,
// padding (0.5, 0.5) and (1, 0.5, √3/2, 0)). Each batch of receivers is set up once (K::receiver:
// the template's `_receiver` part) and evaluated against every light (K::eval_light with F0Pair:
// its `_from` part); no sine, cosine or square root of the azimuth is evaluated.
template <class Arch, class K>
__attribute__((flatten)) void run_specular_pair_receivers(const double* const* receivers, const double* const* lights,
                                                          std::size_t receiver_count, std::size_t light_count,
                                                          double* at_f0_zero, double* at_f0_one, const double* params) {
  using T = double;
  using B = xsimd::batch<T, Arch>;
  constexpr std::size_t W = B::size;
  constexpr T kReceiverPad[kSpecularReceiverColumns] = {T(0.5), T(0.5)};
  constexpr T kLightPad[kSpecularLightColumns] = {T(1), T(0.5), T(0.86602540378443865), T(0)};
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for (std::size_t g = 0; g < receiver_count; g += W) {
    const std::size_t rest = receiver_count - g < W ? receiver_count - g : W;
    B rc[kSpecularReceiverColumns];
    load_columns<B>(receivers, g, rest, kReceiverPad, rc);
    const auto r = K::receiver(rc[0], rc[1]);
    for (std::size_t l = 0; l < light_count; ++l) {
      const std::size_t i = l * receiver_count + g;
      B a[kSpecularLightColumns];
      load_columns<B>(lights, i, rest, kLightPad, a);
      const FresnelPair<B> v = K::eval_light(r, a, p, F0Pair{});
      store_lanes(v.at_f0_zero, at_f0_zero + i, rest);
      store_lanes(v.at_f0_one, at_f0_one + i, rest);
    }
  }
}

// The `specular` kernels with a pair driver (simd_fresnel_pair.hpp), in the order of Kernel from
// spec_sg_warp to spec_sglab: one list for the kernels, their column drivers and both pair drivers.
template <class... K>
struct KernelTypes {};
using SpecularPairKernels =
    KernelTypes<SpecSgWarp<false, false, false>, SpecSgWarp<false, false, true>, SpecSgWarp<true, false, false>,
                SpecSgWarp<false, true, false>, SpecAsg, SpecSgWarpDvn, SpecSglab>;

template <class Arch, class Pairs = SpecularPairKernels>
struct SpecularDrivers;
template <class Arch, class... K>
struct SpecularDrivers<Arch, KernelTypes<K...>> {
  // The `specular` kernels in the order of Kernel (spec_sg_warp … spec_sglab).
  template <class T>
  static constexpr KernelFn<T> kernels[] = {&run_specular<Arch, T, K>...};
  // Their column drivers, in the same order.
  template <class T>
  static constexpr ColumnsKernelFn<T> columns[] = {specular_columns<Arch, T, K>...};
  static constexpr SpecularPairFn pairs[] = {&run_specular_pair<Arch, double, K>...};
  static constexpr SpecularPairColumnsFn pair_columns[] = {&run_specular_pair_receivers<Arch, K>...};
};

template <class Arch>
SpecularPairTable make_pair_table() {
  using D = SpecularDrivers<Arch>;
  static_assert(std::size(D::pairs) == kSpecularPairKernels, "one pair driver per `specular` kernel");
  static_assert(std::size(D::pair_columns) == kSpecularPairKernels, "one column driver per `specular` kernel");
  SpecularPairTable t{};
  for (int i = 0; i < kSpecularPairKernels; ++i) {
    t.d[i] = D::pairs[i];
    t.columns[i] = D::pair_columns[i];
  }
  return t;
}

// The `specular` entries of a table (Kernel spec_sg_warp … spec_sglab), which make_table
// (simd_kernels.hpp) leaves empty.
template <class Arch>
void add_specular_kernels(KernelTable& t) {
  using D = SpecularDrivers<Arch>;
  static_assert(std::size(D::template kernels<double>) == kSpecularPairKernels, "one driver per specular kernel");
  for (int i = 0; i < kSpecularPairKernels; ++i) {
    t.f[kDiffuseKernels + i] = D::template kernels<float>[i];
    t.d[kDiffuseKernels + i] = D::template kernels<double>[i];
    t.columns_f[kDiffuseKernels + i] = D::template columns<float>[i];
    t.columns_d[kDiffuseKernels + i] = D::template columns<double>[i];
  }
}

}  // namespace
}  // namespace sglab::simd_detail
