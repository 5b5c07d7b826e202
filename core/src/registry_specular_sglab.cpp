// The `specular` quantity's method `sglab`, this project's own (specular_sglab.hpp): a unit of its
// own, so that an edit of the own method's formula recompiles this and not the published methods'
// registration (registry_glossy.cpp; docs/testing.md, "Rebuilding after a method's header").
#include <string>
#include <type_traits>

#include "sglab/registry_mp50.hpp"
#include "sglab/specular_sglab.hpp"
#include "registry_specular.hpp"

namespace sglab {

Method specular_sglab_method() {
  const std::string src =
      "sglab (this project): constants of `sglab fit sglab-specular` (paper_tables/own_specular.md)";
  using S = SglabSpecular;
  return make_method_with_parameters(
      exportable, "sglab",
      "sglab (this project): GGX's slope density as a Student t smoothed by the light's Gaussian in slope space "
      "(scale s_D = α²/2·(1 + κρ0), ν = 2 + c_ν ρ/(1 − ρ)), "
      "the BRDF weight and the true light at the product's peak, a horizon factor; constants from `sglab fit "
      "sglab-specular` (paper_tables/own_specular.md)",
      "fitted, not derived: measured on the sweep grid and off it (paper_tables/own_specular.md), none guaranteed "
      "between points; the light is Gaussian in slope "
      "space only near its axis (broad lights at grazing view carry the largest error); roughness held at ≤ 1e4",
      false, nullptr,
      fit_parameters("sglab-specular", src,
                     {{"nu_slope", S::nu_slope},
                      {"inflation", S::inflation, ColumnKind::nonnegative},
                      {"light_weight", S::light_weight, ColumnKind::nonnegative},
                      {"light_floor", S::light_floor, ColumnKind::nonnegative},
                      {"horizon_depth", S::horizon_depth, ColumnKind::unit_interval},
                      {"horizon_rate", S::horizon_rate, ColumnKind::nonnegative}}),
      [](auto a) { return specular_sglab(specular_input(a)); },
      [](auto a, auto p) {
        using T = std::decay_t<decltype(a[0])>;
        const SglabSpecularParams<T> c{T(p[0]), T(p[1]), T(p[2]), T(p[3]), T(p[4]), T(p[5])};
        return specular_sglab(specular_input(a), c);
      });
}

}  // namespace sglab
