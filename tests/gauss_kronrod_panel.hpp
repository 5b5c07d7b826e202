// ∫_a^b f by Boost's adaptive Gauss–Kronrod rule with the panel mapped onto [−1, 1], for the tests'
// own quadratures. Boost's adaptive rule (gauss_kronrod<Real, N>::integrate) compares its error
// estimate of the rule on [−1, 1], not scaled to the panel, with the tolerance times the panel's
// integral, which is scaled: on a panel of half-width h the test is h times too strict, so a narrow
// panel never meets it and is bisected down to the depth limit (2^depth panels of N points, no digit
// gained). Mapped onto [−1, 1], the two are on the same scale.
#pragma once

#include <boost/math/quadrature/gauss_kronrod.hpp>

namespace sglab::test {

template <unsigned N, class Real, class F>
Real gauss_kronrod_panel(const F& f, const Real& a, const Real& b, unsigned max_depth, const Real& tolerance) {
  const Real mid = (a + b) / 2, half = (b - a) / 2;
  return boost::math::quadrature::gauss_kronrod<Real, N>::integrate(
      [&](const Real& x) -> Real { return f(mid + half * x) * half; }, Real(-1), Real(1), max_depth, tolerance);
}

}  // namespace sglab::test
