// Shading from VSGLs (see vsgl_shading.hpp).
#include "sglab/render/vsgl_shading.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>

#include "sglab/clamped_cosine.hpp"
#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/reference.hpp"
#include "sglab/vsgl.hpp"

namespace sglab::render {
namespace {

// The name of the registry quantity whose methods shade the diffuse part.
constexpr std::string_view kClampedCosine = "clamped-cosine";

// λ_in floor for the forms that divide by λ (docs/math.md §10: the checked range starts at 1e-8).
constexpr double kMinDivisorSharpness = 1e-8;

struct Named {
  std::string_view name;
  DiffuseMethod method;
};
constexpr std::array<Named, 10> kSwitched = {{
    {"reference", DiffuseMethod::reference},
    {"punctual", DiffuseMethod::punctual},
    {"punctual-approx", DiffuseMethod::punctual_approx},
    {"sg-cosine", DiffuseMethod::sg_cosine},
    {"cosine-lobe-sg", DiffuseMethod::cosine_lobe_sg},
    {"hill-fitted", DiffuseMethod::hill_fitted},
    {"meder", DiffuseMethod::meder},
    {"tokuyoshi2022", DiffuseMethod::tokuyoshi2022},
    {"tokuyoshi2024", DiffuseMethod::tokuyoshi2024},
    {"sglab", DiffuseMethod::sglab},
}};

const Quantity& clamped_cosine_quantity() {
  const Quantity* q = find_quantity(kClampedCosine);
  if (!q) throw std::logic_error("registry has no clamped-cosine quantity");
  return *q;
}

// The shading loop, instantiated once per diffuse method (no per-evaluation dispatch).
template <class D>
VsglShading shade(const ShadingPoint& p, const VsglSet& set, const ShadingOptions& o, std::span<const char> visible,
                  const D& clamped_cosine) {
  VsglShading out;
  const bool diffuse_receiver = (p.diffuse_reflectance > 0).any();
  const bool glossy_receiver = o.specular && p.glossy();
  if (!diffuse_receiver && !glossy_receiver) return out;
  std::optional<VsglSpecularReceiver<double>> receiver;
  if (glossy_receiver) receiver = vsgl_specular_receiver<double>(p.normal, p.view, p.roughness);
  Rgb diffuse = Rgb::Zero();
  auto add = [&](const VsglPositionalSg<double>& pos, const VsglLobe& lobe) {
    const VsglIncomingSg<double> in = vsgl_incoming_sg<double>(pos, lobe.axis, lobe.sharpness);
    if (diffuse_receiver) diffuse += lobe.amplitude * vsgl_clamped_cosine(in, p.normal, clamped_cosine);
    if (receiver) {
      const VsglSpecularFactor<double> f = vsgl_specular(in, *receiver);
      out.specular += lobe.amplitude * (f.at_f0_zero + p.f0 * (f.at_f0_one - f.at_f0_zero));
    }
  };
  for (std::size_t k = 0; k < set.clusters.size(); ++k) {
    if (!visible.empty() && !visible[k]) continue;
    const VsglCluster& c = set.clusters[k];
    const VsglPositionalSg<double> pos =
        vsgl_positional_sg<double>(c.mean, c.variance, p.position, c.log_two_pi_variance);
    if (pos.empty) continue;
    if (c.has_diffuse) add(pos, c.diffuse);
    if (c.has_specular) add(pos, c.specular);
  }
  out.diffuse = diffuse * p.diffuse_reflectance / pi<double>();
  return out;
}

}  // namespace

std::vector<std::string> diffuse_method_names() {
  std::vector<std::string> out;
  for (const auto& m : clamped_cosine_quantity().methods) out.push_back(m.name);
  return out;
}

ShadingOptions shading_options(std::string_view diffuse_method, bool specular) {
  const Quantity& q = clamped_cosine_quantity();
  const Method* m = q.find(diffuse_method);
  if (!m) {
    std::string names;
    for (const auto& n : diffuse_method_names()) names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown diffuse method '" + std::string(diffuse_method) +
                                "' (clamped-cosine methods: " + names + ")");
  }
  ShadingOptions o;
  o.specular = specular;
  o.diffuse = DiffuseMethod::registry;
  o.registry_method = m;
  for (const auto& s : kSwitched)
    if (s.name == diffuse_method) o.diffuse = s.method;
  return o;
}

std::string diffuse_method_name(const ShadingOptions& o) {
  if (o.diffuse == DiffuseMethod::registry) return o.registry_method ? o.registry_method->name : "?";
  for (const auto& s : kSwitched)
    if (s.method == o.diffuse) return std::string(s.name);
  return "?";
}

VsglShading shade_vsgls_parts(const ShadingPoint& point, const VsglSet& set, const ShadingOptions& o,
                              std::span<const char> visible) {
  const double lambda_d = set.lambda_d;
  switch (o.diffuse) {
    case DiffuseMethod::reference:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_reference(l, c); });
    case DiffuseMethod::punctual:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_punctual(l, c); });
    case DiffuseMethod::punctual_approx:
      return shade(point, set, o, visible, [](double l, double c) {
        return clamped_cosine_punctual_approx(std::max(l, kMinDivisorSharpness), c);
      });
    case DiffuseMethod::sg_cosine:
    {
      // A(λ_d) ≈ π: the exact form's π/A(λ_d) factor becomes 1.
      const double a_pi_factor = o.sg_cosine_a_is_pi ? sg_integral(lambda_d) / pi<double>() : 1.0;
      return shade(point, set, o, visible, [lambda_d, a_pi_factor](double l, double c) {
        return a_pi_factor * clamped_cosine_sg_cosine(l, c, lambda_d);
      });
    }
    case DiffuseMethod::cosine_lobe_sg:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_cosine_lobe_sg(l, c); });
    case DiffuseMethod::hill_fitted:
      return shade(point, set, o, visible, [](double l, double c) {
        return clamped_cosine_hill_fitted(std::max(l, kMinDivisorSharpness), c);
      });
    case DiffuseMethod::meder:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_meder(l, c); });
    case DiffuseMethod::tokuyoshi2022:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_tokuyoshi2022(l, c); });
    case DiffuseMethod::tokuyoshi2024:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_tokuyoshi2024(l, c); });
    case DiffuseMethod::sglab:
      return shade(point, set, o, visible, [](double l, double c) { return clamped_cosine_sglab(l, c); });
    case DiffuseMethod::registry: {
      if (!o.registry_method) throw std::invalid_argument("ShadingOptions: diffuse == registry without a method");
      const Method* m = o.registry_method;
      return shade(point, set, o, visible, [m](double l, double c) {
        const std::array<double, 2> a{std::max(l, kMinDivisorSharpness), c};
        return m->eval_double(a);
      });
    }
  }
  return {};
}

}  // namespace sglab::render
