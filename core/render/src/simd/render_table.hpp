// The renderer's vectorized loops as one table per instruction set (render_sse2.cpp,
// render_avx2.cpp, render_avx512.cpp, each compiled with its -m flags). The table to run is the
// one of the instruction set the registry's batch evaluators use (sglab/simd.hpp active_isa():
// one selection, one SGLAB_SIMD override, for the whole program); render_dispatch.cpp picks it.
// Internal to sglab_render. Deliberately free of any other header (see core/src/simd/simd_table.hpp:
// nothing compiled with -mavx512f may be merged by the linker into code a smaller CPU runs).
#pragma once

#include <cstddef>

namespace sglab::render::simd_detail {

// π as the renderer's scalar code has it (std::numbers::pi); vsgl.hpp kMaxPositionalSharpness;
// sg.hpp kProductScaleSharpness. Copies (this header includes nothing): render_dispatch.cpp
// checks them against the definitions at compile time.
inline constexpr double kPi = 3.141592653589793116;
inline constexpr double kCap = 1e8;
inline constexpr double kProductScale = 1e18;
// visibility.hpp kVplRayLift and kVplRayReach.
inline constexpr double kRayLift = 1e-7;
inline constexpr double kRayReach = 1 - 1e-6;

// ---- the exact VPL sum (reference.cpp) ----

namespace {
// The builtin square root, which the loops' -fno-math-errno makes the instruction. (Internal
// linkage: see the file comment.)
[[gnu::always_inline]] inline double sqrt_(double x) { return __builtin_sqrt(x); }
[[gnu::always_inline]] inline float sqrt_(float x) { return __builtin_sqrtf(x); }
// x clamped to [−1, 1] by selects.
template <class T>
[[gnu::always_inline]] inline T clamp1(T x) {
  const T lo = x < T(-1) ? T(-1) : x;
  return lo > T(1) ? T(1) : lo;
}
// √(c² + α²(1 − c)(1 + c)), c clamped to [−1, 1] inside (1 − c)(1 + c): one side's root of GGX's
// height-correlated visibility (brdf.hpp smith_visibility_ggx) at the cosine c of that side,
// a2 = α². ggx_layer (render_kernels_vpl.hpp) takes it for both directions; a glossy VPL's incoming
// side is the same in all of its terms, so its arrays hold it (VplView::smith_in, reference.cpp),
// the same operations on the same values. (Internal linkage: see the file comment.)
template <class T>
[[gnu::always_inline]] inline T ggx_smith_root(T a2, T c) {
  const T cc = clamp1(c);
  return sqrt_(c * c + a2 * ((1 - cc) * (1 + cc)));
}

// fresnel_schlick (brdf.hpp) without the branches of its clamp, f0 + (1 − f0)·m²·m²·m with m = 1 −
// clamp(c, 0, 1): the polynomial at the unclamped c, and at either end of the clamp the value the
// polynomial has there, written out: c < 0 (m = 1) f0 + (1 − f0), c > 1 (m = 0) f0 + 0, which is
// f0 + (1 − f0)·0·0·0 for every finite f0 (the product is +0, or −0 where f0 > 1 and f0 + −0 = f0 +
// 0). Written with the clamp first, GCC evaluated the polynomial again at m = 0 for each channel
// (x·0 does not fold: three multiplies per channel per term); the values are the same bits
// (RenderKernels.SchlickIsFresnelSchlickToTheBit).
template <class T>
[[gnu::always_inline]] inline T schlick(T f0, T cos_oh) {
  const T m = 1 - cos_oh, m2 = m * m;
  const T inside = f0 + (1 - f0) * m2 * m2 * m;
  return cos_oh < 0 ? f0 + (1 - f0) : (cos_oh > 1 ? f0 + T(0) : inside);
}
}  // namespace

// One VPL array (VplArrays, reference.hpp) in T, padded to a multiple of the lane count.
template <class T>
struct VplView {
  std::size_t n = 0;
  const T *x, *y, *z, *nx, *ny, *nz, *ix, *iy, *iz, *r2, *lambert_r, *lambert_g, *lambert_b;
  // glossy arrays only; smith_in = ggx_smith_root(α², cos_incoming)
  const T *flux_r, *flux_g, *flux_b, *f0_r, *f0_g, *f0_b, *alpha, *cos_incoming, *smith_in;
  const T* visible = nullptr;  // per VPL 0 or 1 (V(y_p, x_i) by ray casting), or nullptr: all visible
};

// What the sum needs of the shading point.
template <class T>
struct Receiver {
  T px, py, pz, nx, ny, nz, vx, vy, vz;
  T rd[3];  // R_d,p/π
  T f0[3];
  T alpha;     // GGX α
  T cos_view;  // n_p·ω_o
};

// Adds Σ_i over the array to out[0..2]. Index: 2·(VPLs glossy) + (receiver glossy).
template <class T>
using VplSumFn = void (*)(const VplView<T>& vpls, const Receiver<T>& point, double* out);
// VplSumFn of two points of the same kind in one pass (each value VplSumFn's to the bit): out gets
// point's sum (visibility vpls.visible), out2 point2's (visibility visible2; nullptr when vpls.visible
// is).
template <class T>
using VplSum2Fn = void (*)(const VplView<T>& vpls, const T* visible2, const Receiver<T>& point,
                           const Receiver<T>& point2, double* out, double* out2);

// ---- VPL visibility (reference.cpp, with visibility) ----

// The scene's shapes as intersect() (raycast.cpp) sees them: boxes (min xyz, max xyz: 6 values),
// rectangles (corner, edge_u, edge_v, the unit normal of edge_u × edge_v, |edge_u|², |edge_v|²:
// 14 values), spheres (centre, radius: 4 values).
struct Occluders {
  std::size_t boxes = 0, rectangles = 0, spheres = 0;
  const double *box = nullptr, *rectangle = nullptr, *sphere = nullptr;
};

// For a point (position p, normal n) and every VPL of a (double) array: out[i] = 1 where the
// term is not 0 by its cosines and vpl_visible (visibility.cpp) finds the VPL visible, else 0 —
// the same arithmetic, ray by ray, so the same answer. scratch: 8·kVisibilityBlock doubles.
inline constexpr std::size_t kVisibilityBlock = 256;
template <class M>
using VisibilityFn = void (*)(const VplView<double>& vpls, const double* p, const double* n, const Occluders& shapes,
                              double* scratch, M* out);

// ---- shadow maps (shadow_map.cpp) ----
// distance[i] = cast_ray's hit distance (raycast.cpp) of the ray from `origin` along the unit
// direction (dx, dy, dz)[i], +∞ for a miss: the same arithmetic, so the same value.
using NearestHitsFn = void (*)(const Occluders& shapes, const double* origin, std::size_t n, const double* dx,
                               const double* dy, const double* dz, double* distance);

// ---- VSGL visibility from cube shadow maps (visibility.cpp) ----
// One cube shadow map (visibility.hpp CubeShadowMap): its origin, its faces' common half extent
// T, texel size (LightView::texel_size) and resolution, and per face its depth image and its frame
// (forward, right, up).
struct CubeView {
  double ox, oy, oz, half_extent, texel, resolution;
  const double* depth[6];
  double frame[6][9];
};
// out[i] = 1 where CubeShadowMap::lit(p_i, n_i) (the face of p_i's largest |p_i − origin|
// component, then ShadowMap::lit's nearest texel and slope-scaled bias), else 0: the same
// arithmetic lane by lane, so the same answer. (p, n): m points as arrays px, py, pz, nx, ny, nz;
// scratch: 4·m doubles.
using CubeLookupFn = void (*)(const CubeView& cube, std::size_t m, const double* const* points, double* scratch,
                              double* out);

// ---- VSGL shading (vsgl_shading.cpp) ----

// The lobes of a VSGL set as arrays (cluster order), double.
struct LobeView {
  std::size_t n = 0;
  const double *mx, *my, *mz, *variance, *log_two_pi_variance, *ax, *ay, *az, *sharpness, *amp_r, *amp_g, *amp_b;
};

// A block of m shading points as arrays.
struct PointBlock {
  std::size_t m = 0;
  const double *px, *py, *pz, *nx, *ny, *nz;
  const double* diffuse;  // 1: the point reflects diffuse light
};

// Per (lobe j, point i), row j·m + i: the incoming SG and its cosine with the normal, and (read
// only) `visible`: 1 where the lobe's cluster is visible from the point, else 0 (V(y_p, μ_v),
// visibility.hpp; all 1 without visibility).
struct IncomingRows {
  double *sharpness, *cosine, *log_scale, *xi_x, *xi_y, *xi_z, *d2, *capped, *mask;
  const double* visible;
  double* scale;  // e^{log_scale} in the vectorized exponential's range, else 0 (ScaleRowsFn)
};

// The incoming SGs of every (lobe, point) row, and the diffuse method's argument rows (λ, c)
// interleaved in `args` (T = the precision the method runs in), λ floored at `sharpness_floor`
// (0: none); rows that need no D get (1, 0) and mask 0. Returns the number of capped rows (their
// log_scale is finished by the caller, which needs log).
template <class T>
using IncomingFn = std::size_t (*)(const LobeView& lobes, const PointBlock& points, double sharpness_floor,
                                   IncomingRows& out, T* args);

// scale[r] = e^{log_scale[r]} for the rows r < rows whose log_scale is in the vectorized
// exponential's range (above its floor, below direct_limit: vsgl.hpp scaled_by_exp's), else 0: once
// per block, for the diffuse sums and a registry method's specular sums alike.
using ScaleRowsFn = void (*)(std::size_t rows, const double* log_scale, double direct_limit, double* scale);

// out_{r,g,b}[i] = Σ_j amp_j · e^{log_scale} · factor · value over the rows with mask 1, in lobe
// order, e^{log_scale} being ScaleRowsFn's `scale`; rows whose log_scale is outside the vectorized
// exponential's range (or ≥ direct_limit) get fallback = 1 (returned: how many) and are left to the caller.
template <class T>
using WeightedSumFn = std::size_t (*)(const LobeView& lobes, std::size_t m, const double* log_scale,
                                      const double* scale, const T* value, const double* mask, double factor,
                                      double direct_limit, double* fallback, double* out_r, double* out_g,
                                      double* out_b);

// The block's glossy points as arrays: vsgl.hpp's VsglSpecularReceiver (local frame t, b, n; ω_o
// in it; the ASG lobe x, y, z, ηx, ηy; λ_s; 1/(πα²); α) and the point's f0.
struct SpecularReceivers {
  std::size_t count = 0;
  const std::size_t* point;  // the point's index in the block
  const double *tx, *ty, *tz, *bx, *by, *bz, *nx, *ny, *nz, *wox, *woy, *woz;
  const double *xx, *xy, *xz, *yx, *yy, *yz, *zx, *zy, *zz, *eta_x, *eta_y, *lambda_s, *ndf_amplitude, *roughness;
  const double *f0_r, *f0_g, *f0_b;
};

// out_{r,g,b}[g] = Σ_j amp_j · (at_f0_zero + f0·(at_f0_one − at_f0_zero)) of vsgl.hpp's
// vsgl_specular for every lobe j (mask: its cluster visible and log_scale > −∞) and glossy point g
// (in lobe order, or partly in vector lanes when there are more lobes than glossy points: the same
// to rounding). The mask's visibility is rows.visible. Rows whose exponent is outside the vectorized exponential's
// range get fallback = 1 (returned: how many; at j·count + g if count ≥ lobes, else at g·lobes + j) and are left to the
// caller.
using SpecularFn = std::size_t (*)(const LobeView& lobes, std::size_t m, const IncomingRows& rows,
                                   const SpecularReceivers& receivers, double direct_limit, double* fallback,
                                   double* out_r, double* out_g, double* out_b);

// The block's glossy points for a registry `specular` method (vsgl_specular_methods.cpp): the
// local frame (t towards the view, b = n × t, n), n·ω_o clamped to [0, 1], α, and f0.
struct MethodReceivers {
  std::size_t count = 0;
  const std::size_t* point;  // the point's index in the block
  const double *tx, *ty, *tz, *bx, *by, *bz, *nx, *ny, *nz, *view_cos, *roughness, *f0_r, *f0_g, *f0_b;
};
// The method's lights' columns (sglab/simd_specular_pair.hpp SpecularPairColumns; the receivers'
// are MethodReceivers' roughness and view_cos), row j·count + g for lobe j and glossy point g.
struct MethodColumns {
  double *light_sharpness, *light_cos, *axis_t, *axis_b;
};
// The columns of every (lobe, glossy point) from the incoming rows (j·m + i): λ_in, ξ·n clamped to
// [−1, 1], ξ·t and ξ·b.
using MethodRowsFn = void (*)(std::size_t lobes, std::size_t m, const IncomingRows& rows,
                              const MethodReceivers& receivers, const MethodColumns& out);
// out_{r,g,b}[g] = Σ_j amp_j · (a0 + f0·(a1 − a0)), a_k = e^{log_scale}·at_f0_k of row j·count + g
// (e^{log_scale}: the rows' `scale`), over the rows with visible 1 and log_scale > −∞, in lobe order;
// rows whose log_scale is outside the vectorized exponential's range get fallback = 1 (returned: how
// many) and are left to the caller.
using MethodSumFn = std::size_t (*)(std::size_t lobes, const double* amp_r, const double* amp_g, const double* amp_b,
                                    std::size_t m, const IncomingRows& rows, const MethodReceivers& receivers,
                                    const double* at_f0_zero, const double* at_f0_one, double direct_limit,
                                    double* fallback, double* out_r, double* out_g, double* out_b);

// ---- environment quadrature (environment_shading.cpp) ----

// A map's quadrature nodes as arrays: unit direction and ω·L per channel (solid angle times radiance).
struct EnvNodes {
  std::size_t n = 0;
  const double *x, *y, *z, *wr, *wg, *wb;
};

// The shading point: unit normal and view, n·ω_o, GGX α and Schlick f0 (one for every channel).
struct EnvReceiver {
  double nx, ny, nz, wox, woy, woz, cos_view, alpha, f0;
};

// out[0..2] = Σ_k ggx_brdf_cosine(α, f0, ω_o, ω_k) · (ω·L)_k (brdf.hpp; 0 below the horizon).
using EnvSpecularSumFn = void (*)(const EnvNodes& nodes, const EnvReceiver& point, double* out);
// EnvSpecularSumFn of two points in one pass over the nodes (each value EnvSpecularSumFn's to the bit).
using EnvSpecularSum2Fn = void (*)(const EnvNodes& nodes, const EnvReceiver& point, const EnvReceiver& point2,
                                   double* out, double* out2);

// Several maps on the same nodes (the same directions; maps whose all-zero texels, which a map's
// nodes leave out, are the same): channel[3m + c] is map m's ω·L in channel c, m < maps ≤ kEnvMapsPerPass.
// Eight maps: a chunk of kEnvChunk nodes of their 27 arrays is 216 KiB, within a core's second-level
// cache (512 KiB per core on the AVX2 machine measured); eight points reuse each chunk while it is there, and
// their sums (8 × 24 lane arrays) stay in the first-level cache (docs/testing.md, "Every fit's
// specular quadrature in one pass").
inline constexpr std::size_t kEnvMapsPerPass = 8;
inline constexpr std::size_t kEnvPointsPerPass = 8;
struct EnvMapsNodes {
  std::size_t n = 0, maps = 0;
  const double *x, *y, *z;
  const double* channel[3 * kEnvMapsPerPass];
};
// out[3(i·maps + m) .. + 2] = EnvSpecularSumFn's sums of point i (i < count ≤ kEnvPointsPerPass) and
// map m, each to the bit: one GGX weight per node and point for every map.
using EnvSpecularMapsFn = void (*)(const EnvMapsNodes& nodes, const EnvReceiver* points, std::size_t count,
                                   double* out);

struct RenderKernelTable {
  const char* isa;  // "sse2", "avx2", "avx512"
  VplSumFn<double> vpl_sum_d[4];
  VplSumFn<float> vpl_sum_f[4];
  VplSum2Fn<double> vpl_sum2_d[4];
  VplSum2Fn<float> vpl_sum2_f[4];
  VisibilityFn<double> visibility_d;
  VisibilityFn<float> visibility_f;
  NearestHitsFn nearest_hits;
  CubeLookupFn cube_lookup;
  IncomingFn<double> incoming_d;
  IncomingFn<float> incoming_f;
  ScaleRowsFn scale_rows;
  WeightedSumFn<double> weighted_sum_d;
  WeightedSumFn<float> weighted_sum_f;
  SpecularFn specular;
  MethodRowsFn method_rows;
  MethodSumFn method_sum;
  EnvSpecularSumFn env_specular_sum;
  EnvSpecularSum2Fn env_specular_sum2;
  EnvSpecularMapsFn env_specular_maps;
};

const RenderKernelTable& render_kernels_sse2();
const RenderKernelTable& render_kernels_avx2();
const RenderKernelTable& render_kernels_avx512();

// The largest log_scale for which vsgl.hpp scaled_by_exp forms e^{log_scale}·x directly (half the
// log of the largest double; render_dispatch.cpp): the kernels' direct_limit.
double scaled_by_exp_direct_limit();

// The table of the instruction set sglab::simd::active_isa() names.
const RenderKernelTable& render_kernels();

}  // namespace sglab::render::simd_detail
