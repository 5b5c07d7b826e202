// The core quantities of docs/math.md §1–3 and §6 and their methods.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "sglab/clamped_cosine.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/hemispherical.hpp"
#include "sglab/reference_mp50.hpp"
#include "sglab/registry_mp50.hpp"
#include "sglab/sg.hpp"
#include "sglab/vmf_filtering.hpp"

namespace sglab {
namespace {

// Methods with a 1/λ factor are undefined at λ = 0 (column `column`).
Domain sharpness_positive(std::size_t column, std::string why) {
  return Domain::above({{column, 0.0}}, "undefined at sharpness 0: " + why);
}

// The `reference` method of a (λ, c) quantity: reference(λ, c), a quadrature of reference.hpp. In
// float it is the double reference rounded (no float quadrature of its own).
template <class F>
Method quadrature_reference_method(F reference) {
  return make_method("reference",
                     "1D tanh-sinh quadrature in t = ω·ξ, azimuth in closed form (core/include/sglab/reference.hpp)",
                     "", false, nullptr, [reference](auto a) {
                       using T = typename decltype(a)::value_type;
                       if constexpr (std::is_same_v<T, float>) {
                         return static_cast<float>(reference(double(a[0]), double(a[1])));
                       } else {
                         return reference(a[0], a[1]);
                       }
                     });
}

// The constants of each method (defined once in core's headers; see Parameter in registry.hpp).
std::vector<Parameter> meder_logistic_parameters() {
  const std::string src = "Meder & Brüderlin 2018, logistic steepness t(λ)";
  return fit_parameters(
      "meder-logistic", src,
      {{"p1", MederLogistic::p1}, {"p2", MederLogistic::p2}, {"p3", MederLogistic::p3}, {"p4", MederLogistic::p4}});
}
std::vector<Parameter> tokuyoshi2022_steepness_parameters() {
  const std::string src = "Tokuyoshi 2022, steepness k(λ) of the hemispherical integral";
  return fit_parameters(
      "tokuyoshi2022-steepness", src,
      {{"A", Tokuyoshi2022Steepness::A}, {"B", Tokuyoshi2022Steepness::B}, {"C", Tokuyoshi2022Steepness::C}});
}
std::vector<Parameter> concat(std::vector<Parameter> a, const std::vector<Parameter>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The large-λ limits of H(λ, c) and D(λ, c), which stand in for the quadrature references past
// kQuadratureMaxSharpness: for λ → ∞ the unit SG is a planar Gaussian of variance 1/λ per axis and
// total mass 2π/λ, and ω·n ≈ c + (the in-plane offset towards n), so
//   H → (2π/λ)·½erfc(−c√(λ/2)),  D → (2π/λ)·(c·½erfc(−c√(λ/2)) + e^{−λc²/2}/√(2πλ)),
// i.e. 2π/λ and 2π⟨c⟩/λ away from the horizon. Relative error O(1/λ + λc⁴) (the θ⁴ term of cos θ
// in the back-facing tail): ≤ 1e-8 on the stiff grid past 1e8, whose back-facing cosines are
// −1e-8 or ≤ −1/16 (where both values underflow to 0).
ReferenceReach large_sharpness_reach(double (*limit)(double lambda, double c), std::string formula) {
  ReferenceReach r;
  r.max_sharpness = kQuadratureMaxSharpness;
  r.limit = [limit](std::span<const double> a) { return limit(a[0], std::clamp(a[1], -1.0, 1.0)); };
  r.limit_formula = std::move(formula) + " (relative error O(1/λ + λc⁴), ≤ 1e-8 on the stiff grid)";
  return r;
}
double hemispherical_large_sharpness(double lambda, double c) {
  return 2 * std::numbers::pi / lambda * 0.5 * std::erfc(-c * std::sqrt(lambda / 2));
}
double clamped_cosine_large_sharpness(double lambda, double c) {
  const double tail = std::exp(-lambda * c * c / 2) / std::sqrt(2 * std::numbers::pi * lambda);
  return 2 * std::numbers::pi / lambda * (c * 0.5 * std::erfc(-c * std::sqrt(lambda / 2)) + tail);
}

}  // namespace

void register_core_quantities(std::vector<Quantity>& out) {
  const Column sharpness{"sharpness", ColumnKind::sharpness, "SG sharpness λ ≥ 0"};
  const Column cosine{"cosine", ColumnKind::cosine, "cosine c = ξ·n between lobe axis and normal"};

  // ---- sg-integral --------------------------------------------------------------------------
  {
    Quantity q{"sg-integral", "A(λ) = ∫ G(ω; ξ, λ) dω over the sphere (docs/math.md §1)", {sharpness}, "exact", {}};
    q.methods.push_back(
        make_method("exact", "2π(1 − e^{−2λ})/λ via expm1 (Tokuyoshi 2015 (two-VSGL poster) §1, Tokuyoshi 2016 §2)", "",
                    false, nullptr, [](auto a) { return sg_integral(a[0]); }));
    q.methods.push_back(make_method("approx", "2π/λ (Iwasaki et al. 2012; Tokuyoshi 2016 §4.2)",
                                    "overestimates by 1/(1 − e^{−2λ}); diverges as λ → 0", false,
                                    sharpness_positive(0, "2π/λ diverges"),
                                    [](auto a) { return sg_integral_approx(a[0]); }));
    out.push_back(std::move(q));
  }

  // ---- hemispherical ------------------------------------------------------------------------
  {
    Quantity q{
        "hemispherical", "H(λ, c) = ∫_{ω·n>0} G(ω; ξ, λ) dω (docs/math.md §2)", {sharpness, cosine}, "reference", {}};
    q.methods.push_back(quadrature_reference_method([](auto l, auto c) { return hemispherical_reference(l, c); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "meder", "Meder & Brüderlin 2018, logistic interpolation between the c = ±1 bounds", "", false,
        nullptr, meder_logistic_parameters(), [](auto a) { return hemispherical_meder(a[0], a[1]); },
        [](auto a, auto p) { return hemispherical_meder(a[0], a[1], p[0], p[1], p[2], p[3]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "tokuyoshi2022", "Tokuyoshi 2022 (poster), CDF of a Gaussian on a plane", "", false, nullptr,
        tokuyoshi2022_steepness_parameters(), [](auto a) { return hemispherical_tokuyoshi2022(a[0], a[1]); },
        [](auto a, auto p) { return hemispherical_tokuyoshi2022(a[0], a[1], p[0], p[1], p[2]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "vmf-tokuyoshi2024",
        "Tokuyoshi et al. 2024: the 2022 factor for the normalized vMF, lerp(e^{−λ}, 1, f)/(1 + e^{−λ})",
        "NORMALIZED: returns H/A(λ), a fraction in [0, 1], not H", false, nullptr, tokuyoshi2022_steepness_parameters(),
        [](auto a) { return hemispherical_vmf_tokuyoshi2024(a[0], a[1]); },
        [](auto a, auto p) { return hemispherical_vmf_tokuyoshi2024(a[0], a[1], p[0], p[1], p[2]); }));
    q.reference_reach = large_sharpness_reach(hemispherical_large_sharpness,
                                              "(2π/λ)·½erfc(−c√(λ/2)) (→ 2π/λ at c > 0)");
    out.push_back(std::move(q));
  }

  // ---- clamped-cosine -----------------------------------------------------------------------
  {
    Quantity q{"clamped-cosine",
               "D(λ, c) = ∫ G(ω; ξ, λ)⟨ω·n⟩ dω, unit-amplitude SG (docs/math.md §3)",
               {sharpness, cosine},
               "reference",
               {}};
    q.methods.push_back(quadrature_reference_method([](auto l, auto c) { return clamped_cosine_reference(l, c); }));
    q.methods.push_back(make_method(
        exportable, "punctual", "A(λ)⟨c⟩: cosine pulled out of the integral (Wang et al. 2009; Tokuyoshi 2016 §4.2)",
        "zero for every c ≤ 0 (no light past the horizon); large error for broad lobes", false, nullptr,
        [](auto a) { return clamped_cosine_punctual(a[0], a[1]); }));
    q.methods.push_back(make_method(exportable, "punctual-approx", "(2π/λ)⟨c⟩ (Tokuyoshi 2016 §4.2, A(λ) ≈ 2π/λ)",
                                    "as `punctual`, and diverges as λ → 0", false,
                                    sharpness_positive(0, "the 2π/λ factor diverges"),
                                    [](auto a) { return clamped_cosine_punctual_approx(a[0], a[1]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "sg-cosine",
        "cosine ≈ π G(ω; n, λ_d)/A(λ_d), λ_d = 2, Iwasaki product (Tokuyoshi 2015 (two-VSGL poster) §3.2)",
        "light leaks past the horizon; the Iwasaki product is poor for broad lobes; exact A(λ_d) used (the paper takes "
        "A(λ_d) ≈ π); for sharp lights (λ → ∞) it tends to (π/A(λ_d))·e^{λ_d(c−1)}·2π/λ instead of 2π⟨c⟩/λ (off by up "
        "to 14 % of the peak 2π/λ, at c ≈ 0.6)",
        false, nullptr,
        {{"lambda_d", "lambda-d", SgCosine::lambda_d,
          "Tokuyoshi's VSGL papers: λ_d ≈ 2 by least squares (objective not stated)", ColumnKind::positive,
          ParameterRole::vsgl_diffuse_sharpness}},
        [](auto a) { return clamped_cosine_sg_cosine(a[0], a[1]); },
        [](auto a, auto p) { return clamped_cosine_sg_cosine(a[0], a[1], p[0]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "cosine-lobe-sg",
        "cosine ≈ 1.17·G(ω; n, 2.133), exact SG product (Pettineo 2016, SG series part 3)",
        "light leaks past the horizon; for sharp lights (λ → ∞) it tends to 1.17·e^{2.133(c−1)}·2π/λ instead of "
        "2π⟨c⟩/λ (17 % high at c = 1)",
        false, nullptr,
        {{"amplitude", "cosine-lobe-sg", CosineLobeSg::amplitude, "Pettineo 2016, SG series part 3",
          ColumnKind::positive},
         {"sharpness", "cosine-lobe-sg", CosineLobeSg::sharpness, "Pettineo 2016, SG series part 3",
          ColumnKind::positive}},
        [](auto a) { return clamped_cosine_cosine_lobe_sg(a[0], a[1]); },
        [](auto a, auto p) { return clamped_cosine_cosine_lobe_sg(a[0], a[1], p[0], p[1]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "hill-fitted", "Pettineo & Hill 2016 fitted irradiance (SG series part 3), c0 = 0.36",
        "PUBLISHED FORM GOES NEGATIVE for λ ≲ 1 (the 'black splotches'); kept as published. Undefined at λ = 0", true,
        sharpness_positive(0, "the fit divides by λ"),
        {{"c0", "hill-irradiance", HillIrradiance::c0, "Pettineo 2016, SG series part 3 (Hill's fit)",
          ColumnKind::positive}},
        [](auto a) { return clamped_cosine_hill_fitted(a[0], a[1]); },
        [](auto a, auto p) { return clamped_cosine_hill_fitted(a[0], a[1], p[0]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "meder",
        "cosine ≈ 32.7080 G(ω; n, 0.0315) − 31.7003, Meder hemispherical integrals (Meder & Brüderlin 2018; PhySG, "
        "Zhang et al. 2021)",
        "PUBLISHED FORM GOES NEGATIVE (difference of two large terms); kept as published. Loses ~5 bits to "
        "cancellation",
        true, nullptr,
        concat(
            {{"amplitude", "cosine-sg", MederCosineSg::amplitude, "Meder & Brüderlin 2018 (PhySG)",
              ColumnKind::positive},
             {"sharpness", "cosine-sg", MederCosineSg::sharpness, "Meder & Brüderlin 2018 (PhySG)",
              ColumnKind::positive},
             {"offset", "cosine-sg", MederCosineSg::offset, "Meder & Brüderlin 2018 (PhySG)", ColumnKind::nonnegative}},
            meder_logistic_parameters()),
        [](auto a) { return clamped_cosine_meder(a[0], a[1]); },
        [](auto a, auto p) { return clamped_cosine_meder(a[0], a[1], p[0], p[1], p[2], p[3], p[4], p[5], p[6]); }));
    q.methods.push_back(make_method_with_parameters(
        exportable, "tokuyoshi2022",
        "cosine ≈ α(e^{λc}G(ω; n, λc) − 1), λc = 0.00084560872241480124, 2022 hemispherical integrals (Tokuyoshi 2022 "
        "(poster))",
        "cancellation between the two terms (×2364 amplification): ~1% in float, by design of λc; clamped at 0", false,
        nullptr,
        concat({{"lambda", "cosine-sharpness", Tokuyoshi2022Cosine::lambda,
                 "Tokuyoshi 2022 (λc; α = α(λc) is derived from it)", ColumnKind::positive}},
               tokuyoshi2022_steepness_parameters()),
        [](auto a) { return clamped_cosine_tokuyoshi2022(a[0], a[1]); },
        [](auto a, auto p) {
          return clamped_cosine_tokuyoshi2022_with(a[0], a[1], p[0], tokuyoshi2022_alpha(p[0]), p[1], p[2], p[3]);
        }));
    {
      const std::string src = "Tokuyoshi et al. 2024, steepness t(λ) of the erfc interpolation";
      q.methods.push_back(make_method_with_parameters(
          exportable, "tokuyoshi2024", "Tokuyoshi et al. 2024, erfc interpolation between the c = ±1 bounds", "", false,
          nullptr,
          fit_parameters("tokuyoshi2024-t", src,
                         {{"A", Tokuyoshi2024T::A},
                          {"B", Tokuyoshi2024T::B},
                          {"C", Tokuyoshi2024T::C},
                          {"D", Tokuyoshi2024T::D},
                          {"E", Tokuyoshi2024T::E}}),
          [](auto a) { return clamped_cosine_tokuyoshi2024(a[0], a[1]); },
          [](auto a, auto p) { return clamped_cosine_tokuyoshi2024(a[0], a[1], p[0], p[1], p[2], p[3], p[4]); }));
    }
    {
      const std::string src = "sglab (this project): constants of `sglab fit sglab` (paper_tables/own_method.md)";
      using S = SglabDiffuse;
      q.methods.push_back(make_method_with_parameters(
          exportable, "sglab",
          "sglab (this project): tokuyoshi2024's erfc interpolation with a refitted t(λ) and one even correction term "
          "(K/t)(e^{−t²} − c²e^{−t²c²}); constants from `sglab fit sglab` (paper_tables/own_method.md)",
          "fitted, not derived: max error 8.1e-5 of D(λ, 1) on a dense check (281 λ × 401 c), none guaranteed between "
          "points; in the back-facing tail the corrected even part is held at ≥ ½ of the uncorrected one (part of the "
          "fitted form, keeps the value positive)",
          false, nullptr,
          fit_parameters("sglab", src,
                         {{"A", S::A},
                          {"B", S::B},
                          {"C", S::C},
                          {"D", S::D},
                          {"E", S::E},
                          {"k", S::k},
                          {"P", S::P, ColumnKind::finite},
                          {"Q", S::Q}}),
          [](auto a) { return clamped_cosine_sglab(a[0], a[1]); },
          [](auto a, auto p) {
            using T = std::decay_t<decltype(a[0])>;
            const SglabDiffuseParams<T> q{T(p[0]), T(p[1]), T(p[2]), T(p[3]), T(p[4]), T(p[5]), T(p[6]), T(p[7])};
            return clamped_cosine_sglab_with(a[0], a[1], q);
          }));
    }
    q.reference_reach = large_sharpness_reach(clamped_cosine_large_sharpness,
                                              "(2π/λ)(c·½erfc(−c√(λ/2)) + e^{−λc²/2}/√(2πλ)) (→ 2π⟨c⟩/λ)");
    out.push_back(std::move(q));
  }

  // ---- product-integral ---------------------------------------------------------------------
  {
    Quantity q{"product-integral",
               "∫ G(ω; ξ1, λ1) G(ω; ξ2, λ2) dω, cosine = ξ1·ξ2 (docs/math.md §1)",
               {{"sharpness1", ColumnKind::sharpness, "λ1 ≥ 0"},
                {"sharpness2", ColumnKind::sharpness, "λ2 ≥ 0"},
                {"cosine", ColumnKind::cosine, "ξ1·ξ2"}},
               "exact",
               {}};
    q.methods.push_back(make_method("exact", "e^{L}·A(λ3) = 4π sinh(λ3)/(λ3 e^{λ1+λ2}) (Tsai & Shih 2006), no overflow",
                                    "", false, nullptr,
                                    [](auto a) { return product_integral_exact(a[0], a[1], a[2]); }));
    q.methods.push_back(make_method(
        "iwasaki",
        "2π G(ξ1; ξ2, λ1λ2/(λ1+λ2))/(λ1+λ2) (Iwasaki et al. 2012; Tokuyoshi 2015 (lobe-aware filtering) Eq. C.1)",
        "accurate only when λ1 or λ2 is large; diverges as λ1 + λ2 → 0", false,
        [](std::span<const double> a) -> std::optional<std::string> {
          if (a[0] + a[1] > 0) return std::nullopt;
          return std::string("undefined at sharpness1 + sharpness2 = 0: 2π/(λ1 + λ2) diverges");
        },
        [](auto a) { return product_integral_iwasaki(a[0], a[1], a[2]); }));
    out.push_back(std::move(q));
  }

  // ---- vMF filtering ------------------------------------------------------------------------
  {
    Quantity q{"vmf-sharpness",
               "vMF sharpness from the mean resultant length r (docs/math.md §6)",
               {{"mean_length", ColumnKind::mean_length, "r = ‖mean of the lobes' average directions‖ ∈ [0, 1]"}},
               "",
               {}};
    q.methods.push_back(
        make_method("toksvig", "r/(1 − r) (Toksvig 2005; Tokuyoshi 2015 (two-VSGL poster) §2.1, Tokuyoshi 2016 §3.1)",
                    "clamped to 1e8 as r → 1", false, nullptr, [](auto a) { return vmf_sharpness_toksvig(a[0]); }));
    q.methods.push_back(make_method("banerjee", "r(3 − r²)/(1 − r²) (Banerjee et al. 2005)", "clamped to 1e8 as r → 1",
                                    false, nullptr, [](auto a) { return vmf_sharpness_banerjee(a[0]); }));
    out.push_back(std::move(q));
  }
  {
    Quantity q{"vmf-mean-length",
               "mean resultant length r from a vMF sharpness (inverse of vmf-sharpness)",
               {sharpness},
               "",
               {}};
    q.methods.push_back(make_method("toksvig", "λ/(1 + λ) (inverse of Toksvig 2005)", "", false, nullptr,
                                    [](auto a) { return vmf_mean_length_toksvig(a[0]); }));
    q.methods.push_back(make_method(
        "banerjee", "root in [0, 1) of r(3 − r²) = λ(1 − r²) (inverse of Banerjee et al. 2005), safeguarded Newton", "",
        false, nullptr, [](auto a) { return vmf_mean_length_banerjee(a[0]); }));
    out.push_back(std::move(q));
  }
}

}  // namespace sglab
