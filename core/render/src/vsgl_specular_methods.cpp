// Specular VSGL shading by a registry method (see vsgl_specular_methods.hpp).
#include "sglab/render/vsgl_specular_methods.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sglab/render/vsgl_shading.hpp"
#include "simd/render_table.hpp"
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

void shade_specular_with_method(const Method& method, std::span<const ShadingPoint> points, const IncomingLobes& in,
                                std::span<const Rgb> amplitude, std::span<VsglShading> out) {
  const std::size_t m = points.size(), lobes = amplitude.size();
  // Per thread, reused: no allocation per block once the arrays have grown.
  struct Scratch {
    std::vector<std::size_t> point;
    std::vector<double> tx, ty, tz, bx, by, bz, nx, ny, nz, view_cos, roughness, f0_r, f0_g, f0_b;  // per glossy point
    std::vector<double> amp_r, amp_g, amp_b;                                                        // per lobe
    std::vector<double> columns[4], at0, at1, fallback, sum_r, sum_g, sum_b, rows;                  // per row
  };
  thread_local Scratch s;
  s.point.clear();
  for (auto* v : {&s.tx, &s.ty, &s.tz, &s.bx, &s.by, &s.bz, &s.nx, &s.ny, &s.nz, &s.view_cos, &s.roughness, &s.f0_r,
                  &s.f0_g, &s.f0_b})
    v->clear();
  for (std::size_t i = 0; i < m; ++i) {
    const ShadingPoint& p = points[i];
    if (!p.glossy()) continue;
    const Frame f = frame_of(p);
    s.point.push_back(i);
    const double values[] = {f.t.x(), f.t.y(), f.t.z(),    f.b.x(),     f.b.y(), f.b.z(), f.n.x(),
                             f.n.y(), f.n.z(), f.view_cos, p.roughness, p.f0(0), p.f0(1), p.f0(2)};
    std::size_t k = 0;
    for (auto* v : {&s.tx, &s.ty, &s.tz, &s.bx, &s.by, &s.bz, &s.nx, &s.ny, &s.nz, &s.view_cos, &s.roughness, &s.f0_r,
                    &s.f0_g, &s.f0_b})
      v->push_back(values[k++]);
  }
  const std::size_t gn = s.point.size(), n = lobes * gn;
  if (n == 0) return;
  s.amp_r.resize(lobes), s.amp_g.resize(lobes), s.amp_b.resize(lobes);
  for (std::size_t j = 0; j < lobes; ++j)
    s.amp_r[j] = amplitude[j](0), s.amp_g[j] = amplitude[j](1), s.amp_b[j] = amplitude[j](2);
  for (auto* v : {&s.at0, &s.at1, &s.fallback}) v->resize(n);
  for (auto& c : s.columns) c.resize(n);
  for (auto* v : {&s.sum_r, &s.sum_g, &s.sum_b}) v->resize(gn);
  const simd_detail::MethodReceivers receivers{
      gn,           s.point.data(),    s.tx.data(),        s.ty.data(),   s.tz.data(),
      s.bx.data(),  s.by.data(),       s.bz.data(),        s.nx.data(),   s.ny.data(),
      s.nz.data(),  s.view_cos.data(), s.roughness.data(), s.f0_r.data(), s.f0_g.data(),
      s.f0_b.data()};
  // The rows as the kernels take them (IncomingRows: the incoming kernel's output, hence non-const
  // pointers); method_rows and method_sum only read them.
  simd_detail::IncomingRows rows{};
  rows.sharpness = const_cast<double*>(in.sharpness), rows.log_scale = const_cast<double*>(in.log_scale);
  rows.xi_x = const_cast<double*>(in.xi_x), rows.xi_y = const_cast<double*>(in.xi_y);
  rows.xi_z = const_cast<double*>(in.xi_z), rows.visible = in.visible, rows.scale = const_cast<double*>(in.scale);
  const simd_detail::MethodColumns columns{s.columns[0].data(), s.columns[1].data(), s.columns[2].data(),
                                           s.columns[3].data()};
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  t.method_rows(lobes, m, rows, receivers, columns);
  if (const simd::SpecularPairColumnsFn pair = simd::specular_pair_columns_evaluator(method)) {
    // Each glossy point's part of the method once, for all the lobes.
    pair({gn, s.roughness.data(), s.view_cos.data(), columns.light_sharpness, columns.light_cos, columns.axis_t,
          columns.axis_b},
         lobes, s.at0.data(), s.at1.data());
  } else {  // rows at f0 = 0 and f0 = 1, one after the other, the azimuth as an angle
    constexpr std::size_t kArity = simd::kSpecularPairArity + 1;  // the `specular` columns
    s.rows.resize(2 * n * kArity);
    for (std::size_t k = 0; k < n; ++k) {
      const double azimuth = std::atan2(columns.axis_b[k], columns.axis_t[k]);
      for (std::size_t f = 0; f < 2; ++f) {
        double* row = s.rows.data() + (2 * k + f) * kArity;
        row[0] = s.roughness[k % gn], row[1] = columns.light_sharpness[k], row[2] = columns.light_cos[k];
        row[3] = s.view_cos[k % gn], row[4] = azimuth, row[5] = double(f);
      }
    }
    std::vector<double>& value = s.fallback;  // not needed yet: the values, in pairs
    value.resize(2 * n);
    method.batch_double(s.rows, kArity, value);
    for (std::size_t k = 0; k < n; ++k) {
      s.at0[k] = value[2 * k];
      s.at1[k] = value[2 * k + 1];
    }
  }
  s.fallback.resize(n);
  const std::size_t fallbacks = t.method_sum(lobes, s.amp_r.data(), s.amp_g.data(), s.amp_b.data(), m, rows, receivers,
                                             s.at0.data(), s.at1.data(), simd_detail::scaled_by_exp_direct_limit(),
                                             s.fallback.data(), s.sum_r.data(), s.sum_g.data(), s.sum_b.data());
  for (std::size_t g = 0; g < gn; ++g) {
    const std::size_t i = s.point[g];
    Rgb specular(s.sum_r[g], s.sum_g[g], s.sum_b[g]);
    if (fallbacks > 0)
      for (std::size_t j = 0; j < lobes; ++j) {
        const std::size_t k = j * gn + g;
        if (s.fallback[k] == 0) continue;
        const double ls = in.log_scale[j * m + i];
        const double at0 = scaled_by_exp(ls, s.at0[k]), at1 = scaled_by_exp(ls, s.at1[k]);
        specular += amplitude[j] * (at0 + points[i].f0 * (at1 - at0));
      }
    out[i].specular += specular;
  }
}

}  // namespace sglab::render
