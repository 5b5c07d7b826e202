// The `specular` kernels of simd_specular.hpp at Fresnel f0 = 0 and f0 = 1 in one pass
// (sglab/simd_specular_pair.hpp). Every `specular` method depends on f0 only through Schlick's
// F = f0 + (1 − f0)(1 − ωo·h)⁵, which is linear in f0, so a caller shading many f0 values mixes the
// two results, v(f0) = v(0) + f0·(v(1) − v(0)) (the VSGL renderer, per pixel).
//
// A kernel's eval_f0(a, p, f0) takes f0 apart from its row: given the row's f0 (RowF0::eval, the
// batch evaluator) it is the kernel; given F0Pair{} its Fresnel factor is the pair
// (F(0), F(1)) and every operation downstream of it (products, quotients, selects) is done on both
// members, so each member is, bit for bit, the kernel at that f0 (the same operations in the same
// order; these units are compiled with -ffp-contract=off), while everything upstream of the Fresnel
// factor (the frame, sin/cos of the azimuth, the lobe products, every exp) is computed once.
// Included by simd_specular.hpp; internal linkage or templates only (see simd_kernels.hpp).
#pragma once

namespace sglab::simd_detail {
namespace {

// The two values of a quantity downstream of the Fresnel factor.
template <class B>
struct FresnelPair {
  B at_f0_zero, at_f0_one;
};
template <class B>
inline FresnelPair<B> operator*(const FresnelPair<B>& x, const B& y) {
  return {x.at_f0_zero * y, x.at_f0_one * y};
}
template <class B>
inline FresnelPair<B> operator*(const B& x, const FresnelPair<B>& y) {
  return {x * y.at_f0_zero, x * y.at_f0_one};
}
template <class B>
inline FresnelPair<B> operator/(const FresnelPair<B>& x, const B& y) {
  return {x.at_f0_zero / y, x.at_f0_one / y};
}
// xsimd::select for the kernels' values, a FresnelPair or a batch.
template <class M, class B>
inline B select_f(const M& m, const B& a, const B& b) {
  return xsimd::select(m, a, b);
}
template <class M, class B>
inline FresnelPair<B> select_f(const M& m, const FresnelPair<B>& a, const B& b) {
  return {xsimd::select(m, a.at_f0_zero, b), xsimd::select(m, a.at_f0_one, b)};
}
template <class M, class B>
inline FresnelPair<B> select_f(const M& m, const B& a, const FresnelPair<B>& b) {
  return {xsimd::select(m, a, b.at_f0_zero), xsimd::select(m, a, b.at_f0_one)};
}

// The f0 argument that asks for both values.
struct F0Pair {};
template <class B>
inline B fresnel_schlick(const B& f0, const B& cos_oh);  // simd_specular.hpp
template <class B>
inline FresnelPair<B> fresnel_schlick(F0Pair, const B& cos_oh) {
  using T = value_t<B>;
  return {fresnel_schlick(B(T(0)), cos_oh), fresnel_schlick(B(T(1)), cos_oh)};
}

// A `specular` kernel K's batch eval(a, p): K::eval_f0 with the row's own f0, a[5]. The pair
// driver (run_specular_pair, simd_kernels.hpp) passes F0Pair{} and rows without f0: eval_f0 reads
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
