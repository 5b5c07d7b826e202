// VSGL shading's loops: the incoming SGs, the built-in ASG specular, a registry `specular` method's rows and sums.
// One part of render_kernels.hpp, which the units of each instruction set include (everything
// here has internal linkage: render_kernels.hpp).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "render_kernels_visibility.hpp"

namespace sglab::render::simd_detail {
namespace {

// ---- VSGL shading -----------------------------------------------------------------------------

// vsgl_positional_sg and vsgl_incoming_sg (vsgl.hpp) for every (lobe, point), lobe-major, each
// inner loop vectorized over the block's points; sg.hpp's sg_product, product_sharpness and
// product_log_amplitude branch-free (past kProductScale both divide through by s = max(λ1, λ2)).
template <class T>
std::size_t incoming(const LobeView& a, const PointBlock& b, double sharpness_floor, IncomingRows& out, T* args) {
  const std::size_t m = b.m;
  const double *px = b.px, *py = b.py, *pz = b.pz, *pnx = b.nx, *pny = b.ny, *pnz = b.nz, *pd = b.diffuse;
  std::size_t capped_rows = 0;
  for (std::size_t j = 0; j < a.n; ++j) {
    const double variance = a.variance[j], log_two_pi_variance = a.log_two_pi_variance[j];
    const double mx = a.mx[j], my = a.my[j], mz = a.mz[j], l1 = a.sharpness[j];
    const double a1x = -a.ax[j], a1y = -a.ay[j], a1z = -a.az[j];
    // sg_product's rescaling past kProductScale by s = max(λ_v, λ_σ): λ_σ ≤ kCap < kProductScale,
    // so it is needed exactly when λ_v > kProductScale, and s = λ_v.
    static_assert(kCap < kProductScale);
    const double s = l1 > kProductScale ? l1 : 1.0, scale = l1 > kProductScale ? 1 / l1 : 1.0;
    const std::size_t r0 = j * m;
    double *lam = out.sharpness + r0, *cosine = out.cosine + r0, *ls = out.log_scale + r0, *xx = out.xi_x + r0,
           *xy = out.xi_y + r0, *xz = out.xi_z + r0, *dd = out.d2 + r0, *capped = out.capped + r0,
           *mask = out.mask + r0;
    const double* visible = out.visible + r0;
    T* arg = args + 2 * r0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : count)
    for (std::size_t i = 0; i < m; ++i) {
      // The positional SG G(ω; ξ_μ, λ_σ)/(2πσ²).
      const double dx = mx - px[i], dy = my - py[i], dz = mz - pz[i];
      const double d2 = dx * dx + dy * dy + dz * dz;
      const double inv = d2 > 0 ? 1 / sqrt_(d2) : 0.0;
      const double ux = dx * inv, uy = dy * inv, uz = d2 > 0 ? dz * inv : 1.0;
      const double lambda_sigma = variance * kCap > d2 ? d2 / variance : kCap;  // capped: also σ² = 0
      // The product with G(ω; −ξ_v, λ_v) (s and scale: hoisted above).
      const double l2 = lambda_sigma;
      const double u1 = l1 * scale, u2 = l2 * scale;
      const double vx = u1 * a1x + u2 * ux, vy = u1 * a1y + u2 * uy, vz = u1 * a1z + u2 * uz;
      const double c12 = clamp1(a1x * ux + a1y * uy + a1z * uz);
      const double du = u1 - u2;
      const double q = du * du + 2 * u1 * u2 * (1 + c12);
      const double l3_scaled = q > 0 ? sqrt_(q > 0 ? q : 0.0) : 0.0, l3 = l3_scaled * s;
      const double denom = l3_scaled + u1 + u2;
      const double log_amplitude = denom > 0 ? -2 * u1 * u2 * (1 - c12) / denom * s : 0.0;
      const double vnorm = sqrt_(vx * vx + vy * vy + vz * vz);
      const double inv_v = vnorm > 0 && l3 > 0 ? 1 / vnorm : 0.0;
      const double ix = inv_v > 0 ? vx * inv_v : a1x, iy = inv_v > 0 ? vy * inv_v : a1y,
                   iz = inv_v > 0 ? vz * inv_v : a1z;
      const double c = clamp1(ix * pnx[i] + iy * pny[i] + iz * pnz[i]);
      lam[i] = l3;
      xx[i] = ix;
      xy[i] = iy;
      xz[i] = iz;
      cosine[i] = c;
      // Empty (σ² = 0 at distance 0): no light; capped: log(1/(2πσ²)) is finished by the caller.
      const double at_cap = variance * kCap > d2 ? 0.0 : 1.0;
      const double empty = d2 > 0 || variance > 0 ? 0.0 : 1.0;
      ls[i] = empty > 0 ? -std::numeric_limits<double>::infinity()
                        : (at_cap > 0 ? 0.0 : -log_two_pi_variance) + log_amplitude;
      dd[i] = d2;
      const double cap_flag = empty > 0 ? 0.0 : at_cap;
      capped[i] = cap_flag;
      count += cap_flag > 0 ? 1 : 0;
      // The diffuse method's row.
      const double on = pd[i] * visible[i] * (1 - empty);
      const double l = l3 > sharpness_floor ? l3 : sharpness_floor;
      arg[2 * i] = on > 0 ? T(l) : T(1);
      arg[2 * i + 1] = on > 0 ? T(c) : T(0);
      mask[i] = on;
    }
    capped_rows += count;
  }
  return capped_rows;
}

// The smallest log_scale for which the vectorized exponential below is used (the largest is the
// caller's direct_limit); outside, the caller uses scaled_by_exp.
constexpr double kVectorExpFloor = -700;

// e^x for x in [kVectorExpFloor, kDirectLimit], on plain arithmetic so that loops calling it
// vectorize: x = k ln2 + r, |r| ≤ ln2/2 (Cody & Waite 1980: ln2 in two parts, the first with
// trailing zero bits so that k·ln2_hi is exact), e^r by its Taylor series to r¹³ (remainder
// < 0.4^14/14! ≈ 3e-17 relative), 2^k written into the exponent bits. k is rounded with the
// 1.5·2^52 trick, which leaves k in the low bits of the sum. Within 2 ulp of std::exp.
[[gnu::always_inline]] inline double exp_in_range(double x) {
  constexpr double log2e = 1.4426950408889634074;        // 1/ln 2
  constexpr double ln2_hi = 6.93147180369123816490e-01;  // ln 2, upper part (fdlibm's e_exp.c)
  constexpr double ln2_lo = 1.90821492927058770002e-10;  // ln 2 − ln2_hi
  constexpr double round_shift = 6755399441055744.0;     // 1.5·2^52
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

// ScaleRowsFn (render_table.hpp): e^{log_scale} of every row once, which the diffuse sums and a
// registry method's specular sums both take.
void scale_rows(std::size_t rows, const double* log_scale, double direct_limit, double* scale) {
#pragma omp simd
  for (std::size_t r = 0; r < rows; ++r) {
    const double ls = log_scale[r];
    const bool in_range = ls > kVectorExpFloor && ls < direct_limit;
    scale[r] = in_range ? exp_in_range(in_range ? ls : 0.0) : 0.0;
  }
}

template <class T>
std::size_t weighted_sum(const LobeView& a, std::size_t m, const double* log_scale, const double* scale, const T* value,
                         const double* mask, double factor, double direct_limit, double* fallback, double* out_r,
                         double* out_g, double* out_b) {
  for (std::size_t i = 0; i < m; ++i) out_r[i] = out_g[i] = out_b[i] = 0;
  std::size_t fallbacks = 0;
  for (std::size_t j = 0; j < a.n; ++j) {
    const double ar = a.amp_r[j], ag = a.amp_g[j], ab = a.amp_b[j];
    const std::size_t r0 = j * m;
    const double *lsj = log_scale + r0, *sj = scale + r0, *mj = mask + r0;
    const T* vj = value + r0;
    double* fj = fallback + r0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : count)
    for (std::size_t i = 0; i < m; ++i) {
      const double ls = lsj[i], x = factor * double(vj[i]);
      const double in_range = (ls > kVectorExpFloor ? 1.0 : 0.0) * (ls < direct_limit ? 1.0 : 0.0);
      const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * (x != 0 ? 1.0 : 0.0) * mj[i];
      const double fb = lit * (1 - in_range);
      fj[i] = fb;
      count += fb > 0 ? 1 : 0;
      const double w = lit * in_range > 0 ? sj[i] * x : 0.0;
      out_r[i] += ar * w;
      out_g[i] += ag * w;
      out_b[i] += ab * w;
    }
    fallbacks += count;
  }
  return fallbacks;
}

// vsgl_specular (vsgl.hpp) of lobe j's row i (the incoming SG) at glossy point g: asg_sg_product_two_vsgls
// (asg.hpp), scaled_by_exp, the product axis ξ_m (sg.hpp sg_product) and brdf_factor_m (brdf.hpp)
// at f0 = 0 and 1, on components and branch-free; returns the lobe's contribution per channel
// without its amplitude's. e^{log_scale} and the ASG's exponential are taken as one exponential
// of their sum (the same value to rounding). `fallback` = 1: the exponent is outside the
// vectorized exponential's range (the contribution is then 0 here and left to the caller).
struct SpecularTerm {
  double r, g, b, fallback;
};
[[gnu::always_inline]] inline SpecularTerm specular_term(const SpecularReceivers& p, std::size_t g, double ls, double l,
                                                         double wx, double wy, double wz, double visible,
                                                         double direct_limit) {
  // ξ_in in the local frame.
  const double x0 = wx * p.tx[g] + wy * p.ty[g] + wz * p.tz[g];
  const double x1 = wx * p.bx[g] + wy * p.by[g] + wz * p.bz[g];
  const double x2 = wx * p.nx[g] + wy * p.ny[g] + wz * p.nz[g];
  // ∫ Ĝ G ≈ π Ĝ(ξ; ηxν/(ηx+ν), ηyν/(ηy+ν))/√((ηx+ν)(ηy+ν)), ν = λ/2 (reduced_bandwidth).
  const double nu = l / 2, ex = p.eta_x[g], ey = p.eta_y[g];
  const double lox = ex <= nu ? ex : nu, hix = ex <= nu ? nu : ex, loy = ey <= nu ? ey : nu, hiy = ey <= nu ? nu : ey;
  const double rx = lox > 0 ? lox / (1 + lox / hix) : 0.0, ry = loy > 0 ? loy / (1 + loy / hiy) : 0.0;
  const double zx = p.zx[g], zy = p.zy[g], zz = p.zz[g];
  const double cz = x0 * zx + x1 * zy + x2 * zz;
  const double cx = x0 * p.xx[g] + x1 * p.xy[g] + x2 * p.xz[g];
  const double cy = x0 * p.yx[g] + x1 * p.yy[g] + x2 * p.yz[g];
  const double exponent = ls + (-rx * cx * cx - ry * cy * cy);
  const double factor = cz * (kPi / (sqrt_(ex + nu) * sqrt_(ey + nu))) * p.ndf_amplitude[g];
  const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * (cz > 0 ? 1.0 : 0.0) * visible;
  const double in_range = (exponent > kVectorExpFloor ? 1.0 : 0.0) * (ls < direct_limit ? 1.0 : 0.0);
  const double scale = lit * in_range > 0 ? exp_in_range(in_range > 0 ? exponent : 0.0) * factor : 0.0;
  // ξ_m: the axis of the product of G(ξ_in, λ) and G(ξ_z, λ_s).
  const double ls2 = p.lambda_s[g];
  const double big = l > ls2 ? l : ls2, sc = big > kProductScale ? 1 / big : 1.0;
  const double u1 = l * sc, u2 = ls2 * sc;
  const double vx = u1 * x0 + u2 * zx, vy = u1 * x1 + u2 * zy, vz = u1 * x2 + u2 * zz;
  const double c12 = clamp1(cz), du = u1 - u2, q = du * du + 2 * u1 * u2 * (1 + c12);
  const double vnorm = sqrt_(vx * vx + vy * vy + vz * vz);
  const double inv_v = vnorm > 0 && q > 0 ? 1 / vnorm : 0.0;
  const double mx = inv_v > 0 ? vx * inv_v : x0, my = inv_v > 0 ? vy * inv_v : x1, mz = inv_v > 0 ? vz * inv_v : x2;
  // M(ξ_m) = F·V·⟨ξ_m·n⟩ with F = m⁵ (f0 = 0) and 1 (f0 = 1); the half vector as brdf.hpp's.
  const double wox = p.wox[g], woy = p.woy[g], woz = p.woz[g], alpha = p.roughness[g];
  double hx = wox + mx, hy = woy + my, hz = woz + mz;
  const double hn = sqrt_(hx * hx + hy * hy + hz * hz);
  const double inv_h = hn > 0 ? 1 / hn : 0.0;
  hx = hn > 0 ? hx * inv_h : 0.0;
  hy = hn > 0 ? hy * inv_h : 0.0;
  hz = hn > 0 ? hz * inv_h : 1.0;
  const double coh = wox * hx + woy * hy + woz * hz;
  const double c = coh < 0 ? 0.0 : (coh > 1 ? 1.0 : coh), mm = 1 - c, m2 = mm * mm, m5 = m2 * m2 * mm;
  const double a2 = alpha * alpha, co = woz, ci = mz;
  const double cco = clamp1(co), cci = clamp1(ci);
  const double so = sqrt_(co * co + a2 * ((1 - cco) * (1 + cco))), si = sqrt_(ci * ci + a2 * ((1 - cci) * (1 + cci)));
  const double den = ci * so + co * si;
  const double vis = ci > 0 && co >= 0 && den > 0 ? 1 / (2 * den) : 0.0;
  const double one = scale * (vis * ci), zero = scale * (m5 * vis * ci);
  return {zero + p.f0_r[g] * (one - zero), zero + p.f0_g[g] * (one - zero), zero + p.f0_b[g] * (one - zero),
          lit * (1 - in_range)};
}

// Every (lobe, glossy point), each point's sum in lobe order. The loop runs over the longer of
// the two: glossy points (few lobes) or lobes (few glossy points in a block: many lobes).
std::size_t specular(const LobeView& a, std::size_t m, const IncomingRows& rows, const SpecularReceivers& p,
                     double direct_limit, double* fallback, double* out_r, double* out_g, double* out_b) {
  const std::size_t gn = p.count, n = a.n;
  std::size_t fallbacks = 0;
  if (gn >= n) {
    for (std::size_t g = 0; g < gn; ++g) out_r[g] = out_g[g] = out_b[g] = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const double ar = a.amp_r[j], ag = a.amp_g[j], ab = a.amp_b[j];
      const std::size_t r0 = j * m;
      const double *lam = rows.sharpness + r0, *lsj = rows.log_scale + r0, *ix = rows.xi_x + r0, *iy = rows.xi_y + r0,
                   *iz = rows.xi_z + r0, *vj = rows.visible + r0;
      double* fj = fallback + j * gn;
      std::size_t count = 0;
#pragma omp simd reduction(+ : count)
      for (std::size_t g = 0; g < gn; ++g) {
        const std::size_t i = p.point[g];
        const SpecularTerm t = specular_term(p, g, lsj[i], lam[i], ix[i], iy[i], iz[i], vj[i], direct_limit);
        fj[g] = t.fallback;
        count += t.fallback > 0 ? 1 : 0;
        out_r[g] += ar * t.r;
        out_g[g] += ag * t.g;
        out_b[g] += ab * t.b;
      }
      fallbacks += count;
    }
    return fallbacks;
  }
  const double *lsr = rows.log_scale, *lam = rows.sharpness, *ix = rows.xi_x, *iy = rows.xi_y, *iz = rows.xi_z,
               *vis = rows.visible, *amp_r = a.amp_r, *amp_g = a.amp_g, *amp_b = a.amp_b;
  for (std::size_t g = 0; g < gn; ++g) {
    const std::size_t i = p.point[g];
    double* fg = fallback + g * n;
    double s0 = 0, s1 = 0, s2 = 0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : s0, s1, s2, count)
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t r = j * m + i;
      const SpecularTerm t = specular_term(p, g, lsr[r], lam[r], ix[r], iy[r], iz[r], vis[r], direct_limit);
      fg[j] = t.fallback;
      count += t.fallback > 0 ? 1 : 0;
      s0 += amp_r[j] * t.r;
      s1 += amp_g[j] * t.g;
      s2 += amp_b[j] * t.b;
    }
    out_r[g] = s0;
    out_g[g] = s1;
    out_b[g] = s2;
    fallbacks += count;
  }
  return fallbacks;
}

// ---- VSGL shading by a registry `specular` method ------------------------------------------------

// The block's glossy points (MethodReceivers::point) are its points in increasing order, so a block
// whose every point is glossy has point[g] == g: the loops below then read the incoming rows as
// they lie (kAllGlossy) instead of gathering them by index, the same values.
template <bool kAllGlossy>
void method_rows_of(std::size_t lobes, std::size_t m, const IncomingRows& rows, const MethodReceivers& p,
                    const MethodColumns& out) {
  const std::size_t gn = p.count;
  const std::size_t* point = p.point;
  const double *tx = p.tx, *ty = p.ty, *tz = p.tz, *bx = p.bx, *by = p.by, *bz = p.bz, *nx = p.nx, *ny = p.ny,
               *nz = p.nz;
  for (std::size_t j = 0; j < lobes; ++j) {
    const std::size_t r0 = j * m, k0 = j * gn;
    const double *lam = rows.sharpness + r0, *ix = rows.xi_x + r0, *iy = rows.xi_y + r0, *iz = rows.xi_z + r0;
    double *ls = out.light_sharpness + k0, *lc = out.light_cos + k0, *at = out.axis_t + k0, *ab = out.axis_b + k0;
#pragma omp simd
    for (std::size_t g = 0; g < gn; ++g) {
      const std::size_t i = kAllGlossy ? g : point[g];
      const double x = ix[i], y = iy[i], z = iz[i];
      ls[g] = lam[i];
      lc[g] = clamp1(dot3(x, y, z, nx[g], ny[g], nz[g]));
      at[g] = dot3(x, y, z, tx[g], ty[g], tz[g]);
      ab[g] = dot3(x, y, z, bx[g], by[g], bz[g]);
    }
  }
}

void method_rows(std::size_t lobes, std::size_t m, const IncomingRows& rows, const MethodReceivers& p,
                 const MethodColumns& out) {
  if (p.count == m) method_rows_of<true>(lobes, m, rows, p, out);
  else method_rows_of<false>(lobes, m, rows, p, out);
}

template <bool kAllGlossy>
std::size_t method_sum_of(std::size_t lobes, const double* amp_r, const double* amp_g, const double* amp_b,
                          std::size_t m, const IncomingRows& rows, const MethodReceivers& p, const double* at0,
                          const double* at1, double direct_limit, double* fallback, double* out_r, double* out_g,
                          double* out_b) {
  const std::size_t gn = p.count;
  const std::size_t* point = p.point;
  const double *f0r = p.f0_r, *f0g = p.f0_g, *f0b = p.f0_b;
  for (std::size_t g = 0; g < gn; ++g) out_r[g] = out_g[g] = out_b[g] = 0;
  std::size_t fallbacks = 0;
  for (std::size_t j = 0; j < lobes; ++j) {
    const double ar = amp_r[j], ag = amp_g[j], ab = amp_b[j];
    const std::size_t r0 = j * m, k0 = j * gn;
    const double *lsj = rows.log_scale + r0, *sj = rows.scale + r0, *vj = rows.visible + r0, *z0 = at0 + k0,
                 *z1 = at1 + k0;
    double* fj = fallback + k0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : count)
    for (std::size_t g = 0; g < gn; ++g) {
      const std::size_t i = kAllGlossy ? g : point[g];
      const double ls = lsj[i];
      const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * vj[i];
      const double in_range = (ls > kVectorExpFloor ? 1.0 : 0.0) * (ls < direct_limit ? 1.0 : 0.0);
      const double fb = lit * (1 - in_range);
      fj[g] = fb;
      count += fb > 0 ? 1 : 0;
      const bool on = lit * in_range > 0;
      const double e = on ? sj[i] : 0.0;
      const double a0 = on ? e * z0[g] : 0.0, a1 = on ? e * z1[g] : 0.0;
      out_r[g] += ar * (a0 + f0r[g] * (a1 - a0));
      out_g[g] += ag * (a0 + f0g[g] * (a1 - a0));
      out_b[g] += ab * (a0 + f0b[g] * (a1 - a0));
    }
    fallbacks += count;
  }
  return fallbacks;
}

std::size_t method_sum(std::size_t lobes, const double* amp_r, const double* amp_g, const double* amp_b, std::size_t m,
                       const IncomingRows& rows, const MethodReceivers& p, const double* at0, const double* at1,
                       double direct_limit, double* fallback, double* out_r, double* out_g, double* out_b) {
  return p.count == m ? method_sum_of<true>(lobes, amp_r, amp_g, amp_b, m, rows, p, at0, at1, direct_limit, fallback,
                                            out_r, out_g, out_b)
                      : method_sum_of<false>(lobes, amp_r, amp_g, amp_b, m, rows, p, at0, at1, direct_limit, fallback,
                                             out_r, out_g, out_b);
}

}  // namespace
}  // namespace sglab::render::simd_detail
