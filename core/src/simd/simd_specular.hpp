// Vectorized batch evaluators of the specular methods (docs/simd.md): quantity `specular` (GGX,
// core/include/sglab/specular.hpp) and `specular-gaussian-ndf` (gaussian_ndf.hpp). Included by
// simd_kernels.hpp, after the diffuse kernels, and compiled with it once per instruction set.
//
// Every kernel IS the method's scalar template instantiated on Lanes (simd_lanes.hpp; its Eigen
// 3-vectors Vec3<Lanes>): the template's `_at` form on the frame's vectors (specular_view,
// specular_light_axis), with the row's f0 or the pair f0 = 0 and 1 (simd_fresnel_pair.hpp), or,
// for the renderer's columns, its two parts, `_receiver` and `specular_from` (the light's axis by
// specular_light_axis_cs). There is no second copy of a formula. Of the
// constants registry_simd.cpp passes, only specular/sglab's fitted six (p[2…7]) are read: the
// floors (p[0], p[1]), sglab's roughness ceiling and exponent cap (p[8], p[9]) and sg-warp-meder's
// Meder constants are the templates' own, from their single definitions.
// Everything here has internal linkage or is a template (see simd_kernels.hpp).
#pragma once

#include <tuple>

#include "sglab/gaussian_ndf.hpp"
#include "sglab/specular.hpp"
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
// A light's columns in the receiver driver (simd_kernels.hpp run_specular_pair_receivers): light
// sharpness, light_cos, cos φ, sin φ; its axis ξ as specular_light_axis_cs forms it.
template <class B>
inline Vec3<Lanes<B>> light_axis(const B* light) {
  return sglab::specular_light_axis_cs(Lanes<B>(light[1]), Lanes<B>(light[2]), Lanes<B>(light[3]));
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

// The `specular-gaussian-ndf` kernels: the templates on the row itself.
template <class B>
inline SpecularInput<Lanes<B>> lane_input(const B* a) {
  return {a[0], a[1], a[2], a[3], a[4], a[5]};
}
struct GndfSgWarp {
  template <class B>
  static B eval(const B* a, const B* /*p*/) {
    return sglab::specular_gaussian_ndf_sg_warp(lane_input(a)).v;
  }
};
struct GndfSgWarpMeder {
  template <class B>
  static B eval(const B* a, const B* /*p*/) {
    return sglab::specular_gaussian_ndf_sg_meder(lane_input(a)).v;
  }
};

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
