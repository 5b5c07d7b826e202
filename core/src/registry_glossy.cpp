// The glossy quantities of docs/math.md §4–5: ASG integrals, the ASG × SG product integral,
// and specular reflection of an SG light off GGX.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "sglab/asg_integral.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/registry_mp50.hpp"
#include "sglab/specular.hpp"
#include "registry_specular.hpp"

namespace sglab {
namespace {

template <class F>
Method method(std::string name, std::string source, std::string flaws, Domain domain, F f) {
  return make_method(std::move(name), std::move(source), std::move(flaws), false, std::move(domain), f);
}

// The same for a method whose formula also instantiates on the tracing type (every branch on an
// input a select): `sglab export` emits it (registry.hpp `exportable`).
template <class F>
Method exportable_method(std::string name, std::string source, std::string flaws, Domain domain, F f) {
  return make_method(exportable, std::move(name), std::move(source), std::move(flaws), false, std::move(domain), f);
}

// Adds to q a `specular` method exported as written: its formula f on the row's SpecularInput.
template <class F>
void add_specular_method(Quantity& q, std::string name, std::string source, std::string flaws, F f) {
  q.methods.push_back(exportable_method(std::move(name), std::move(source), std::move(flaws), nullptr,
                                        [f](auto a) { return f(specular_input(a)); }));
}

// A method whose evaluation is a double quadrature: float rounds the double result, mp50 converts
// it (a 50-digit 2D quadrature is too slow to sweep; the flaws text says so).
template <class F>
Method double_only_method(std::string name, std::string source, std::string flaws, F f) {
  Method m;
  m.name = std::move(name);
  m.source = std::move(source);
  m.flaws = std::move(flaws);
  m.evaluates_in_double = true;
  // One generic evaluator through set_evaluators (so batch evaluators exist too): double runs
  // f directly, float and mp50 convert to double and back.
  set_evaluators(m, [f](auto a) {
    using T = typename decltype(a)::value_type;
    if constexpr (std::is_same_v<T, double>) {
      return f(a);
    } else {
      std::vector<double> d;
      d.reserve(a.size());
      for (const auto& x : a) d.push_back(static_cast<double>(x));
      return T(f(std::span<const double>(d)));
    }
  });
  return m;
}

Domain all_positive(const std::vector<std::size_t>& columns, std::string why) {
  std::vector<std::pair<std::size_t, double>> bounds;
  for (auto c : columns) bounds.emplace_back(c, 0.0);
  return Domain::above(std::move(bounds), "undefined when a bandwidth is 0: " + why);
}

// The ASG of the asg-sg-product-integral columns: the standard frame, bandwidths (ηx, ηy).
template <class T>
Asg<T> standard_asg(const T& eta_x, const T& eta_y) {
  return {Vec3<T>(T(1), T(0), T(0)), Vec3<T>(T(0), T(1), T(0)), Vec3<T>(T(0), T(0), T(1)), eta_x, eta_y};
}

// The SG axis of the asg-sg-product-integral columns: cosine with ξz, azimuth from ξx.
template <class T>
Vec3<T> product_sg_axis(const T& cosine, const T& azimuth) {
  return specular_light_axis(cosine, azimuth);
}

// The relative size of the first neglected term of asg_sg_product_line_limit below (ηx ≥ ηy):
// ψ''(0)/(4ηx ψ(0)) for ψ(u) the integrand across the line (u = ω·x), whose second logarithmic
// derivative is bounded by 1 (the √(1 − u²) and cosine factors), 2ηy sin²b (≤ 100 where
// e^{−ηy sin²b} is above e^{−50}), λ and (λξx)² (the SG's slope across the line).
// Each term divided by ηx before they are added: (1 + … + λ)/(4ηx) overflowed to DBL_MAX/∞ = 0 at
// ηx = λ = DBL_MAX and took the line limit for two equally sharp lobes (it returned 0 for
// π/(1.5·DBL_MAX) = 1.17e-308); a term that still overflows is +∞ and keeps the 2D quadrature.
double asg_line_limit_error(double eta_x, double eta_y, double lambda, double xi_x) {
  const double slope = lambda * xi_x;
  return (1 / eta_x + std::min(2 * eta_y, 100.0) / eta_x + lambda / eta_x + slope * (slope / eta_x)) / 4;
}
// Used when that term is below this. The limit below includes that term, so what is left is the
// next one, ψ^(4)/(32ηx²ψ) ≈ 3(4ε)²/32 = 1.5ε² ≤ 4e-7 (ψ near a Gaussian in u): within the
// reference's 1e-6. (The 2D quadrature below missed 2.3e-2 relative at ηx = 1e6, ηy = 1: its
// azimuthal panels do not follow an ASG that anisotropic.)
constexpr double kAsgLineLimitError = 5e-4;

// ∫ Ĝ G dω for ηx far above every other scale (ηx ≥ ηy): with ω = (u, √(1 − u²) sin b, √(1 − u²) cos b),
// dω = du db, the ASG is e^{−ηx u²} times a function smooth in u, so by Laplace's method
//   ∫ Ĝ G dω = √(π/ηx)·∫_{−π/2}^{π/2} ψ(0; b)·(1 + ψ''(0; b)/(4ηx ψ(0; b))) db·(1 + O(ε²)),
// ψ(0; b) = cos b e^{−ηy sin²b} G((0, sin b, cos b); ξ, λ), ψ''/ψ = (λξx)² − 1 + 2ηy sin²b − λρ cos(b − β)
// (the second derivative across the line of log ψ plus the square of its first, λξx), ε = asg_line_limit_error. With ξ
// = (ξx, ρ sin β, ρ cos β), ‖ω − ξ‖²/2 = (1 − ρ) + 2ρ sin²((b − β)/2) on the line, 1 − ρ = ξx²/(1 + ρ). The 1D integral
// is adaptive Gauss–Kronrod split geometrically about b = 0 (width 1/√ηy) and b = β (width 1/√λ), in the offset from
// the sharper of the two so that its width is resolved down to the smallest double. The ASG's 2D quadrature floors its
// widths at 1e-7 rad and evaluates ω·x from ω: it gave 2.9e-19 at ηx = 1e20 and 0 at 1e30.
double asg_sg_product_line_limit(double eta_x, double eta_y, double lambda, const Vec3d& xi) {
  const double pi = std::numbers::pi;
  const double rho = std::hypot(xi(1), xi(2)), beta = std::atan2(xi(1), xi(2));
  const double offset = lambda * (xi(0) * xi(0) / (1 + rho));
  const bool about_light = lambda > eta_y;
  const double centre = about_light ? beta : 0.0;
  auto g = [&](double t) -> double {
    const double b = centre + t;
    const double d = about_light ? t : b - beta;
    const double sb = std::sin(b), sh = std::sin(0.5 * d);
    const double cb = std::cos(b);
    if (!(cb > 0)) return 0.0;
    const double curvature = (lambda * xi(0)) * (lambda * xi(0)) - 1 + 2 * eta_y * sb * sb - lambda * rho * std::cos(d);
    return cb * std::exp(-eta_y * sb * sb - offset - 2 * lambda * rho * sh * sh) * (1 + curvature / (4 * eta_x));
  };
  const double lo = -0.5 * pi - centre, hi = 0.5 * pi - centre;
  std::vector<double> br{lo, hi};
  const SphereQuadrature q;
  detail::add_geometric_breaks(br, -centre, 0.25 * (eta_y > 1 ? 1 / std::sqrt(eta_y) : 1.0), lo, hi, q.ratio);
  detail::add_geometric_breaks(br, beta - centre, 0.25 * (lambda > 1 ? 1 / std::sqrt(lambda) : 1.0), lo, hi, q.ratio);
  std::sort(br.begin(), br.end());
  using boost::math::quadrature::gauss_kronrod;
  const double coarse = detail::sum_panels(
      br, [&](double a, double b) { return gauss_kronrod<double, 15>::integrate(g, a, b, 0, 0.0); });
  if (!(coarse > 0)) return 0.0;
  const double share = 1e-3 * q.tolerance * coarse / double(br.size());
  const double line = detail::sum_panels(
      br, [&](double a, double b) { return detail::gauss_kronrod_absolute(g, a, b, share, q.max_depth); });
  return std::sqrt(pi / eta_x) * line;
}

// Exact ∫ Ĝ G dω by 2D quadrature (glossy_reference.hpp): pole = the SG axis (evaluated about it,
// right for any λ: integrate_sg_about_axis), foci = the ASG axis and the product axis, clipped to the
// ASG's hemisphere. Past kAsgLineLimitError, the line limit above (ηx or ηy far above the rest).
double asg_sg_product_quadrature(double eta_x, double eta_y, double lambda, double cosine, double azimuth) {
  const Vec3d xi = product_sg_axis(cosine, azimuth);
  // The ASG is symmetric under x ↔ y with (ηx, ηy) and (ξx, ξy) swapped.
  if (eta_x >= eta_y && asg_line_limit_error(eta_x, eta_y, lambda, xi(0)) <= kAsgLineLimitError)
    return asg_sg_product_line_limit(eta_x, eta_y, lambda, xi);
  if (eta_y > eta_x && asg_line_limit_error(eta_y, eta_x, lambda, xi(1)) <= kAsgLineLimitError)
    return asg_sg_product_line_limit(eta_y, eta_x, lambda, Vec3d(xi(1), xi(0), xi(2)));
  const Asg<double> g = standard_asg(eta_x, eta_y);
  const double eta_max = std::max(eta_x, eta_y);
  const double w_asg = eta_max > 1 ? 1 / std::sqrt(eta_max) : 1.0;
  const double w_sg = lambda > 1 ? 1 / std::sqrt(lambda) : 1.0;
  const Vec3d prod = sg_product(xi, lambda, g.z, 2 * std::sqrt(eta_x) * std::sqrt(eta_y)).axis;
  const SphereFocus foci[2] = {{g.z, w_asg}, {prod, std::min(w_asg, w_sg)}};
  const Vec3d clips[1] = {g.z};
  return integrate_sg_about_axis([&](const Vec3d& w) { return asg_eval(w, g); }, xi, lambda, foci, clips,
                                 SphereQuadrature{});
}

}  // namespace

std::vector<Column> specular_columns(std::string roughness) {
  return {{"roughness", ColumnKind::positive, std::move(roughness)},
          {"light_sharpness", ColumnKind::sharpness, "SG light sharpness λ ≥ 0"},
          {"light_cos", ColumnKind::cosine, "cosine between the light axis and the normal"},
          {"view_cos", ColumnKind::unit_interval, "cosine between the view direction and the normal, in [0, 1]"},
          {"light_azimuth", ColumnKind::angle,
           "light azimuth from the view's azimuth (radians; π with light_cos = view_cos is the mirror direction)"},
          {"f0", ColumnKind::unit_interval, "Schlick reflectance at normal incidence"}};
}

void register_glossy_quantities(std::vector<Quantity>& out) {
  const Column eta_x{"eta_x", ColumnKind::nonnegative, "ASG bandwidth ηx ≥ 0 (along ξx)"};
  const Column eta_y{"eta_y", ColumnKind::nonnegative, "ASG bandwidth ηy ≥ 0 (along ξy)"};

  // ---- asg-integral ---------------------------------------------------------------------------
  {
    Quantity q{"asg-integral", "∫ Ĝ(ω; ξx, ξy, ξz, ηx, ηy) dω (docs/math.md §4)", {eta_x, eta_y}, "exact", {}};
    q.methods.push_back(
        method("exact", "π∫_0^1 e^{−ηmin u} e^{−tu/2}I0(tu/2) du, t = |ηx − ηy| (derived in asg.hpp), tanh-sinh",
               "float evaluates in double and rounds", nullptr, [](auto a) { return asg_integral_exact(a[0], a[1]); }));
    q.methods.push_back(method(
        "approx", "π/√(ηxηy) (Xu et al. 2013): the Gaussian over the whole tangent plane",
        "overestimates by the tail beyond the disc (≈ π e^{−(ηx+ηy)/2} I0(|ηx−ηy|/2)/ηmin); diverges as ηx or ηy → 0",
        all_positive({0, 1}, "π/√(ηxηy) diverges"), [](auto a) { return asg_integral_approx(a[0], a[1]); }));
    q.methods.push_back(
        method("as-printed",
               "B(λx, λy) as printed in Tokuyoshi 2015 (lobe-aware filtering) App. C, F(t) = 2π e^{−t/2}I0(t/2) exact",
               "undefined at ηmin = 0 (t/λy); see tests/asg_test.cpp for its measured error",
               all_positive({0, 1}, "B divides by λy"), [](auto a) { return asg_integral_as_printed(a[0], a[1]); }));
    out.push_back(std::move(q));
  }

  // ---- asg-sg-product-integral ------------------------------------------------------------------
  {
    Quantity q{"asg-sg-product-integral",
               "∫ Ĝ(ω; x, y, z, ηx, ηy) G(ω; ξ, λ) dω, ASG in the standard frame, ξ = (s cos φ, s sin φ, cosine) "
               "(docs/math.md §4)",
               {eta_x,
                eta_y,
                {"sharpness", ColumnKind::sharpness, "SG sharpness λ ≥ 0"},
                {"cosine", ColumnKind::cosine, "ξ·ξz, cosine between the SG axis and the ASG axis"},
                {"azimuth", ColumnKind::angle, "azimuth of ξ about ξz, from ξx (radians)"}},
               "exact",
               {}};
    q.methods.push_back(double_only_method(
        "exact", "2D adaptive Gauss–Kronrod about the SG axis and the ASG axis (glossy_reference.hpp integrate_sphere)",
        "double quadrature (≤ 1e-6 relative); float rounds and mp50 converts the double result",
        [](std::span<const double> a) { return asg_sg_product_quadrature(a[0], a[1], a[2], a[3], a[4]); }));
    q.methods.push_back(method(
        "two-vsgls",
        "π Ĝ(ξ; ηxν/(ηx+ν), ηyν/(ηy+ν))/√((ηx+ν)(ηy+ν)), ν = λ/2 (Tokuyoshi 2015 (two-VSGL poster) §3.2; Xu et al. "
        "2013)",
        "0 whenever ξ·ξz ≤ 0 (the ASG is evaluated at the SG axis); poor for broad lobes (plane approximation)",
        [](std::span<const double> a) -> std::optional<std::string> {
          if ((a[0] + a[2] / 2) > 0 && (a[1] + a[2] / 2) > 0) return std::nullopt;
          return std::string("undefined when ηx + λ/2 or ηy + λ/2 is 0 (division by zero)");
        },
        [](auto a) {
          using T = typename decltype(a)::value_type;
          return asg_sg_product_two_vsgls(standard_asg(a[0], a[1]), product_sg_axis(a[3], a[4]), T(a[2]));
        }));
    q.methods.push_back(
        method("lobe-aware",
               "2π Ĝ(ξ; λxλy/(2λx+λy), λxλy/(2λy+λx))/√((2λx+λy)(2λy+λx)) AS PRINTED in Tokuyoshi 2015 (lobe-aware "
               "filtering) App. C",
               "AS PRINTED IT DOES NOT DEPEND ON THE SG SHARPNESS λ (evidently a typo: with λ in place of the second "
               "bandwidth of each pair it equals `two-vsgls` exactly); 0 whenever ξ·ξz ≤ 0",
               all_positive({0, 1}, "the printed form is 0/0 at ηx = ηy = 0"), [](auto a) {
                 return asg_sg_product_lobe_aware_printed(standard_asg(a[0], a[1]), product_sg_axis(a[3], a[4]));
               }));
    q.reference_reach.max_sharpness = kQuadratureMaxSharpness;
    q.reference_reach.rows = 40;
    q.reference_reach.rows_quick = 10;
    q.reference_reach.cost = "the reference (2D quadrature) takes 20–200 ms per point";
    out.push_back(std::move(q));
  }

  // ---- specular -----------------------------------------------------------------------------
  {
    Quantity q{"specular",
               "L = ∫ G(ω; ξ, λ) f(ωo, ω)⟨ω·n⟩ dω, unit-amplitude SG light, GGX + height-correlated Smith + Schlick; "
               "n = (0,0,1), ωo = (√(1−v²), 0, v), ξ = (s cos φ, s sin φ, light_cos)",
               specular_columns("GGX α > 0"),
               "reference",
               {}};
    q.methods.push_back(
        double_only_method("reference",
                           "adaptive 2D Gauss–Kronrod about the light axis and the mirror/dominant-visible-normal "
                           "directions (glossy_reference.hpp)",
                           "double quadrature, ≤ 1e-6 relative (checked against a finer rule and Monte Carlo); float "
                           "rounds and mp50 converts the double result (an mp50 2D quadrature is too slow)",
                           [](std::span<const double> a) { return specular_reference_value(specular_input(a)); }));
    // Its cost grows without bound as α → 0: refused below kMinReferenceRoughness.
    q.methods.back().domain_error = [](std::span<const double> a) -> std::optional<std::string> {
      if (a[0] >= kMinReferenceRoughness) return std::nullopt;
      return "roughness below " + std::to_string(kMinReferenceRoughness).substr(0, 5) +
             ": the quadrature's cost grows without bound as α → 0 (the renderer's minimum α is the same)";
    };
    add_specular_method(q, "sg-warp",
                        "SG lobe G(ω; ξ_s, 2/α²/(4|ξ_s·n|))/(πα²) (Wang et al. 2009 warp; Tokuyoshi 2015 (two-VSGL "
                        "poster) §1.1, Tokuyoshi 2015 (lobe-aware filtering) App. B) × SG light, exact product "
                        "integral (Tsai & Shih 2006), M at the lobe axis ξ_s (Wang et al. 2009)",
                        "isotropic lobe about the mirror direction: wrong shape and position at grazing view and for "
                        "rough surfaces; energy not normalized",
                        [](const auto& in) { return specular_sg_warp(in); });
    add_specular_method(
        q, "sg-warp-product-axis",
        "as sg-warp with M at the product lobe's axis ξ_m = (λξ + λ_sξ_s)/‖…‖ instead of ξ_s (a variant, not Wang et "
        "al. 2009)",
        "as sg-warp; a false 0 where ξ_m is at or below the horizon though the light still reaches the surface",
        [](const auto& in) { return specular_sg_warp(in, SgProductForm::exact, false, FactorAt::product_axis); });
    add_specular_method(
        q, "sg-warp-iwasaki",
        "as sg-warp with the Iwasaki et al. 2012 product integral (Tokuyoshi 2015 (lobe-aware filtering) Eq. C.1)",
        "as sg-warp; the Iwasaki product overestimates broad lobes (2π/(λ1+λ2) > 4π at small λ)",
        [](const auto& in) { return specular_sg_warp(in, SgProductForm::iwasaki); });
    add_specular_method(q, "sg-warp-th2019", "as sg-warp with λ_h = 2/α² − 2 (Tokuyoshi & Harada 2019)",
                        "as sg-warp; λ_h = 0 at α = 1 (a constant lobe)",
                        [](const auto& in) { return specular_sg_warp(in, SgProductForm::exact, true); });
    add_specular_method(q, "asg",
                        "ASG lobe (Xu et al. 2013 warp, ηx = λ_h/8, ηy = λ_h/(8 v²)) × SG light, product integral of "
                        "Tokuyoshi 2015 (two-VSGL poster) §3.2 (ν = λ/2), M at ξ_m",
                        "0 when the light axis is ≥ 90° from the mirror direction; the plane approximation of the "
                        "product overestimates broad lobes; energy not normalized",
                        [](const auto& in) { return specular_asg(in); });
    add_specular_method(
        q, "sg-warp-dvn",
        "refinement: vMF about the GGX dominant-visible-normal reflection (Tokuyoshi et al. 2024, λ_h = 2/α² − 2) as "
        "the VNDF reflection pdf, times F·G2/G1(ωo) at the product axis, exact product",
        "isotropic lobe (no grazing anisotropy); F·G2/G1 taken at one direction",
        [](const auto& in) { return specular_sg_warp_dvn(in); });
    q.methods.push_back(specular_sglab_method());  // registry_specular_sglab.cpp
    q.reference_reach.max_sharpness = kQuadratureMaxSharpness;
    q.reference_reach.rows = 16;
    q.reference_reach.rows_quick = 4;
    q.reference_reach.affordable = [](std::span<const double> a) { return a[0] >= 0.1 && a[1] <= 1e4; };
    q.reference_reach.cost =
        "the reference (adaptive 2D quadrature) takes 0.02–2 s per point and ~100 s at α = 1e-4 with grazing view";
    q.reference_reach.affordable_rows = "those with roughness ≥ 0.1 and light sharpness ≤ 1e4";
    out.push_back(std::move(q));
  }
}

}  // namespace sglab
