// The stiff cases of docs/math.md §10 that are not formulas of their own, as quantities: the
// product of (nearly) opposite SG lobes of equal sharpness (sg.hpp), degenerate VPL sets (a single
// point, a patch far from the origin) and the shading point on top of a VSGL (vsgl.hpp). Each
// column carries the values the stability atlas sweeps (Column::stiff_values).
#include <algorithm>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>

#include "sglab/registry_mp50.hpp"
#include "sglab/sg.hpp"
#include "sglab/stiff_cases.hpp"
#include "sglab/vsgl.hpp"

namespace sglab {
namespace {

using DomainFn = std::function<std::optional<std::string>(std::span<const double>)>;

// ξ1 = (0, 0, 1) and ξ2 at angle δ from −ξ1.
template <class T>
std::pair<Vec3<T>, Vec3<T>> opposite_axes(const T& delta) {
  using std::cos;
  using std::sin;
  return {Vec3<T>(T(0), T(0), T(1)), Vec3<T>(T(sin(delta)), T(0), T(-cos(delta)))};
}

// The product of two SGs of equal sharpness λ on (nearly) opposite axes, by the definition in
// 50 digits: v = λξ1 + λξ2, λ3 = ‖v‖, L = λ3 − 2λ (the cancellation costs ≤ 8 of 50 digits at
// λ = 1e8), ∫ = e^L·2π(1 − e^{−2λ3})/λ3 (4π e^L at λ3 = 0). Independent of sg.hpp's stable forms.
mp50 opposite_integral_definition(const mp50& lambda, const mp50& delta) {
  const auto [x1, x2] = opposite_axes<mp50>(delta);
  const Vec3<mp50> v = lambda * x1 + lambda * x2;
  const mp50 l3 = sqrt(v.squaredNorm());
  const mp50 L = l3 - 2 * lambda;
  if (l3 == 0) return 2 * two_pi<mp50>() * exp(L);
  return two_pi<mp50>() * exp(L) * (-expm1(-2 * l3)) / l3;
}

// The sharpness and the opposite-axis angle δ of the two opposite-lobe quantities.
std::vector<Column> opposite_columns() {
  const std::vector<double> deltas{0.0, 1e-12, 1e-8, 1e-6, 1e-4, 1e-2, 0.1, 1.0};
  return {{"sharpness", ColumnKind::sharpness, "λ1 = λ2 = λ", stiff::sharpnesses(2), stiff::sharpnesses(1)},
          {"delta", ColumnKind::angle, "angle of ξ2 from −ξ1 (radians); 0 = exactly opposite", deltas, {}}};
}

Quantity opposite_integral() {
  Quantity q{"sg-product-opposite",
             "∫ G(ω; ξ1, λ) G(ω; ξ2, λ) dω with ξ2 at angle δ from −ξ1 (docs/math.md §1, §10: product sharpness → 0)",
             opposite_columns(),
             "definition",
             {}};
  q.methods.push_back(make_method("definition",
                                  "v = λξ1 + λξ2, λ3 = ‖v‖, e^{λ3−2λ}·A(λ3), in 50 digits (no stable-form rewriting)",
                                  "", false, nullptr, [](auto a) {
                                    using T = typename decltype(a)::value_type;
                                    return T(opposite_integral_definition(mp50(a[0]), mp50(a[1])));
                                  }));
  q.methods.push_back(make_method(
      "sg_product", "sg.hpp sg_product(ξ1, λ, ξ2, λ): e^{L}·A(λ3) from the vector form; NaN if the axis is not finite",
      "", false, nullptr, [](auto a) {
        using T = typename decltype(a)::value_type;
        using std::exp;
        using std::isfinite;
        const auto [x1, x2] = opposite_axes<T>(a[1]);
        const SgProduct<T> p = sg_product(x1, a[0], x2, a[0]);
        for (int k = 0; k < 3; ++k)
          if (!isfinite(p.axis(k))) return T(std::numeric_limits<double>::quiet_NaN());
        return T(exp(p.log_amplitude) * sg_integral(p.sharpness));
      }));
  q.methods.push_back(make_method("product_integral_exact",
                                  "sg.hpp product_integral_exact(λ, λ, ξ1·ξ2), the scalar stable form", "", false,
                                  nullptr, [](auto a) {
                                    using T = typename decltype(a)::value_type;
                                    const auto [x1, x2] = opposite_axes<T>(a[1]);
                                    return product_integral_exact(a[0], a[0], T(x1.dot(x2)));
                                  }));
  q.methods.push_back(make_method(
      "iwasaki", "sg.hpp product_integral_iwasaki(λ, λ, ξ1·ξ2) (Iwasaki et al. 2012)", "", false,
      [](std::span<const double> a) -> std::optional<std::string> {
        if (a[0] > 0) return std::nullopt;
        return std::string("undefined at λ1 + λ2 = 0");
      },
      [](auto a) {
        using T = typename decltype(a)::value_type;
        const auto [x1, x2] = opposite_axes<T>(a[1]);
        return product_integral_iwasaki(a[0], a[0], T(x1.dot(x2)));
      }));
  return q;
}

Quantity opposite_value() {
  Quantity q{"sg-product-opposite-value",
             "G(ξ1; ξ1, λ)·G(ξ1; ξ2, λ) = e^{−λ(1 + cos δ)} through the product SG e^{L}G(ξ1; ξ3, λ3) (uses its axis)",
             opposite_columns(),
             "definition",
             {}};
  q.methods.push_back(
      make_method("definition", "e^{λ(ξ1·ξ2 − 1)} = e^{−λ(1 + cos δ)} in 50 digits", "", false, nullptr, [](auto a) {
        using T = typename decltype(a)::value_type;
        const mp50 l(a[0]), d(a[1]);
        return T(exp(-l * (1 + cos(d))));
      }));
  q.methods.push_back(
      make_method("sg_product", "sg.hpp sg_product: e^{L}·sg_eval(ξ1, ξ3, λ3)", "", false, nullptr, [](auto a) {
        using T = typename decltype(a)::value_type;
        using std::exp;
        const auto [x1, x2] = opposite_axes<T>(a[1]);
        const SgProduct<T> p = sg_product(x1, a[0], x2, a[0]);
        return T(exp(p.log_amplitude) * sg_eval(x1, p.axis, p.sharpness));
      }));
  return q;
}

// Nine VPLs on a 3 × 3 grid of spacing h in a plane at distance D from the origin:
// y_ij = D·(0.6, 0.8, 0) + h·(i·(0, 0, 1) + j·(−0.8, 0.6, 0)), i, j ∈ {−1, 0, 1}, unit weights.
// σ² = E‖y − μ‖² = 4h²/3 exactly (each in-plane axis has variance 2h²/3); h = 0 is a single point
// (nine coincident VPLs, σ² = 0). `origin_at_first` selects the reference point o of the sums:
// 0 (the papers' E‖y‖² − ‖μ‖²) or the first VPL (vsgl.hpp's remedy).
template <class T>
T patch_variance(const T& distance, const T& spacing, bool origin_at_first) {
  const Vec3<T> centre = distance * Vec3<T>(T(0.6), T(0.8), T(0));
  const Vec3<T> e1(T(0), T(0), T(1)), e2(T(-0.8), T(0.6), T(0));
  VsglPositionSums<T> sums;
  Vec3<T> origin = Vec3<T>::Zero();
  bool first = true;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) {
      const Vec3<T> y = centre + spacing * (T(i) * e1 + T(j) * e2);
      if (first && origin_at_first) origin = y;
      first = false;
      add_position(sums, T(1), y, origin);
    }
  return vsgl_position(sums, origin).variance;
}

Quantity vsgl_variance() {
  Quantity q{
      "vsgl-variance",
      "σ_v² of nine VPLs on a 3×3 patch of spacing h at distance D from the origin (vsgl.hpp; docs/math.md §7, §10); "
      "the exact variance is 4h²/3 (0 for a single point), so a relative error where it is 0 means any non-zero σ²",
      {{"distance",
        ColumnKind::nonnegative,
        "D, the patch's distance from the origin",
        {0.0, 1.0, 1e2, 1e4, 1e6, 1e8},
        {}},
       {"spacing",
        ColumnKind::nonnegative,
        "h, the grid spacing (0: a single point)",
        {0.0, 1e-6, 1e-3, 1.0, 1e3},
        {}}},
      "exact",
      {}};
  q.methods.push_back(make_method("exact", "4h²/3 (closed form)", "", false, nullptr, [](auto a) {
    using T = typename decltype(a)::value_type;
    return T(4) * a[1] * a[1] / T(3);
  }));
  q.methods.push_back(make_method("origin-zero", "sums relative to o = 0: σ² = E‖y‖² − ‖E y‖² (the papers' form)", "",
                                  false, nullptr, [](auto a) { return patch_variance(a[0], a[1], false); }));
  q.methods.push_back(make_method("origin-first-vpl", "sums relative to o = the first VPL (vsgl.hpp's reference point)",
                                  "", false, nullptr, [](auto a) { return patch_variance(a[0], a[1], true); }));
  return q;
}

// Diffuse shading from one VSGL whose positional mean μ is `distance` from the shading point:
// μ = (1, 2, 3), y_p = μ − distance·u, u = (0.6, 0, 0.8); lobe axis ξ_v = −u, λ_v = 10; normal
// (0, 0, 1); the clamped-cosine integral by `d`. Returns ∫ L_in⟨ω·n⟩dω / c_v (vsgl.hpp).
template <class T, class D>
T on_top_shading(const T& distance, const T& variance, const D& d) {
  const Vec3<T> u(T(0.6), T(0), T(0.8));
  const Vec3<T> mean(T(1), T(2), T(3));
  const Vec3<T> yp = mean - distance * u;
  const VsglPositionalSg<T> pos = vsgl_positional_sg(mean, variance, yp);
  const VsglIncomingSg<T> in = vsgl_incoming_sg(pos, Vec3<T>(-u), T(10));
  return vsgl_clamped_cosine(in, Vec3<T>(T(0), T(0), T(1)), d);
}

// One method of vsgl-on-top per clamped-cosine method `cc` (the diffuse integral of the pipeline).
// The reference pipeline is a yardstick computed in double: its float is the double rounded, as
// for the registry's quadrature references.
Method on_top_method(const Method& cc, bool is_reference) {
  const auto m = std::make_shared<const Method>(cc);
  DomainFn domain = nullptr;
  if (cc.domain_error) {
    // The method's own domain check at the (λ_in, c) it would be called with.
    domain = [m](std::span<const double> a) -> std::optional<std::string> {
      std::optional<std::string> why;
      on_top_shading(a[0], a[1], [&](double l, double c) {
        const double in[2] = {l, c};
        if (!why) why = m->domain_error(in);
        return 0.0;
      });
      return why;
    };
  }
  auto shade = [m](const auto& distance, const auto& variance) {
    using T = std::decay_t<decltype(distance)>;
    return on_top_shading(distance, variance, [&m](const T& l, const T& c) {
      const T in[2] = {l, c};
      return eval_as<T>(*m, std::span<const T>(in));
    });
  };
  return make_method(cc.name, "vsgl.hpp vsgl_clamped_cosine with clamped-cosine/" + cc.name, "", cc.may_be_negative,
                     domain, [shade, is_reference](auto a) {
                       using T = typename decltype(a)::value_type;
                       if constexpr (std::is_same_v<T, float>)
                         if (is_reference) return float(shade(double(a[0]), double(a[1])));
                       return T(shade(a[0], a[1]));
                     });
}

Quantity vsgl_on_top(const Quantity& clamped_cosine) {
  Quantity q{"vsgl-on-top",
             "∫ L_in⟨ω·n⟩ dω / c_v of one VSGL (λ_v = 10) at a shading point `distance` from μ_v, σ_v² = variance "
             "(vsgl.hpp Eq. 7; docs/math.md §10: λ_σ → 0, ξ_μ undefined on top of μ_v; σ² = 0 a point light). Float "
             "positions (μ = (1, 2, 3)) cannot resolve distances below ~1e-7, so float sees the shading point on top "
             "of μ_v there",
             {{"distance", ColumnKind::nonnegative, "‖μ_v − y_p‖", {0.0, 1e-12, 1e-8, 1e-4, 1.0, 1e4}, {}},
              {"variance", ColumnKind::nonnegative, "σ_v²", {0.0, 1e-12, 1e-6, 1.0, 1e6}, {}}},
             clamped_cosine.reference_method,
             {}};
  for (const Method& m : clamped_cosine.methods) q.methods.push_back(on_top_method(m, m.name == q.reference_method));
  return q;
}

}  // namespace

void register_stiff_quantities(std::vector<Quantity>& out) {
  out.push_back(opposite_integral());
  out.push_back(opposite_value());
  out.push_back(vsgl_variance());
  const auto cc = std::find_if(out.begin(), out.end(), [](const Quantity& q) { return q.name == "clamped-cosine"; });
  if (cc != out.end()) {
    Quantity on_top = vsgl_on_top(*cc);
    out.push_back(std::move(on_top));
  }
}

}  // namespace sglab
