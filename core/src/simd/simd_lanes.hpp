// The scalar type that turns a method's template into its vectorized batch evaluator (docs/simd.md):
// Lanes<B> is an xsimd batch B (every lane one row) that the scalar templates of core/include/sglab
// instantiate on as they do on float, double, ceres::Jet, mp50 and Trace. One formula, written once:
//   - arithmetic is the batch's, lane by lane, in the template's order;
//   - the template's unqualified exp, expm1, erf, erfc, log1p, sin, cos, sqrt, abs find, by
//     argument-dependent lookup, the functions below: glibc libmvec's (simd_math.hpp vm_*, with its
//     saturations) and the hardware square root;
//   - value_of(x) is x itself (as for Trace), so a comparison gives a LaneMask, and the template's
//     select(cond, if_true, if_false) (scalar.hpp) resolves to the select below: each side runs only
//     when some lane takes it (a branch only extreme inputs take costs a test of the mask), and
//     when lanes disagree both run and xsimd::select joins them lane by lane;
//   - a series summed until its term falls below ε (series_converged) sums until every lane's has.
// An `if` on a value (not a select) does not compile: LaneMask has no conversion to bool.
//
// Everything here is in an unnamed namespace: the templates instantiated on Lanes in the
// per-instruction-set units (simd_sse2.cpp, simd_avx2.cpp, simd_avx512.cpp) have internal linkage,
// so the linker cannot merge AVX-512 code into code that runs on a smaller CPU (simd_kernels.hpp).
// The namespace holds only these functions: argument-dependent lookup on a Lanes finds nothing
// else that could compete with the scalar templates' own helpers.
#pragma once

#include <array>
#include <cstddef>
#include <type_traits>

#include <Eigen/Core>
#include <xsimd/xsimd.hpp>

#include "sglab/eigen_scalar.hpp"
#include "sglab/scalar.hpp"
#include "simd_math.hpp"

namespace sglab::simd_lanes {
namespace {

template <class B>
struct LaneMask {
  typename B::batch_bool_type m;
};

template <class B>
struct Lanes {
  using batch_type = B;
  using value_type = typename B::value_type;
  B v;

  Lanes() : v(value_type(0)) {}
  Lanes(const B& b) : v(b) {}  // NOLINT: implicit, as a float converts to a Jet
  template <class A, std::enable_if_t<std::is_arithmetic_v<A> && !std::is_same_v<A, bool>, int> = 0>
  Lanes(A a) : v(static_cast<value_type>(a)) {}  // NOLINT: a literal broadcast to every lane

  Lanes& operator+=(const Lanes& o) { return v = v + o.v, *this; }
  Lanes& operator-=(const Lanes& o) { return v = v - o.v, *this; }
  Lanes& operator*=(const Lanes& o) { return v = v * o.v, *this; }
  Lanes& operator/=(const Lanes& o) { return v = v / o.v, *this; }
};

template <class X>
struct is_lanes : std::false_type {};
template <class B>
struct is_lanes<Lanes<B>> : std::true_type {};

// Both operands as Lanes<B>: a Lanes, or a number broadcast to every lane.
template <class B>
inline const B& lanes_of(const Lanes<B>& x) {
  return x.v;
}
template <class B, class A, std::enable_if_t<std::is_arithmetic_v<A>, int> = 0>
inline B lanes_of(const A& a) {
  return B(static_cast<typename B::value_type>(a));
}
// (No `type` for any other pair, e.g. a Lanes and an Eigen vector of Lanes: the operators below
// then drop out of overload resolution and Eigen's own apply.)
template <class X, class Y, class = void>
struct common_lanes {};
template <class B>
struct common_lanes<Lanes<B>, Lanes<B>, void> {
  using type = B;
};
template <class B, class A>
struct common_lanes<Lanes<B>, A, std::enable_if_t<std::is_arithmetic_v<A>>> {
  using type = B;
};
template <class B, class A>
struct common_lanes<A, Lanes<B>, std::enable_if_t<std::is_arithmetic_v<A>>> {
  using type = B;
};
template <class X, class Y>
using common_lanes_t = typename common_lanes<X, Y>::type;

template <class B>
inline Lanes<B> operator-(const Lanes<B>& a) {
  return {-a.v};
}
template <class B>
inline Lanes<B> operator+(const Lanes<B>& a) {
  return a;
}
#define SGLAB_LANES_BINARY(op, R, wrap)                       \
  template <class X, class Y, class B = common_lanes_t<X, Y>> \
  inline R operator op(const X& a, const Y& b) {              \
    return wrap(lanes_of<B>(a) op lanes_of<B>(b));            \
  }
#define SGLAB_LANES_VALUE(x) \
  Lanes<B> { x }
#define SGLAB_LANES_MASK(x) \
  LaneMask<B> { x }
SGLAB_LANES_BINARY(+, Lanes<B>, SGLAB_LANES_VALUE)
SGLAB_LANES_BINARY(-, Lanes<B>, SGLAB_LANES_VALUE)
SGLAB_LANES_BINARY(*, Lanes<B>, SGLAB_LANES_VALUE)
SGLAB_LANES_BINARY(/, Lanes<B>, SGLAB_LANES_VALUE)
SGLAB_LANES_BINARY(<, LaneMask<B>, SGLAB_LANES_MASK)
SGLAB_LANES_BINARY(<=, LaneMask<B>, SGLAB_LANES_MASK)
SGLAB_LANES_BINARY(>, LaneMask<B>, SGLAB_LANES_MASK)
SGLAB_LANES_BINARY(>=, LaneMask<B>, SGLAB_LANES_MASK)
#undef SGLAB_LANES_BINARY
#undef SGLAB_LANES_VALUE
#undef SGLAB_LANES_MASK

template <class B>
inline LaneMask<B> operator!(const LaneMask<B>& a) {
  return {~a.m};
}
template <class B>
inline LaneMask<B> operator&&(const LaneMask<B>& a, const LaneMask<B>& b) {
  return {a.m && b.m};
}
template <class B>
inline LaneMask<B> operator||(const LaneMask<B>& a, const LaneMask<B>& b) {
  return {a.m || b.m};
}

// ---- lane-wise math (found by argument-dependent lookup from the templates' unqualified calls)
#define SGLAB_LANES_UNARY(fn, batch_fn)   \
  template <class B>                      \
  inline Lanes<B> fn(const Lanes<B>& x) { \
    return {batch_fn(x.v)};               \
  }
SGLAB_LANES_UNARY(exp, simd_detail::vm_exp)
SGLAB_LANES_UNARY(expm1, simd_detail::vm_expm1)
SGLAB_LANES_UNARY(erf, simd_detail::vm_erf)
SGLAB_LANES_UNARY(erfc, simd_detail::vm_erfc)
SGLAB_LANES_UNARY(log1p, simd_detail::vm_log1p)
SGLAB_LANES_UNARY(sin, simd_detail::vm_sin)
SGLAB_LANES_UNARY(cos, simd_detail::vm_cos)
// The hardware instruction: correctly rounded, as std::sqrt.
SGLAB_LANES_UNARY(sqrt, xsimd::sqrt)
SGLAB_LANES_UNARY(abs, xsimd::abs)
#undef SGLAB_LANES_UNARY
// std::max and std::min's values (the first argument when neither is larger), lane by lane: the
// templates' `using std::max; max(a, b)` finds these (more specialized than std::max, which would
// need a bool from a lane mask).
template <class B>
inline Lanes<B> max(const Lanes<B>& a, const Lanes<B>& b) {
  return {xsimd::select(a.v < b.v, b.v, a.v)};
}
template <class B>
inline Lanes<B> min(const Lanes<B>& a, const Lanes<B>& b) {
  return {xsimd::select(b.v < a.v, b.v, a.v)};
}

// ---- selects (scalar.hpp select on a lane mask) ---------------------------------------------
template <class B, class R>
inline R join(const LaneMask<B>& cond, const R& a, const R& b) {
  if constexpr (is_lanes<R>::value) {
    return {xsimd::select(cond.m, a.v, b.v)};
  } else {  // a std::array of Lanes (sglab_steepness, sglab_bounds_over_2pi) or an Eigen vector of
            // them (Vec3<Lanes>): element by element
    R out;
    for (decltype(out.size()) i = 0; i < out.size(); ++i) out[i] = join(cond, a[i], b[i]);
    return out;
  }
}

template <class B, class F, class G>
inline auto select(const LaneMask<B>& cond, F&& if_true, G&& if_false) -> decltype(if_true()) {
  using R = decltype(if_true());
  if (xsimd::all(cond.m)) return if_true();
  if (xsimd::none(cond.m)) return if_false();
  const R a = if_true();
  const R b = if_false();
  return join(cond, a, b);
}

// scalar.hpp's choose of two values already computed: a blend (join), no test of the mask.
template <class B, class R>
inline R choose(const LaneMask<B>& cond, const R& a, const R& b) {
  return join(cond, a, b);
}

// The clamps of scalar.hpp, which every formula applies to its inputs, as plain blends: their
// sides are values already computed, so testing the mask first (select above) costs more than it
// saves. The same values as scalar.hpp's selects.
template <class B>
inline Lanes<B> clamp(const Lanes<B>& x, const Lanes<B>& lo, const Lanes<B>& hi) {
  return {xsimd::select(x.v < lo.v, lo.v, xsimd::select(x.v > hi.v, hi.v, x.v))};
}
template <class B>
inline Lanes<B> clamp_cosine(const Lanes<B>& c) {
  using T = typename B::value_type;
  return clamp(c, Lanes<B>(T(-1)), Lanes<B>(T(1)));
}
template <class B>
inline Lanes<B> positive_part(const Lanes<B>& x) {
  using T = typename B::value_type;
  return {xsimd::select(x.v > B(T(0)), x.v, B(T(0)))};
}

// A series summed until its term no longer changes the sum stops when that holds in every lane (a
// lane that converged earlier adds terms below ε of its sum).
template <class B>
inline bool series_converged(const Lanes<B>& term, const Lanes<B>& sum, int /*terms*/) {
  using T = typename B::value_type;
  return xsimd::all(xsimd::abs(term.v) <= B(epsilon<T>()) * xsimd::abs(sum.v));
}

}  // namespace
}  // namespace sglab::simd_lanes

// Eigen vectors of lanes (Vec3<Lanes>: the specular methods' axes and directions), as trace.hpp's of
// Trace: plain scalar arithmetic at the costs of the lanes' number type (eigen_scalar.hpp).
namespace Eigen {
template <class B>
struct NumTraits<sglab::simd_lanes::Lanes<B>>
    : sglab::ScalarNumTraits<sglab::simd_lanes::Lanes<B>, typename B::value_type> {};
namespace internal {
// A 3-vector's sum (dot products, squared norms) in the order the scalar templates' double
// instantiation has: Eigen adds the first two terms as one SSE2 packet of two doubles, then the
// third, (a0 + a1) + a2 (measured on this build). Without packets (float: no packet of 3; Lanes)
// Eigen splits the sum in halves, a0 + (a1 + a2), which is float's order already.
template <class B, class Evaluator>
requires(sizeof(typename B::value_type) ==
         8) struct redux_novec_unroller<scalar_sum_op<sglab::simd_lanes::Lanes<B>, sglab::simd_lanes::Lanes<B>>,
                                        Evaluator, 0, 3> {
  using Scalar = sglab::simd_lanes::Lanes<B>;
  static EIGEN_STRONG_INLINE Scalar run(const Evaluator& eval, const scalar_sum_op<Scalar, Scalar>& func) {
    constexpr int n = Evaluator::InnerSizeAtCompileTime;
    const auto at = [&](int k) { return eval.coeffByOuterInner(k / n, k % n); };
    return func(func(at(0), at(1)), at(2));
  }
};
}  // namespace internal
}  // namespace Eigen

namespace sglab {
// value_of(x) of Lanes is x itself (a comparison then gives a LaneMask, as Trace's gives a TraceBool);
// its number type is the lanes' float or double.
template <class B>
struct scalar_traits<simd_lanes::Lanes<B>> {
  using value_type = typename B::value_type;
  static const simd_lanes::Lanes<B>& value(const simd_lanes::Lanes<B>& x) { return x; }
};
}  // namespace sglab
