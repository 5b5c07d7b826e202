// Shading from VSGLs (see vsgl_shading.hpp).
#include "sglab/render/vsgl_shading.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "sglab/render/simd_dispatch.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"
#include "sglab/vsgl.hpp"

namespace sglab::render {
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

// The lobes of a set as arrays, in cluster order (diffuse lobe, then specular lobe).
struct LobeArrays {
  std::vector<double> mx, my, mz, variance, log_two_pi_variance, ax, ay, az, sharpness, amp_r, amp_g, amp_b;
  std::vector<Rgb> amplitude;
  std::vector<std::size_t> cluster;
  std::size_t size() const { return mx.size(); }
};

// Per point, per lobe: the incoming SG (Eq. 7) and its cosine with the normal.
struct Incoming {
  std::vector<double> sharpness, cosine, log_scale, xi_x, xi_y, xi_z, d2, capped;  // capped: 0 or 1
  void resize(std::size_t n) {
    for (auto* v : {&sharpness, &cosine, &log_scale, &xi_x, &xi_y, &xi_z, &d2, &capped}) v->resize(n);
  }
};

// vsgl_positional_sg and vsgl_incoming_sg (vsgl.hpp) for every lobe at once, on components. The
// log of the normalization where λ_σ is capped needs log(d²): those lobes are flagged (`capped`)
// and finished by the caller.
SGLAB_SIMD_CLONES void incoming_sgs(const LobeArrays& a, double px, double py, double pz, double nx, double ny,
                                    double nz, Incoming& out, std::size_t offset) {
  const std::size_t n = a.size();
  const double cap = kMaxPositionalSharpness;
  const double *mx = a.mx.data(), *my = a.my.data(), *mz = a.mz.data(), *var = a.variance.data(),
               *lt = a.log_two_pi_variance.data(), *ax = a.ax.data(), *ay = a.ay.data(), *az = a.az.data(),
               *lv = a.sharpness.data();
  double *lam = out.sharpness.data() + offset, *cosine = out.cosine.data() + offset, *ls = out.log_scale.data() + offset,
         *xx = out.xi_x.data() + offset, *xy = out.xi_y.data() + offset, *xz = out.xi_z.data() + offset,
         *dd = out.d2.data() + offset, *capped = out.capped.data() + offset;
#pragma omp simd
  for (std::size_t j = 0; j < n; ++j) {
    // The positional SG G(ω; ξ_μ, λ_σ)/(2πσ²).
    const double variance = var[j], log_two_pi_variance = lt[j];  // loaded unconditionally: vectorizes
    const double dx = mx[j] - px, dy = my[j] - py, dz = mz[j] - pz;
    const double d2 = dx * dx + dy * dy + dz * dz;
    // (Conditions are written out where used rather than kept as bools: that vectorizes.)
    const double inv = d2 > 0 ? 1 / std::sqrt(d2) : 0.0;
    const double ux = dx * inv, uy = dy * inv, uz = d2 > 0 ? dz * inv : 1.0;
    const double lambda_sigma = variance * cap > d2 ? d2 / variance : cap;  // capped: also σ² = 0
    // The product with G(ω; −ξ_v, λ_v) (sg.hpp sg_product).
    const double l1 = lv[j], l2 = lambda_sigma;
    const double a1x = -ax[j], a1y = -ay[j], a1z = -az[j];
    const double big = l1 > l2 ? l1 : l2;
    const double scale = big > kProductScaleSharpness ? 1 / big : 1.0;
    const double vx = (l1 * scale) * a1x + (l2 * scale) * ux, vy = (l1 * scale) * a1y + (l2 * scale) * uy,
                 vz = (l1 * scale) * a1z + (l2 * scale) * uz;
    // product_sharpness and product_log_amplitude (sg.hpp), branch-free so that the loop
    // vectorizes: past kProductScaleSharpness both divide through by s = max(λ1, λ2).
    const double c12 = std::min(std::max(a1x * ux + a1y * uy + a1z * uz, -1.0), 1.0);
    const double u1 = l1 * scale, u2 = l2 * scale, du = u1 - u2;
    const double q = du * du + 2 * u1 * u2 * (1 + c12);
    const double l3 = (q > 0 ? std::sqrt(q > 0 ? q : 0.0) : 0.0) / scale;
    const double denom = l3 * scale + u1 + u2;
    const double log_amplitude = denom > 0 ? -2 * u1 * u2 * (1 - c12) / denom / scale : 0.0;
    const double vnorm = std::sqrt(vx * vx + vy * vy + vz * vz);
    const double inv_v = vnorm > 0 && l3 > 0 ? 1 / vnorm : 0.0;
    const double ix = inv_v > 0 ? vx * inv_v : a1x, iy = inv_v > 0 ? vy * inv_v : a1y, iz = inv_v > 0 ? vz * inv_v : a1z;
    lam[j] = l3;
    xx[j] = ix;
    xy[j] = iy;
    xz[j] = iz;
    cosine[j] = std::min(std::max(ix * nx + iy * ny + iz * nz, -1.0), 1.0);
    // Empty (σ² = 0 at distance 0): no light; capped: log(1/(2πσ²)) is finished by the caller.
    const double at_cap = variance * cap > d2 ? 0.0 : 1.0;
    const double empty = d2 > 0 || variance > 0 ? 0.0 : 1.0;
    ls[j] = empty > 0 ? -std::numeric_limits<double>::infinity() : (at_cap > 0 ? 0.0 : -log_two_pi_variance) + log_amplitude;
    dd[j] = d2;
    capped[j] = empty > 0 ? 0.0 : at_cap;
  }
}

// The largest log_scale for which e^{log_scale}·x is formed directly (vsgl.hpp scaled_by_exp), and
// the smallest for which the vectorized exponential below is used; outside, scaled_by_exp is.
const double kDirectLimit = std::log(std::numeric_limits<double>::max()) / 2;
constexpr double kVectorExpFloor = -700;

// e^x for x in [kVectorExpFloor, kDirectLimit], on plain arithmetic so that loops calling it
// vectorize: x = k ln2 + r, |r| ≤ ln2/2 (Cody & Waite 1980: ln2 in two parts, the first with
// trailing zero bits so that k·ln2_hi is exact), e^r by its Taylor series to r¹³ (remainder
// < 0.4^14/14! ≈ 3e-17 relative), 2^k written into the exponent bits. k is rounded with the
// 1.5·2^52 trick, which leaves k in the low bits of the sum. Within 2 ulp of std::exp.
[[gnu::always_inline]] inline double exp_in_range(double x) {
  constexpr double log2e = 1.4426950408889634074;   // 1/ln 2
  constexpr double ln2_hi = 6.93147180369123816490e-01;  // ln 2, upper part (fdlibm's e_exp.c)
  constexpr double ln2_lo = 1.90821492927058770002e-10;  // ln 2 − ln2_hi
  constexpr double round_shift = 6755399441055744.0;      // 1.5·2^52
  const double t = x * log2e + round_shift;
  const double k = t - round_shift;
  const double r = (x - k * ln2_hi) - k * ln2_lo;
  // Horner, 1/13! … 1/0! (written out: a loop over an array of them does not vectorize).
  double p = 1.0 / 6227020800.0;
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  const std::uint64_t k_bits = std::bit_cast<std::uint64_t>(t) - std::bit_cast<std::uint64_t>(round_shift);
  return p * std::bit_cast<double>((k_bits + 1023) << 52);
}

// Σ_j amplitude_j · e^{log_scale_j} · factor · value_j over the lobes with mask_j = 1, as
// scaled_by_exp forms each term; lobes whose log_scale is outside the vectorized range (and not
// −∞: no light) get fallback_j = 1 and are left to the caller.
SGLAB_SIMD_CLONES void weighted_sum(std::size_t n, const double* log_scale, const double* value, const double* mask,
                                    const double* amp_r, const double* amp_g, const double* amp_b, double factor,
                                    double* fallback, double* out) {
  double s0 = 0, s1 = 0, s2 = 0;
#pragma omp simd reduction(+ : s0, s1, s2)
  for (std::size_t j = 0; j < n; ++j) {
    const double ls = log_scale[j], x = factor * value[j], m = mask[j];
    // (Single comparisons combined as 0/1 factors, not &&: that vectorizes.)
    const double in_range = (ls > kVectorExpFloor ? 1.0 : 0.0) * (ls < kDirectLimit ? 1.0 : 0.0);
    const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * (x != 0 ? 1.0 : 0.0) * m;
    fallback[j] = lit * (1 - in_range);
    const double w = lit * in_range > 0 ? exp_in_range(in_range > 0 ? ls : 0.0) * x : 0.0;
    s0 += amp_r[j] * w;
    s1 += amp_g[j] * w;
    s2 += amp_b[j] * w;
  }
  out[0] = s0;
  out[1] = s1;
  out[2] = s2;
}

}  // namespace

struct VsglShader::Data {
  LobeArrays lobes;
  Method diffuse;          // bound where needed
  bool floor_sharpness = false;
  double diffuse_factor = 1;  // sg-cosine with A(λ_d) ≈ π
  ShadingOptions options;
};

VsglShader::VsglShader(VsglShader&&) noexcept = default;
VsglShader::~VsglShader() = default;
std::size_t VsglShader::lobes() const { return data_->lobes.size(); }

VsglShader::VsglShader(const VsglSet& set, const ShadingOptions& o) : data_(std::make_unique<Data>()) {
  Data& d = *data_;
  d.options = o;
  const Method& method = o.diffuse ? *o.diffuse : default_diffuse_method();
  d.diffuse = method;
  // A parameter named lambda_d is the VSGL set's λ_d (the sharpness of the VPLs' diffuse lobes).
  const auto lambda_d = std::find_if(method.parameters.begin(), method.parameters.end(),
                                     [](const Parameter& p) { return p.name == "lambda_d"; });
  if (lambda_d != method.parameters.end() && method.bind) {
    std::vector<double> values;
    for (const Parameter& p : method.parameters) values.push_back(&p == &*lambda_d ? set.lambda_d : p.published);
    d.diffuse = method.bind(values);
  }
  if (!d.diffuse.batch_double) throw std::invalid_argument("diffuse method '" + method.name + "' has no batch evaluator");
  d.floor_sharpness = bool(method.domain_error);
  // A(λ_d) ≈ π: the exact form's π/A(λ_d) factor becomes 1.
  if (o.sg_cosine_a_is_pi && method.name == "sg-cosine") d.diffuse_factor = sg_integral(set.lambda_d) / pi<double>();

  LobeArrays& a = d.lobes;
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
  VsglShading out;
  shade_block(std::span<const ShadingPoint>(&p, 1), visible, std::span<VsglShading>(&out, 1));
  return out;
}

void VsglShader::shade(std::span<const ShadingPoint> points, std::span<VsglShading> out) const {
  if (out.size() != points.size()) throw std::invalid_argument("VsglShader::shade: points and out differ in size");
  // Blocks of points whose lobes make batches of about kRows rows (few lobes: many points).
  constexpr std::size_t kRows = 512;
  const std::size_t per_block = std::max<std::size_t>(1, kRows / std::max<std::size_t>(1, lobes()));
  for (std::size_t b = 0; b < points.size(); b += per_block) {
    const std::size_t m = std::min(per_block, points.size() - b);
    shade_block(points.subspan(b, m), {}, out.subspan(b, m));
  }
}

void VsglShader::shade_block(std::span<const ShadingPoint> points, std::span<const char> visible,
                             std::span<VsglShading> out) const {
  const Data& d = *data_;
  const LobeArrays& a = d.lobes;
  const std::size_t n = a.size(), rows = n * points.size();
  for (auto& o : out) o = VsglShading{};
  if (n == 0) return;

  struct Scratch {
    Incoming in;
    std::vector<double> args, value, mask, fallback;
  };
  thread_local Scratch s;
  s.in.resize(rows);
  s.args.resize(2 * rows);
  s.value.resize(rows);
  s.mask.resize(rows);
  s.fallback.resize(rows);
  // The incoming SG of every (point, lobe), row i·n + j.
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ShadingPoint& p = points[i];
    incoming_sgs(a, p.position.x(), p.position.y(), p.position.z(), p.normal.x(), p.normal.y(), p.normal.z(), s.in, i * n);
  }
  for (std::size_t r = 0; r < rows; ++r)
    if (s.in.capped[r] != 0)
      s.in.log_scale[r] += -(std::log(two_pi<double>()) + std::log(s.in.d2[r]) - std::log(kMaxPositionalSharpness));
  auto active = [&](std::size_t r) {
    return s.in.log_scale[r] > -std::numeric_limits<double>::infinity() && (visible.empty() || visible[a.cluster[r % n]]);
  };

  // D(λ_in, ξ_in·n) for every (point, lobe) in one batch call (rows of (λ, c)); points that reflect
  // no diffuse light get masked rows.
  bool any_diffuse = false;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool diffuse_receiver = (points[i].diffuse_reflectance > 0).any();
    any_diffuse = any_diffuse || diffuse_receiver;
    for (std::size_t r = i * n; r < (i + 1) * n; ++r) {
      const bool on = diffuse_receiver && active(r);
      const double l = s.in.sharpness[r];
      s.args[2 * r] = on ? (d.floor_sharpness ? std::max(l, kMinDivisorSharpness) : l) : 1.0;
      s.args[2 * r + 1] = on ? s.in.cosine[r] : 0.0;
      s.mask[r] = on ? 1.0 : 0.0;
    }
  }
  if (any_diffuse) d.diffuse.batch_double(s.args, 2, s.value);

  for (std::size_t i = 0; i < points.size(); ++i) {
    const ShadingPoint& p = points[i];
    const std::size_t r0 = i * n;
    if ((p.diffuse_reflectance > 0).any()) {
      double sum[3];
      weighted_sum(n, s.in.log_scale.data() + r0, s.value.data() + r0, s.mask.data() + r0, a.amp_r.data(),
                   a.amp_g.data(), a.amp_b.data(), d.diffuse_factor, s.fallback.data() + r0, sum);
      Rgb diffuse(sum[0], sum[1], sum[2]);
      for (std::size_t j = 0; j < n; ++j)
        if (s.fallback[r0 + j] != 0)
          diffuse += a.amplitude[j] * scaled_by_exp(s.in.log_scale[r0 + j], d.diffuse_factor * s.value[r0 + j]);
      out[i].diffuse = diffuse * p.diffuse_reflectance / pi<double>();
    }
    if (d.options.specular && !d.options.specular_method && p.glossy()) {
      const VsglSpecularReceiver<double> receiver = vsgl_specular_receiver<double>(p.normal, p.view, p.roughness);
      for (std::size_t j = 0; j < n; ++j) {
        if (!active(r0 + j)) continue;
        VsglIncomingSg<double> in;
        in.axis = Vec3(s.in.xi_x[r0 + j], s.in.xi_y[r0 + j], s.in.xi_z[r0 + j]);
        in.sharpness = s.in.sharpness[r0 + j];
        in.log_scale = s.in.log_scale[r0 + j];
        const VsglSpecularFactor<double> f = vsgl_specular(in, receiver);
        out[i].specular += a.amplitude[j] * (f.at_f0_zero + p.f0 * (f.at_f0_one - f.at_f0_zero));
      }
    }
  }
  if (d.options.specular && d.options.specular_method)  // a registry method (vsgl_specular_methods.cpp)
    shade_specular_with_method(*d.options.specular_method, points, n,
                               {s.in.xi_x.data(), s.in.xi_y.data(), s.in.xi_z.data(), s.in.sharpness.data(), s.in.log_scale.data()},
                               a.amplitude, active, out);
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
    throw std::invalid_argument("unknown diffuse method '" + std::string(diffuse_method) +
                                "' (clamped-cosine methods: " + names + ")");
  }
  ShadingOptions o;
  o.specular = specular;
  o.diffuse = m;
  return o;
}

std::string diffuse_method_name(const ShadingOptions& o) {
  return o.diffuse ? o.diffuse->name : std::string(kDefaultDiffuseMethod);
}

VsglShading shade_vsgls_parts(const ShadingPoint& point, const VsglSet& set, const ShadingOptions& o,
                              std::span<const char> visible) {
  return VsglShader(set, o).shade(point, visible);
}

}  // namespace sglab::render
