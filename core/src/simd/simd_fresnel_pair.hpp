// The `specular` kernels of simd_specular.hpp at Fresnel f0 = 0 and f0 = 1 in one pass
// (sglab/simd_specular_pair.hpp). Every `specular` method depends on f0 only through Schlick's
// F = f0 + (1 − f0)(1 − ωo·h)⁵, which is linear in f0, so a caller shading many f0 values mixes the
// two results, v(f0) = v(0) + f0·(v(1) − v(0)) (the VSGL renderer, per pixel).
//
// A kernel's eval_f0(a, p, f0) takes f0 apart from its row: given the row's f0 (RowF0::eval, the
// batch evaluator) it is the kernel; given F0Pair{} it passes the scalar template (specular.hpp's
// `_at` forms, templates on the f0 type too) the pair (0, 1) as its f0. fresnel_schlick below,
// found by argument-dependent lookup, gives F at both, and every operation of the template
// downstream of it (products, quotients, selects: brdf.hpp fresnel_value_t) is done on both
// members, so each member is, bit for bit, the kernel at that f0 (the same operations in the same
// order; these units are compiled with -ffp-contract=off), while everything upstream of the Fresnel
// factor (the frame, sin/cos of the azimuth, the lobe products, every exp) is computed once.
// Included by simd_specular.hpp; internal linkage or templates only (see simd_kernels.hpp).
#pragma once

namespace sglab::simd_detail {
namespace {

// The two values of a quantity downstream of the Fresnel factor: V is Lanes of a batch inside the
// scalar templates (their value type for this f0), the batch itself in the drivers.
template <class V>
struct FresnelPair {
  V at_f0_zero, at_f0_one;
  FresnelPair() = default;
  FresnelPair(const V& zero, const V& one) : at_f0_zero(zero), at_f0_one(one) {}
  explicit FresnelPair(const V& both) : at_f0_zero(both), at_f0_one(both) {}  // a value without F (0)
};
template <class V>
inline FresnelPair<V> operator*(const FresnelPair<V>& x, const V& y) {
  return {x.at_f0_zero * y, x.at_f0_one * y};
}
template <class V>
inline FresnelPair<V> operator*(const V& x, const FresnelPair<V>& y) {
  return {x * y.at_f0_zero, x * y.at_f0_one};
}
template <class V>
inline FresnelPair<V> operator/(const FresnelPair<V>& x, const V& y) {
  return {x.at_f0_zero / y, x.at_f0_one / y};
}
// The f0 argument that asks for both values.
struct F0Pair {};

// ---- the pair on Lanes (the templates' f0) ------------------------------------------------------
// (Lanes: simd_drivers.hpp's alias of simd_lanes::Lanes.)
// brdf.hpp's Schlick F at f0 = 0 and 1 (the template itself, twice).
template <class B>
inline FresnelPair<Lanes<B>> fresnel_schlick(const FresnelPair<Lanes<B>>& f0, const Lanes<B>& cos_oh) {
  return {sglab::fresnel_schlick(f0.at_f0_zero, cos_oh), sglab::fresnel_schlick(f0.at_f0_one, cos_oh)};
}
// The templates' select (simd_lanes.hpp) joins a pair member by member.
template <class B>
inline FresnelPair<Lanes<B>> join(const simd_lanes::LaneMask<B>& cond, const FresnelPair<Lanes<B>>& a,
                                  const FresnelPair<Lanes<B>>& b) {
  return {Lanes<B>(xsimd::select(cond.m, a.at_f0_zero.v, b.at_f0_zero.v)),
          Lanes<B>(xsimd::select(cond.m, a.at_f0_one.v, b.at_f0_one.v))};
}
// The templates' f0 from a kernel's: the row's f0 column, or the pair (0, 1).
template <class B>
inline Lanes<B> lanes_f0(const B& f0) {
  return Lanes<B>(f0);
}
template <class B>
inline FresnelPair<Lanes<B>> lanes_f0(F0Pair) {
  using T = value_t<B>;
  return {Lanes<B>(T(0)), Lanes<B>(T(1))};
}
// And a template's value back as the kernel's.
template <class B>
inline B batch_of(const Lanes<B>& x) {
  return x.v;
}
template <class B>
inline FresnelPair<B> batch_of(const FresnelPair<Lanes<B>>& x) {
  return {x.at_f0_zero.v, x.at_f0_one.v};
}

// A `specular` kernel K's batch eval(a, p): K::eval_f0 with the row's own f0, a[5]. The pair
// driver (run_specular_pair, simd_specular.hpp) passes F0Pair{} and rows without f0: eval_f0 reads
// a[0 … 4] only.
template <class K>
struct RowF0 {
  template <class B>
  static B eval(const B* a, const B* p) {
    return K::eval_f0(a, p, a[5]);
  }
};

}  // namespace
}  // namespace sglab::simd_detail
