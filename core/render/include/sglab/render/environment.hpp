// Environment maps on disk and the environments sglab makes itself (equirectangular, 2:1, the
// convention of sglab/envmap.hpp), and shading a sphere and a plane lit by an environment with
// visibility ignored (V = 1, as in the "Rendering using Spherical Gaussians" blog).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sglab/envmap.hpp"
#include "sglab/render/vpl.hpp"

namespace sglab::render {

// Bad environment input (missing file, no RGB channels, NaN/Inf/negative texel, not 2:1): the
// message names the file and the problem.
struct EnvironmentError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Reads an EXR's RGB channels: "R", "G", "B", or else the first layer "L.R", "L.G", "L.B".
// Throws EnvironmentError.
EnvMap load_environment(const std::string& path);
// The bytes of an EXR holding the map as channels R, G, B (32-bit float).
std::string encode_environment(const EnvMap& map,
                               const std::vector<std::pair<std::string, std::string>>& attributes = {});

// ---- generated environments -----------------------------------------------------------------

// Preetham, Shirley & Smits 1999, "A practical analytic model for daylight": the Perez et al.
// 1993 distribution F(θ, γ) = (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ) for Y, x, y with the
// coefficients of their Appendix A.2 (linear in turbidity T), the zenith luminance
// Y_z = (4.0453T − 4.9710) tan χ − 0.2155T + 2.4192 (kcd/m²), χ = (4/9 − T/120)(π − 2θ_s), and the
// zenith chromaticities' cubic polynomials in θ_s; value = zenith·F(θ, γ)/F(0, θ_s), then
// xyY → XYZ → linear sRGB (IEC 61966-2-1 D65 matrix), negative components clamped to 0.
// Not from the paper (stated in the file header of every map): the sun is a uniform disk of
// angular diameter sun_size_deg and luminance sun_luminance × Y_z, white; below the horizon is a
// Lambertian ground of albedo ground_albedo lit by the sky and the sun (radiance E/π · albedo).
// The largest --sun-luminance (disk luminance / zenith luminance): with the zenith luminance of any
// turbidity in [2, 10] (below 1e2), the disk's texels stay far inside float (FLT_MAX ≈ 3.4e38) and
// their squares inside double, so a fit of the map has finite errors.
inline constexpr double kMaxSunLuminance = 1e30;
// The smallest GGX roughness the environment shading takes (`envmap render|lobes --roughness`):
// below it the lobe is narrower than a texel of any map sglab reads and the texel quadrature of
// the specular layers no longer measures anything (at 1e-300 its statistics were NaN).
inline constexpr double kMinEnvRoughness = 1e-3;

struct SkyOptions {
  int width = 512, height = 256;
  double turbidity = 3;           // Preetham's T ∈ [2, 10]
  double sun_elevation_deg = 30;  // above the horizon, [0, 90]
  double sun_azimuth_deg = 0;     // φ of the sun
  double sun_size_deg = 2;        // angular diameter (the real sun: 0.53°)
  double sun_luminance = 500;     // disk luminance / zenith luminance
  double ground_albedo = 0.2;
  int supersample = 4;  // per texel side (the sun's edge)
};
EnvMap make_sky(const SkyOptions& o);

// A "studio": a dim uniform background plus rectangular area lights at unit distance, each given
// by the direction of its centre, its angular width and height (as seen from the centre) and an
// RGB radiance; texels are supersampled so that the rectangles' edges are area-weighted.
struct AreaLight {
  double elevation_deg, azimuth_deg, width_deg, height_deg;
  std::array<double, 3> radiance;
};
struct StudioOptions {
  int width = 512, height = 256;
  std::array<double, 3> background{0.03, 0.03, 0.03};
  std::vector<AreaLight> lights = {
      {40, 30, 40, 25, {6.0, 5.6, 5.0}},    // key
      {15, -110, 60, 35, {1.2, 1.4, 1.6}},  // fill
      {75, 170, 20, 70, {3.0, 3.0, 3.0}},   // top strip
  };
  int supersample = 4;
};
EnvMap make_studio(const StudioOptions& o);

// The CIE standard overcast sky (Moon & Spencer 1942; CIE S 011/E:2003 sky type 1): luminance
// L(θ) = L_z (1 + 2 cos θ)/3 above the horizon (θ from the zenith), white, L_z = zenith; below
// the horizon a Lambertian ground of albedo ground_albedo lit by that sky, radiance
// albedo · E/π with E = ∫ L cos θ dω = (7/9) π L_z in closed form. Smooth everywhere but at the
// horizon.
struct OvercastOptions {
  int width = 512, height = 256;
  double zenith = 1.0;
  double ground_albedo = 0.2;
  int supersample = 4;
};
EnvMap make_overcast(const OvercastOptions& o);

// An indoor room seen from its centre: walls, ceiling and floor of uniform radiance (each a box
// face, hard edges between them), ceiling light panels and a window (rectangular emitters as
// in make_studio, hard edges). Deterministic: its layout is fixed (file environment.cpp).
struct IndoorOptions {
  int width = 512, height = 256;
  int supersample = 4;
};
EnvMap make_indoor(const IndoorOptions& o);

// The shipped synthetic mixture of known lobes (broad to sharp; used by the recovery test and
// the tables).
SgMixture synthetic_mixture();

// ---- shading (V = 1) --------------------------------------------------------------------------

// One shaded pixel: unit normal n and unit view direction o (towards the viewer), world frame.
struct EnvShadingPoint {
  int pixel;  // index in the image
  Vec3 normal, view;
};

struct EnvImage {
  int width = 0, height = 0;
  std::vector<EnvShadingPoint> points;  // only the covered pixels
};

// A unit sphere seen orthographically along −x (o = +x), res × res pixels.
EnvImage sphere_image(int res);
// A plane with normal +z seen from every view direction of a res_azimuth × res_elevation grid:
// pixel (i, j) has o at azimuth 2π(i + ½)/res_azimuth and elevation (π/2)(j + ½)/res_elevation
// (the shading of a planar patch under a distant environment depends on o only).
EnvImage plane_image(int res_azimuth, int res_elevation);

// Exact shading by texel quadrature of the piecewise-constant map (sglab/envmap.hpp): each texel
// split into supersample² equal-(θ, φ) sub-texels of exact solid angle, the BRDF evaluated at
// their centres (midpoint rule; its error is measured by the callers at supersample 1 vs 2).
//   diffuse:  (1/π) ∫ L(ω)⟨ω·n⟩ dω               (albedo 1)
//   specular: ∫ L(ω) f_GGX(o, ω)⟨ω·n⟩ dω          (GGX + height-correlated Smith + Schlick, brdf.hpp)
std::vector<Rgb> integrate_diffuse(const EnvMap& map, const EnvImage& image, int supersample = 1);
std::vector<Rgb> integrate_specular(const EnvMap& map, const EnvImage& image, double roughness, double f0,
                                    int supersample = 1);
// integrate_specular of several maps of one size (std::invalid_argument otherwise) on one image, each
// map's values integrate_specular's to the bit: maps with the same nodes (the same all-zero texels,
// which the quadrature leaves out) share one GGX evaluation per node and point.
std::vector<std::vector<Rgb>> integrate_specular(const std::vector<const EnvMap*>& maps, const EnvImage& image,
                                                 double roughness, double f0, int supersample = 1);

// The diffuse shading of a mixture with the closed-form-accurate clamped-cosine reference per
// lobe (clamped_cosine_reference, reference.hpp): (1/π) Σ_j μ_j D(λ_j, ξ_j·n).
std::vector<Rgb> mixture_diffuse_reference(const SgMixture& m, const EnvImage& image);

// The same with registry methods: quantity "clamped-cosine" (diffuse) or "specular" (frame of
// the registry: n = z, o in the xz-plane), method by name, summed over the lobes. Throws
// std::invalid_argument for an unknown method.
std::vector<Rgb> mixture_diffuse_method(const SgMixture& m, const EnvImage& image, const std::string& method);
std::vector<Rgb> mixture_specular_method(const SgMixture& m, const EnvImage& image, const std::string& method,
                                         double roughness, double f0);

// Relative L2, SMAPE (mean 2|v − r|/(|v| + |r|)) and the brightness-weighted error Σ|v − r|/Σ|r|
// over the covered pixels (and channels) of two shadings of `image` (core/include/sglab/error_metrics.hpp).
struct ShadingError {
  double relative_l2 = 0, smape = 0, brightness_weighted = 0;
};
ShadingError shading_error(const std::vector<Rgb>& value, const std::vector<Rgb>& reference, const EnvImage& image);

}  // namespace sglab::render
