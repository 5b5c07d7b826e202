// Formulas `sglab export` emits that are not registry quantities (emit.hpp export_only_quantities):
// the filtering weights of core/include/sglab/filtering_weights.hpp, the functions the filter
// (core/render/src/filtering.cpp) calls, instantiated on the tracing type like the registry's
// methods (not retyped). Their columns are the function's scalar arguments in order, each vector
// as its three components.
#include "emit.hpp"

#include "sglab/filtering_weights.hpp"
#include "sglab/registry_mp50.hpp"  // make_method: every precision

namespace sglab::shader {
namespace {

std::vector<Column> vector_columns(const std::string& name, const std::string& what) {
  return {{name + "_x", ColumnKind::finite, "x of " + what},
          {name + "_y", ColumnKind::finite, "y of " + what},
          {name + "_z", ColumnKind::finite, "z of " + what}};
}

// The weights take different arguments, so each is one method of a Quantity of its own, all
// named "filtering" (`filtering/lobe-weight`, `filtering/normal-weight`).
std::vector<Quantity> make_export_only() {
  std::vector<Quantity> out;
  Quantity q;
  q.name = "filtering";
  q.description =
      "a filtering weight w(i, j) ∈ [0, 1] of pixel j for pixel i (Tokuyoshi 2015 (lobe-aware filtering); docs/math.md "
      "§8)";
  {
    Quantity lobe = q;
    auto add = [&](std::vector<Column> c) { lobe.columns.insert(lobe.columns.end(), c.begin(), c.end()); };
    add(vector_columns("axis_i", "pixel i's specular lobe axis ξ_i (unit)"));
    add({{"sharpness_i", ColumnKind::sharpness, "pixel i's lobe sharpness λ_i ≥ 0 (unsmoothed; 0: a uniform lobe)"}});
    add(vector_columns("axis_j", "pixel j's specular lobe axis ξ_j (unit)"));
    add({{"sharpness_j", ColumnKind::sharpness, "pixel j's lobe sharpness λ_j ≥ 0 (unsmoothed)"},
         {"beta", ColumnKind::nonnegative, "the exponent β of q^β (20 in the paper's Fig. D.2)"},
         {"kappa", ColumnKind::positive,
          "the smoothing kernel's sharpness κ > 0 (+∞: no smoothing; 100 in Fig. D.2)"}});
    lobe.methods.push_back(
        make_method(exportable, "lobe-weight",
                    "Tokuyoshi 2015 (lobe-aware filtering) Eq. (9), (12) in the optimized form of App. E: "
                    "w = exp(β/2·log(4u/v²) + βu/v·(ξ_i·ξ_j − 1)), u = λ̄_iλ̄_j, v = λ̄_i + λ̄_j, λ̄ = λκ/(λ + κ) (each "
                    "lobe smoothed by the "
                    "kernel); log(4u/v²) as log1p(−r²), r = (λ̄_i − λ̄_j)/v, or a product of two ratios, and ξ_i·ξ_j − 1 "
                    "as −‖ξ_i − ξ_j‖²/2 "
                    "(filtering_weights.hpp lobe_aware_weight)",
                    "the Iwasaki product approximation of the lobes' similarity: accurate for sharp lobes (error "
                    "O(1/λ̄)); one uniform and one "
                    "sharp lobe give 0, two uniform lobes 1 (as published)",
                    false, nullptr, [](auto a) {
                      using T = std::decay_t<decltype(a[0])>;
                      return lobe_aware_weight(Vec3<T>(a[0], a[1], a[2]), T(a[3]), Vec3<T>(a[4], a[5], a[6]), T(a[7]),
                                               T(a[8]), T(a[9]));
                    }));
    out.push_back(std::move(lobe));
  }
  {
    Quantity normal = q;
    auto add = [&](std::vector<Column> c) { normal.columns.insert(normal.columns.end(), c.begin(), c.end()); };
    add(vector_columns("normal_i", "pixel i's shading normal n_i (unit)"));
    add(vector_columns("normal_j", "pixel j's shading normal n_j (unit)"));
    add({{"sigma_n2", ColumnKind::nonnegative,
          "the variance σ_n² ≥ 0 (0.05404477 = (2λ_c + κ)/(βλ_cκ) for β = 20, κ = 100: the diffuse lobe-aware weight, "
          "App. D)"}});
    normal.methods.push_back(make_method(
        exportable, "normal-weight",
        "the normal-aware weight of Tokuyoshi 2015 (lobe-aware filtering) App. D: w_n = G(n_i; n_j, 1/σ_n²) = "
        "exp(−‖n_i − n_j‖²/(2σ_n²)) (no cancellation in n_i·n_j − 1; σ_n² = 0: 1 for equal normals, 0 otherwise) "
        "(filtering_weights.hpp normal_weight)",
        "", false, nullptr, [](auto a) {
          using T = std::decay_t<decltype(a[0])>;
          return normal_weight(Vec3<T>(a[0], a[1], a[2]), Vec3<T>(a[3], a[4], a[5]), T(a[6]));
        }));
    out.push_back(std::move(normal));
  }
  return out;
}

}  // namespace

const std::vector<Quantity>& export_only_quantities() {
  static const std::vector<Quantity> q = make_export_only();
  return q;
}

}  // namespace sglab::shader
