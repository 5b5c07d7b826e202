// Specular VSGL shading by a registry method (see vsgl_specular_methods.hpp).
#include "sglab/render/vsgl_specular_methods.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sglab/render/vsgl_shading.hpp"
#include "sglab/simd_specular_pair.hpp"
#include "sglab/vsgl.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::render {
namespace {

constexpr std::string_view kSpecular = "specular";

const Quantity& specular_quantity() {
  const Quantity* q = find_quantity(kSpecular);
  if (!q) throw std::logic_error("registry has no specular quantity");
  return *q;
}

// The receiver's local frame: n, and the tangent t towards the view (b = n × t).
struct Frame {
  Vec3 t, b, n;
  double view_cos;
};
Frame frame_of(const ShadingPoint& p) {
  Frame f;
  f.n = p.normal;
  const double vn = p.view.dot(p.normal);
  Vec3 t = p.view - vn * p.normal;
  const double len = t.norm();
  f.t = len > 0 ? Vec3(t / len) : Vec3(p.normal.unitOrthogonal());
  f.b = f.n.cross(f.t);
  f.view_cos = std::clamp(vn, 0.0, 1.0);
  return f;
}

}  // namespace

std::vector<std::string> specular_method_names() {
  std::vector<std::string> out{std::string(kDefaultSpecularMethod)};
  const Quantity& q = specular_quantity();
  for (const auto& m : q.methods)
    if (m.name != q.reference_method) out.push_back(m.name);
  return out;
}

const Method* find_specular_method(std::string_view name) {
  if (name == kDefaultSpecularMethod) return nullptr;
  const Quantity& q = specular_quantity();
  const Method* m = q.find(name);
  if (!m || m->name == q.reference_method) {
    std::string names;
    for (const auto& n : specular_method_names()) names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument(
        "unknown specular method " + quote(name) +
        (m ? " (the quadrature reference, 0.02–2 s per evaluation, is not a shading method)" : "") +
        " (specular methods: " + names + ")");
  }
  return m;
}

void shade_specular_with_method(const Method& method, std::span<const ShadingPoint> points, std::size_t lobes,
                                const IncomingLobes& in, std::span<const Rgb> amplitude,
                                const std::function<bool(std::size_t)>& active, std::span<VsglShading> out) {
  constexpr std::size_t kArity = simd::kSpecularPairArity;  // the `specular` columns but f0
  struct Scratch {
    std::vector<double> args, rows, at0, at1;
    std::vector<std::size_t> row;  // the (point, lobe) row of each evaluation
  };
  thread_local Scratch s;
  s.args.clear();
  s.row.clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ShadingPoint& p = points[i];
    if (!p.glossy()) continue;
    const Frame f = frame_of(p);
    for (std::size_t j = 0; j < lobes; ++j) {
      const std::size_t r = i * lobes + j;
      if (!active(r)) continue;
      const Vec3 xi(in.xi_x[r], in.xi_y[r], in.xi_z[r]);
      const double light_cos = std::clamp(xi.dot(f.n), -1.0, 1.0);
      const double azimuth = std::atan2(xi.dot(f.b), xi.dot(f.t));
      s.args.insert(s.args.end(), {p.roughness, in.sharpness[r], light_cos, f.view_cos, azimuth});
      s.row.push_back(r);
    }
  }
  const std::size_t n = s.row.size();
  if (n == 0) return;
  s.at0.resize(n);
  s.at1.resize(n);
  if (const simd::SpecularPairFn pair = simd::specular_pair_evaluator(method)) {
    pair(s.args, s.at0, s.at1);
  } else {  // rows at f0 = 0 and f0 = 1, one after the other
    s.rows.clear();
    for (std::size_t k = 0; k < n; ++k)
      for (double f0 : {0.0, 1.0}) {
        s.rows.insert(s.rows.end(), s.args.begin() + std::ptrdiff_t(k * kArity),
                      s.args.begin() + std::ptrdiff_t((k + 1) * kArity));
        s.rows.push_back(f0);
      }
    std::vector<double>& value = s.args;  // no longer needed: the values, in pairs
    value.resize(2 * n);
    method.batch_double(s.rows, kArity + 1, value);
    for (std::size_t k = 0; k < n; ++k) {
      s.at0[k] = value[2 * k];
      s.at1[k] = value[2 * k + 1];
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t r = s.row[k], i = r / lobes, j = r % lobes;
    const double at0 = scaled_by_exp(in.log_scale[r], s.at0[k]);
    const double at1 = scaled_by_exp(in.log_scale[r], s.at1[k]);
    out[i].specular += amplitude[j] * (at0 + points[i].f0 * (at1 - at0));
  }
}

}  // namespace sglab::render
