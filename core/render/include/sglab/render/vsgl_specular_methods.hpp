// Specular VSGL shading by any method of the registry's `specular` quantity (`sglab render
// --specular METHOD`). The default stays the renderer's own form, `vsgl-asg` (vsgl.hpp
// vsgl_specular: Tokuyoshi 2015 (two-VSGL poster) §3.2 and Tokuyoshi 2016 §4, the receiver's GGX
// lobe as an ASG, Xu et al. 2013), computed lobe by lobe in the receiver's tangent frame.
//
// With a registry method, each (shading point, lobe) becomes a row of the quantity's columns in
// its local frame: n = the point's normal, ωo = its view at azimuth 0 (tangent t = the view's
// projection on the tangent plane, b = n × t; any tangent at normal view), ξ = the incoming SG's
// axis (vsgl_shading.hpp, Eq. 7): roughness α, light sharpness λ_in, light_cos = ξ·n,
// view_cos = ωo·n (clamped to [0, 1]), light_azimuth = atan2(ξ·b, ξ·t) (the kernels are handed ξ·t
// and ξ·b themselves, the axis as it is, not the angle), f0. Every method is affine
// in Schlick's f0 (F = f0 + (1 − f0)(1 − ωo·h)⁵ is a factor of each), so it is evaluated at f0 = 0
// and f0 = 1 and interpolated per channel, as vsgl-asg is. The value is for a unit-amplitude SG
// light: times the lobe's amplitude and e^{log_scale} (vsgl.hpp scaled_by_exp). All rows of a
// block of points go through the method's batch evaluator in one call (the SIMD kernels,
// docs/simd.md); a registry method with a pair kernel (sglab/simd_specular_pair.hpp) gives both
// f0 values in one evaluation, bit for bit the batch evaluator's.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/registry.hpp"
#include "sglab/render/vpl.hpp"

namespace sglab::render {

struct VsglShading;

// The default specular shading: the renderer's VSGL ASG form (not a registry method).
inline constexpr std::string_view kDefaultSpecularMethod = "vsgl-asg";

// kDefaultSpecularMethod, then the registry's `specular` methods except its quadrature reference.
std::vector<std::string> specular_method_names();

// The registry method of that name, or nullptr for kDefaultSpecularMethod. Throws
// std::invalid_argument naming the bad name and listing the valid ones.
const Method* find_specular_method(std::string_view name);

// The incoming SGs of the lobes for each of the points, lobe-major (row j·points + i,
// vsgl_shading.cpp): with scale = e^{log_scale} where log_scale is in the range of the kernels'
// vectorized exponential, else 0; and per row 1 where the lobe's cluster is visible from the point, else 0.
struct IncomingLobes {
  const double *xi_x, *xi_y, *xi_z, *sharpness, *log_scale, *scale, *visible;
};

// Adds to out[i].specular the specular radiance of every glossy point from every lobe j visible
// from it (and log_scale > −∞), amplitude[j] being lobe j's: the rows as columns, the light's axis
// by its components in the receiver's frame (no angle), through `method`'s column
// pair evaluator (sglab/simd_specular_pair.hpp), or its batch evaluator at f0 = 0 and f0 = 1 (the
// azimuth then by atan2) for a method without one; the e^{log_scale}-weighted sums vectorized.
void shade_specular_with_method(const Method& method, std::span<const ShadingPoint> points, const IncomingLobes& in,
                                std::span<const Rgb> amplitude, std::span<VsglShading> out);

}  // namespace sglab::render
