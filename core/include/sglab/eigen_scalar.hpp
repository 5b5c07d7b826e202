// Eigen's traits of a number type R whose arithmetic is that of one value of type V, done by R
// itself (Trace, whose values are floats; simd Lanes<B>, lane by lane in B's value type): as Ceres
// does for its Jets, Eigen does plain scalar arithmetic on R (no packets of R) at V's costs, so it
// unrolls a 3-vector's dot product and norm in the same order for R as for V.
#pragma once

#include <limits>

#include <Eigen/Core>

namespace sglab {

template <class R, class V>
struct ScalarNumTraits : Eigen::GenericNumTraits<V> {
  using Real = R;
  using NonInteger = R;
  using Nested = R;
  using Literal = R;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = Eigen::NumTraits<V>::ReadCost,
    AddCost = Eigen::NumTraits<V>::AddCost,
    MulCost = Eigen::NumTraits<V>::MulCost
  };
  static inline Real epsilon() { return Real(std::numeric_limits<V>::epsilon()); }
  static inline Real dummy_precision() { return Real(Eigen::NumTraits<V>::dummy_precision()); }
  static inline Real highest() { return Real(std::numeric_limits<V>::max()); }
  static inline Real lowest() { return Real(std::numeric_limits<V>::lowest()); }
  static inline int digits10() { return Eigen::NumTraits<V>::digits10(); }
};

}  // namespace sglab
