// Shading from VSGLs (see vsgl_shading.hpp).
#include "sglab/render/vsgl_shading.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "sglab/render/vsgl_specular_methods.hpp"
#include "sglab/vsgl.hpp"
#include "simd/render_table.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::render {

// The lobes of a set as arrays, in cluster order (diffuse lobe, then specular lobe). Outside the
// anonymous namespace: VsglShader::Data holds one.
struct LobeArrays {
  std::vector<double> mx, my, mz, variance, log_two_pi_variance, ax, ay, az, sharpness, amp_r, amp_g, amp_b;
  std::vector<Rgb> amplitude;
  std::vector<std::size_t> cluster;
  std::size_t size() const { return mx.size(); }
};

namespace {

// The name of the registry quantity whose methods shade the diffuse part.
constexpr std::string_view kClampedCosine = "clamped-cosine";

// λ_in floor for the forms that divide by λ (docs/math.md §10: the checked range starts at 1e-8).
constexpr double kMinDivisorSharpness = 1e-8;

const Quantity& clamped_cosine_quantity() {
  const Quantity* q = find_quantity(kClampedCosine);
  if (!q) throw std::logic_error("registry has no clamped-cosine quantity");
  return *q;
}

const Method& default_diffuse_method() {
  const Method* m = clamped_cosine_quantity().find(kDefaultDiffuseMethod);
  if (!m) throw std::logic_error("registry has no clamped-cosine method " + std::string(kDefaultDiffuseMethod));
  return *m;
}

// The lobes as the kernels see them.
simd_detail::LobeView view_of(const LobeArrays& a) {
  simd_detail::LobeView v;
  v.n = a.size();
  v.mx = a.mx.data(), v.my = a.my.data(), v.mz = a.mz.data(), v.variance = a.variance.data();
  v.log_two_pi_variance = a.log_two_pi_variance.data();
  v.ax = a.ax.data(), v.ay = a.ay.data(), v.az = a.az.data(), v.sharpness = a.sharpness.data();
  v.amp_r = a.amp_r.data(), v.amp_g = a.amp_g.data(), v.amp_b = a.amp_b.data();
  return v;
}

}  // namespace

struct VsglShader::Data {
  LobeArrays lobes;
  std::size_t clusters = 0;  // of the set (the visibility's stride per point)
  Method diffuse;            // bound where needed
  bool floor_sharpness = false;
  double diffuse_factor = 1;  // sg-cosine with A(λ_d) ≈ π
  ShadingOptions options;
};

VsglShader::VsglShader(VsglShader&&) noexcept = default;
VsglShader::~VsglShader() = default;
std::size_t VsglShader::lobes() const { return data_->lobes.size(); }
std::size_t VsglShader::clusters() const { return data_->clusters; }

VsglShader::VsglShader(const VsglSet& set, const ShadingOptions& o) : data_(std::make_unique<Data>()) {
  Data& d = *data_;
  d.options = o;
  const Method& method = o.diffuse ? *o.diffuse : default_diffuse_method();
  d.diffuse = method;
  // The VSGL set's λ_d (the sharpness of the VPLs' diffuse lobes) for the parameter of that role.
  const Parameter* lambda_d = vsgl_diffuse_sharpness(method);
  if (lambda_d && method.bind) {
    std::vector<double> values;
    for (const Parameter& p : method.parameters) values.push_back(&p == lambda_d ? set.lambda_d : p.published);
    d.diffuse = method.bind(values);
  }
  if (!d.diffuse.batch_double)
    throw std::invalid_argument("diffuse method '" + method.name + "' has no batch evaluator");
  d.floor_sharpness = bool(method.domain_error);
  // A(λ_d) ≈ π: the exact form's π/A(λ_d) factor becomes 1.
  if (o.sg_cosine_a_is_pi && lambda_d) d.diffuse_factor = sg_integral(set.lambda_d) / pi<double>();

  LobeArrays& a = d.lobes;
  d.clusters = set.clusters.size();
  auto add = [&](const VsglCluster& c, std::size_t k, const VsglLobe& lobe) {
    a.mx.push_back(c.mean.x());
    a.my.push_back(c.mean.y());
    a.mz.push_back(c.mean.z());
    a.variance.push_back(c.variance);
    a.log_two_pi_variance.push_back(std::isnan(c.log_two_pi_variance) ? std::log(two_pi<double>() * c.variance)
                                                                      : c.log_two_pi_variance);
    a.ax.push_back(lobe.axis.x());
    a.ay.push_back(lobe.axis.y());
    a.az.push_back(lobe.axis.z());
    a.sharpness.push_back(lobe.sharpness);
    a.amplitude.push_back(lobe.amplitude);
    a.amp_r.push_back(lobe.amplitude(0));
    a.amp_g.push_back(lobe.amplitude(1));
    a.amp_b.push_back(lobe.amplitude(2));
    a.cluster.push_back(k);
  };
  for (std::size_t k = 0; k < set.clusters.size(); ++k) {
    const VsglCluster& c = set.clusters[k];
    if (c.has_diffuse) add(c, k, c.diffuse);
    if (c.has_specular) add(c, k, c.specular);
  }
}

VsglShading VsglShader::shade(const ShadingPoint& p, std::span<const char> visible) const {
  if (!visible.empty() && visible.size() != clusters())
    throw std::invalid_argument("VsglShader::shade: visible has " + std::to_string(visible.size()) +
                                " entries, not one per cluster (" + std::to_string(clusters()) + ")");
  VsglShading out;
  shade_block(std::span<const ShadingPoint>(&p, 1), visible, std::span<VsglShading>(&out, 1));
  return out;
}

void VsglShader::shade(std::span<const ShadingPoint> points, std::span<VsglShading> out) const {
  shade(points, {}, out);
}

void VsglShader::shade(std::span<const ShadingPoint> points, std::span<const char> visible,
                       std::span<VsglShading> out) const {
  if (out.size() != points.size()) throw std::invalid_argument("VsglShader::shade: points and out differ in size");
  if (!visible.empty() && visible.size() != points.size() * clusters())
    throw std::invalid_argument("VsglShader::shade: visible has " + std::to_string(visible.size()) +
                                " entries, not points × clusters (" + std::to_string(points.size() * clusters()) + ")");
  // Blocks of points whose lobes make batches of about kRows rows (few lobes: many points), a
  // multiple of kLanes points (the loops run over a block's points: no scalar remainder).
  constexpr std::size_t kRows = 4096, kLanes = 16;
  const std::size_t per_block = std::max(kLanes, kRows / std::max<std::size_t>(1, lobes()) / kLanes * kLanes);
  for (std::size_t b = 0; b < points.size(); b += per_block) {
    const std::size_t m = std::min(per_block, points.size() - b);
    shade_block(points.subspan(b, m), visible.empty() ? visible : visible.subspan(b * clusters(), m * clusters()),
                out.subspan(b, m));
  }
}

namespace {

// The specular receivers of a block's glossy points as arrays (simd_detail::SpecularReceivers).
struct Receivers {
  std::vector<std::size_t> point;
  std::vector<double> tx, ty, tz, bx, by, bz, nx, ny, nz, wox, woy, woz, xx, xy, xz, yx, yy, yz, zx, zy, zz, eta_x,
      eta_y, lambda_s, ndf_amplitude, roughness, f0_r, f0_g, f0_b;
  std::array<std::vector<double>*, 29> all() {
    return {&tx,   &ty,   &tz,  &bx, &by, &bz, &nx, &ny, &nz,    &wox,   &woy,      &woz,           &xx,
            &xy,   &xz,   &yx,  &yy, &yz, &zx, &zy, &zz, &eta_x, &eta_y, &lambda_s, &ndf_amplitude, &roughness,
            &f0_r, &f0_g, &f0_b};
  }
  void clear() {
    point.clear();
    for (auto* v : all()) v->clear();
  }
  void push(std::size_t i, const VsglSpecularReceiver<double>& r, const Rgb& f0) {
    point.push_back(i);
    const double values[] = {r.tangent.x(),
                             r.tangent.y(),
                             r.tangent.z(),
                             r.bitangent.x(),
                             r.bitangent.y(),
                             r.bitangent.z(),
                             r.normal.x(),
                             r.normal.y(),
                             r.normal.z(),
                             r.view_local.x(),
                             r.view_local.y(),
                             r.view_local.z(),
                             r.lobe.x.x(),
                             r.lobe.x.y(),
                             r.lobe.x.z(),
                             r.lobe.y.x(),
                             r.lobe.y.y(),
                             r.lobe.y.z(),
                             r.lobe.z.x(),
                             r.lobe.z.y(),
                             r.lobe.z.z(),
                             r.lobe.eta_x,
                             r.lobe.eta_y,
                             r.lambda_s,
                             r.ndf_amplitude,
                             r.roughness,
                             f0(0),
                             f0(1),
                             f0(2)};
    std::size_t k = 0;
    for (auto* v : all()) v->push_back(values[k++]);
  }
  simd_detail::SpecularReceivers view() const {
    simd_detail::SpecularReceivers v;
    v.count = point.size();
    v.point = point.data();
    v.tx = tx.data(), v.ty = ty.data(), v.tz = tz.data(), v.bx = bx.data(), v.by = by.data(), v.bz = bz.data();
    v.nx = nx.data(), v.ny = ny.data(), v.nz = nz.data(), v.wox = wox.data(), v.woy = woy.data(), v.woz = woz.data();
    v.xx = xx.data(), v.xy = xy.data(), v.xz = xz.data(), v.yx = yx.data(), v.yy = yy.data(), v.yz = yz.data();
    v.zx = zx.data(), v.zy = zy.data(), v.zz = zz.data(), v.eta_x = eta_x.data(), v.eta_y = eta_y.data();
    v.lambda_s = lambda_s.data(), v.ndf_amplitude = ndf_amplitude.data(), v.roughness = roughness.data();
    v.f0_r = f0_r.data(), v.f0_g = f0_g.data(), v.f0_b = f0_b.data();
    return v;
  }
};

// Per thread, reused: no allocation per block once the arrays have grown.
struct Scratch {
  std::vector<double> px, py, pz, nx, ny, nz, diffuse;  // per point
  std::vector<double> sharpness, cosine, log_scale, scale, xi_x, xi_y, xi_z, d2, capped, mask, fallback,
      visible;  // per row
  std::vector<double> args_double, value_double;
  std::vector<float> args_float, value_float;
  std::vector<double> sum_r, sum_g, sum_b;  // per point (or per glossy point)
  Receivers receivers;                      // the glossy points
  std::vector<double> spec_fallback;        // per (lobe, glossy point)
  void resize(std::size_t points, std::size_t rows, bool single) {
    for (auto* v : {&px, &py, &pz, &nx, &ny, &nz, &diffuse, &sum_r, &sum_g, &sum_b}) v->resize(points);
    for (auto* v :
         {&sharpness, &cosine, &log_scale, &scale, &xi_x, &xi_y, &xi_z, &d2, &capped, &mask, &fallback, &visible})
      v->resize(rows);
    if (single) {
      args_float.resize(2 * rows);
      value_float.resize(rows);
    } else {
      args_double.resize(2 * rows);
      value_double.resize(rows);
    }
  }
};

// One block's shading: the lobes, the block's points and the incoming-SG rows as the kernels see
// them, and the per-thread arrays they fill.
struct BlockPass {
  const LobeArrays& a;
  std::span<const ShadingPoint> points;
  std::span<const char> visible;  // visible[i·clusters + c] for point i, cluster c; empty: all visible
  std::size_t clusters;
  std::span<VsglShading> out;
  Scratch& s;
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  std::size_t n = a.size(), m = points.size(), rows = n * m;
  simd_detail::LobeView lobes = view_of(a);
  simd_detail::PointBlock block{};
  simd_detail::IncomingRows in{};
  bool any_diffuse = false;

  // The block's points as arrays, and the lobes' visibility.
  void prepare(bool single) {
    s.resize(m, rows, single);
    for (std::size_t i = 0; i < m; ++i) {
      const ShadingPoint& p = points[i];
      s.px[i] = p.position.x(), s.py[i] = p.position.y(), s.pz[i] = p.position.z();
      s.nx[i] = p.normal.x(), s.ny[i] = p.normal.y(), s.nz[i] = p.normal.z();
      const bool diffuse_receiver = (p.diffuse_reflectance > 0).any();
      s.diffuse[i] = diffuse_receiver ? 1.0 : 0.0;
      any_diffuse = any_diffuse || diffuse_receiver;
    }
    if (visible.empty()) {
      std::fill(s.visible.begin(), s.visible.begin() + std::ptrdiff_t(rows), 1.0);
    } else {
      for (std::size_t j = 0; j < n; ++j) {
        const std::size_t c = a.cluster[j];
        double* row = s.visible.data() + j * m;
        for (std::size_t i = 0; i < m; ++i) row[i] = visible[i * clusters + c] ? 1.0 : 0.0;
      }
    }
    block = {m, s.px.data(), s.py.data(), s.pz.data(), s.nx.data(), s.ny.data(), s.nz.data(), s.diffuse.data()};
    in = {s.sharpness.data(), s.cosine.data(), s.log_scale.data(), s.xi_x.data(),    s.xi_y.data(), s.xi_z.data(),
          s.d2.data(),        s.capped.data(), s.mask.data(),      s.visible.data(), s.scale.data()};
  }

  // The incoming SG of every (lobe, point), row j·m + i, and the diffuse method's rows (λ, c).
  void incoming(bool single, bool floor_sharpness) {
    const double floor = floor_sharpness ? kMinDivisorSharpness : 0.0;
    const std::size_t capped = single ? t.incoming_f(lobes, block, floor, in, s.args_float.data())
                                      : t.incoming_d(lobes, block, floor, in, s.args_double.data());
    if (capped > 0)
      for (std::size_t r = 0; r < rows; ++r)
        if (s.capped[r] != 0)
          s.log_scale[r] += -(std::log(two_pi<double>()) + std::log(s.d2[r]) - std::log(kMaxPositionalSharpness));
  }

  // e^{log_scale} of every row (the rows' scale), for the diffuse sums and a registry method's specular sums.
  void scale() { t.scale_rows(rows, s.log_scale.data(), simd_detail::scaled_by_exp_direct_limit(), s.scale.data()); }

  // D(λ_in, ξ_in·n) for every row in one batch call; e^{log_scale}-weighted sums per point.
  void diffuse(const Method& method, double factor, bool single) {
    const std::size_t fallbacks =
        single ? (method.batch_float(s.args_float, 2, s.value_float),
                  t.weighted_sum_f(lobes, m, s.log_scale.data(), s.scale.data(), s.value_float.data(), s.mask.data(),
                                   factor, simd_detail::scaled_by_exp_direct_limit(), s.fallback.data(), s.sum_r.data(),
                                   s.sum_g.data(), s.sum_b.data()))
               : (method.batch_double(s.args_double, 2, s.value_double),
                  t.weighted_sum_d(lobes, m, s.log_scale.data(), s.scale.data(), s.value_double.data(), s.mask.data(),
                                   factor, simd_detail::scaled_by_exp_direct_limit(), s.fallback.data(), s.sum_r.data(),
                                   s.sum_g.data(), s.sum_b.data()));
    for (std::size_t i = 0; i < m; ++i) {
      if (s.diffuse[i] == 0) continue;
      Rgb sum(s.sum_r[i], s.sum_g[i], s.sum_b[i]);
      if (fallbacks > 0)
        for (std::size_t j = 0; j < n; ++j) {
          const std::size_t r = j * m + i;
          const double value = single ? double(s.value_float[r]) : s.value_double[r];
          if (s.fallback[r] != 0) sum += a.amplitude[j] * scaled_by_exp(s.log_scale[r], factor * value);
        }
      out[i].diffuse = sum * points[i].diffuse_reflectance / pi<double>();
    }
  }

  // A registry method (vsgl_specular_methods.cpp), on the block's rows as they are.
  void specular_with(const Method& method) {
    shade_specular_with_method(method, points,
                               {s.xi_x.data(), s.xi_y.data(), s.xi_z.data(), s.sharpness.data(), s.log_scale.data(),
                                s.scale.data(), s.visible.data()},
                               a.amplitude, out);
  }

  // The default ASG specular: the block's glossy points' specular receivers (vsgl.hpp) as arrays,
  // then every (lobe, glossy point) in one vectorized pass; rows outside its exponential's range
  // one by one.
  void specular_asg() {
    Receivers& g = s.receivers;
    g.clear();
    for (std::size_t i = 0; i < m; ++i)
      if (points[i].glossy())
        g.push(i, vsgl_specular_receiver<double>(points[i].normal, points[i].view, points[i].roughness), points[i].f0);
    const std::size_t gn = g.point.size();
    if (gn == 0) return;
    s.spec_fallback.resize(n * gn);
    for (auto* v : {&s.sum_r, &s.sum_g, &s.sum_b}) v->resize(std::max(m, gn));
    const std::size_t fallbacks = t.specular(lobes, m, in, g.view(), simd_detail::scaled_by_exp_direct_limit(),
                                             s.spec_fallback.data(), s.sum_r.data(), s.sum_g.data(), s.sum_b.data());
    for (std::size_t k = 0; k < gn; ++k) {
      const std::size_t i = g.point[k];
      Rgb specular(s.sum_r[k], s.sum_g[k], s.sum_b[k]);
      if (fallbacks > 0) {
        const VsglSpecularReceiver<double> receiver = vsgl_specular_receiver<double>(points[i].normal, points[i].view,
                                                                                     points[i].roughness);
        for (std::size_t j = 0; j < n; ++j) {
          if (s.spec_fallback[gn >= n ? j * gn + k : k * n + j] == 0) continue;
          const std::size_t r = j * m + i;
          VsglIncomingSg<double> sg;
          sg.axis = Vec3(s.xi_x[r], s.xi_y[r], s.xi_z[r]);
          sg.sharpness = s.sharpness[r];
          sg.log_scale = s.log_scale[r];
          const VsglSpecularFactor<double> f = vsgl_specular(sg, receiver);
          specular += a.amplitude[j] * (f.at_f0_zero + points[i].f0 * (f.at_f0_one - f.at_f0_zero));
        }
      }
      out[i].specular = specular;
    }
  }
};

}  // namespace

void VsglShader::shade_block(std::span<const ShadingPoint> points, std::span<const char> visible,
                             std::span<VsglShading> out) const {
  const Data& d = *data_;
  for (auto& o : out) o = VsglShading{};
  if (d.lobes.size() == 0 || points.empty()) return;
  const bool single = d.options.precision == Precision::single;
  thread_local Scratch scratch;
  BlockPass pass{d.lobes, points, visible, d.clusters, out, scratch};
  pass.prepare(single);
  pass.incoming(single, d.floor_sharpness);
  // (The built-in ASG specular takes e^{log_scale} in one exponential with its own: no scale.)
  if (pass.any_diffuse || (d.options.specular && d.options.specular_method)) pass.scale();
  if (pass.any_diffuse) pass.diffuse(d.diffuse, d.diffuse_factor, single);
  if (!d.options.specular) return;
  if (d.options.specular_method) pass.specular_with(*d.options.specular_method);
  else pass.specular_asg();
}

std::vector<std::string> diffuse_method_names() {
  std::vector<std::string> out;
  for (const auto& m : clamped_cosine_quantity().methods) out.push_back(m.name);
  return out;
}

ShadingOptions shading_options(std::string_view diffuse_method, bool specular) {
  const Method* m = clamped_cosine_quantity().find(diffuse_method);
  if (!m) {
    std::string names;
    for (const auto& n : diffuse_method_names()) names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown diffuse method " + quote(diffuse_method) +
                                " (clamped-cosine methods: " + names + ")");
  }
  ShadingOptions o;
  o.specular = specular;
  o.diffuse = std::shared_ptr<const Method>(std::shared_ptr<const Method>(), m);  // the registry's: not owned
  return o;
}

const Parameter* vsgl_diffuse_sharpness(const Method& m) {
  for (const Parameter& p : m.parameters)
    if (p.role == ParameterRole::vsgl_diffuse_sharpness) return &p;
  return nullptr;
}

std::string diffuse_method_name(const ShadingOptions& o) {
  return o.diffuse ? o.diffuse->name : std::string(kDefaultDiffuseMethod);
}

VsglShading shade_vsgls_parts(const ShadingPoint& point, const VsglSet& set, const ShadingOptions& o,
                              std::span<const char> visible) {
  return VsglShader(set, o).shade(point, visible);
}

}  // namespace sglab::render
