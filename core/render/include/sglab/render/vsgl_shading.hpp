// Shading from VSGLs (Tokuyoshi 2015 (two-VSGL poster) §3, Tokuyoshi 2016 §4): the indirect
// radiance reflected towards ShadingPoint::view, summed over every VSGL lobe (diffuse and specular
// VSGLs alike) of every cluster:
//
//   incoming (Eq. 7):  L_in(ω) = c_v/(2πσ²) G(ω; −ξ_v, λ_v) G(ω; ξ_μ, λ_σ) = c_in G(ω; ξ_in, λ_in)
//   diffuse:           L_d = R_d/π · c_in · D(λ_in, ξ_in·n)  with D = ∫ G⟨ω·n⟩dω by a selectable
//                      clamped-cosine method of the registry (`sglab eval --list`); every method
//                      returns the same physical quantity D, so the factor R_d/π is common:
//                        sg-cosine        D = π/A(λ_d) · 2π G(ξ_in; n, λ_inλ_d/(λ_in+λ_d))/(λ_in+λ_d)
//                                         (the poster's form, exact A(λ_d) or, with
//                                         sg_cosine_a_is_pi, its A(λ_d) ≈ π; λ_d is the VSGL set's)
//                        punctual-approx  D = (2π/λ_in)⟨ξ_in·n⟩ (Tokuyoshi 2016 §4.2)
//                        tokuyoshi2024    the erfc interpolation (most accurate published; the default)
//                        sglab            this project's own refit of it with an even correction
//                        reference        the quadrature (slow; exact D for the SG)
//                        …and every other clamped-cosine method of the registry.
//   specular:          the receiver's GGX lobe as an ASG (Xu et al. 2013 warp) × the incoming SG,
//                      M(ω) at the product lobe's axis ξ_m (Tokuyoshi 2015 (two-VSGL poster) §3.2; specular.hpp `asg`);
//                      only for glossy receivers (ShadingPoint::glossy()) and only if requested.
//                      The default, `vsgl-asg`; any method of the registry's `specular` quantity
//                      instead through ShadingOptions::specular_method (vsgl_specular_methods.hpp).
//
// VSGL VISIBILITY is ignored by default, as in the 2015 poster (no visibility term): every VSGL
// lights every shading point, and the render output says so (kVsglVisibilityNote). Tokuyoshi 2016
// §4.1 (2016) multiplies by V(y_p, μ_v) from a shadow map at μ_v: pass `visible` (the renderer's
// --visibility, visibility.hpp), with the reference's VPLs ray-cast for visibility too.
//
// Stiff cases: the shading point on μ_v (λ_σ = 0), σ_v² = 0 (λ_σ capped at 1e8: a point light to
// 1e-8), tiny σ² (amplitudes in log form) — see sglab/vsgl.hpp. Methods whose published form
// diverges at λ = 0 (punctual-approx, hill-fitted: 1/λ) are evaluated at λ_in ≥ 1e-8, the bottom
// of the sharpness range they are measured over (docs/math.md §10); methods that go negative as
// published (hill-fitted, meder) are NOT clamped: their flaw shows in the image.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/registry.hpp"
#include "sglab/render/vpl.hpp"
#include "sglab/render/vsgl_generation.hpp"

namespace sglab::render {

inline constexpr std::string_view kVsglVisibilityNote =
    "VSGL visibility ignored (as in the papers): every VSGL lights every shading point";

// The clamped-cosine method a render uses when none is named.
inline constexpr std::string_view kDefaultDiffuseMethod = "tokuyoshi2024";

struct ShadingOptions {
  // The clamped-cosine method giving D: an entry of the registry's clamped-cosine quantity (held
  // without ownership: the registry lives for the whole program), or a copy of one bound to a
  // constant set (registry.hpp bind), owned here. nullptr: kDefaultDiffuseMethod. Any method the
  // registry lists works, through its batch evaluator (Method::batch_double, one call per shading
  // point for all its lobes). A parameter of role ParameterRole::vsgl_diffuse_sharpness
  // (sg-cosine's λ_d) is the VSGL set's λ_d: the method is bound to it. Methods whose domain
  // excludes λ = 0 (Method::domain_error set) are evaluated at λ_in ≥ 1e-8.
  std::shared_ptr<const Method> diffuse;
  bool specular = true;  // ASG specular on glossy receivers
  // The specular method: a method of the registry's `specular` quantity
  // (vsgl_specular_methods.hpp); nullptr: the VSGL ASG form below (kDefaultSpecularMethod).
  const Method* specular_method = nullptr;
  // sg-cosine only (the method with a vsgl_diffuse_sharpness parameter): take A(λ_d) ≈ π as the two-VSGL poster does
  // (Tokuyoshi 2015 supplement §3.2, after Iwasaki et al. 2012), i.e. D = 2π G(ξ_in; n, λ_inλ_d/(λ_in+λ_d))/(λ_in+λ_d);
  // false: the exact A(λ_d).
  bool sg_cosine_a_is_pi = false;
  // Precision::single: the diffuse method runs in float (Method::batch_float, its arguments λ_in
  // and ξ_in·n rounded to float); the incoming SGs, the e^{log_scale} weights, the sums and the
  // specular part stay double.
  Precision precision = Precision::double_;
};

// The method's parameter of role ParameterRole::vsgl_diffuse_sharpness (the VSGL set's λ_d
// replaces it in shading), nullptr if it has none.
const Parameter* vsgl_diffuse_sharpness(const Method& m);

// Options for a clamped-cosine method named as in the registry. Throws std::invalid_argument
// naming the bad name and listing the valid ones.
ShadingOptions shading_options(std::string_view diffuse_method, bool specular = true);
std::string diffuse_method_name(const ShadingOptions& o);
// The clamped-cosine methods of the registry, in registry order.
std::vector<std::string> diffuse_method_names();

struct VsglShading {
  Rgb diffuse = Rgb::Zero();
  Rgb specular = Rgb::Zero();
  Rgb total() const { return diffuse + specular; }
};

// A VSGL set prepared for shading many points with one set of options: the lobes as arrays
// (cluster order, each cluster's diffuse lobe then its specular lobe) and the diffuse method bound.
// shade() is const and may run on many threads at once. Points are shaded in blocks, as arrays: the
// incoming SG of every (lobe, point) (positional Gaussian × intensity SG, Eq. 7) in loops
// vectorized over the block's points (core/render/src/simd/), D for all of them in one batch call
// of the method, the e^{log_scale}-weighted sums vectorized; each point's sum runs in lobe order,
// as the one-lobe-at-a-time form, so results agree with it to rounding. No allocation per block.
class VsglShader {
 public:
  VsglShader(const VsglSet& set, const ShadingOptions& options);
  VsglShader(VsglShader&&) noexcept;
  ~VsglShader();
  // Indirect radiance at `point` towards point.view from every VSGL of the set. `visible`, if not
  // empty, has one entry per cluster: 0 = V(y_p, μ_v) = 0, the cluster is skipped (Tokuyoshi 2016
  // supplement §4.1; visibility.hpp).
  VsglShading shade(const ShadingPoint& point, std::span<const char> visible = {}) const;
  // Many points at once (every cluster visible): out[i] for points[i]. The diffuse method is then
  // called on batches of (point, lobe) rows, wide even for a few lobes.
  void shade(std::span<const ShadingPoint> points, std::span<VsglShading> out) const;
  // Many points, each with its own visibility: visible[i·clusters() + c] for points[i] and the
  // set's cluster c (0: V(y_p, μ_v) = 0). The same blocks and the same arithmetic as without
  // visibility, the hidden (lobe, point) rows masked to 0.
  void shade(std::span<const ShadingPoint> points, std::span<const char> visible, std::span<VsglShading> out) const;
  std::size_t lobes() const;
  std::size_t clusters() const;

 private:
  // visible: empty (all visible) or visible[i·clusters() + c] for points[i].
  void shade_block(std::span<const ShadingPoint> points, std::span<const char> visible,
                   std::span<VsglShading> out) const;
  struct Data;
  std::unique_ptr<Data> data_;
};

// One point (builds a VsglShader per call: use VsglShader for many points).
VsglShading shade_vsgls_parts(const ShadingPoint& point, const VsglSet& set, const ShadingOptions& options,
                              std::span<const char> visible = {});
inline Rgb shade_vsgls(const ShadingPoint& point, const VsglSet& set, const ShadingOptions& options,
                       std::span<const char> visible = {}) {
  return shade_vsgls_parts(point, set, options, visible).total();
}

}  // namespace sglab::render
