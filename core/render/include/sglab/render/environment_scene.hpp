// A distant environment in a rendered scene (the scene JSON's "environment", scene.hpp), visibility
// ignored (V = 1, as in the "Rendering using Spherical Gaussians" blog), shaded at the camera's
// first hits with the same shading code as `sglab envmap render` (environment.hpp), in three
// layers that separate the two error sources:
//   (1) the map integrated exactly (texel quadrature, environment.hpp),
//   (2) the SG mixture integrated exactly (diffuse: the clamped-cosine reference per lobe;
//       specular: the texel quadrature of the mixture's texel means),
//   (3) the mixture shaded with a registry clamped-cosine method and a registry specular method.
// Fit part = (2) against (1), approximation part = (3) against (2).
#pragma once

#include <string>
#include <vector>

#include "sglab/envmap.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/render/mixture_record.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/scene.hpp"

namespace sglab::render {

// Scene directions (y up, scene.hpp) to environment directions (z up, sglab/envmap.hpp): the
// rotation (x, y, z) ↦ (z, x, y), so the environment's zenith is the scene's +y.
inline Vec3 scene_to_environment(const Vec3& v) { return Vec3(v(2), v(0), v(1)); }

struct EnvironmentLayers {
  // Row-major camera images; `map` is empty when there is no map (a mixture alone).
  std::vector<Rgb> map, mixture, approximation;
  EnvImage image;  // the pixels that hit geometry
  // Relative L2 change of layer (1) between 1 and 2 × 2 sub-texels per texel (the layer is the
  // 2 × 2 one): the quadrature's stated tolerance. 0 without a map.
  double quadrature_change = 0;
};

// Shades every hit pixel of `gbuffer` with its object's material (albedo × diffuse + the GGX layer
// when glossy; an RGB f0 by linearity of Schlick's F in f0: f(f0) = (1 − f0) f(0) + f0 f(1)).
// `map` may be null. Layer (2)'s specular quadrature uses the mixture's texel means at the map's
// size (or mixture_width × mixture_width/2 without a map). Throws std::invalid_argument for an
// unknown method.
EnvironmentLayers shade_environment(const Scene& scene, const GBuffer& gbuffer, const EnvMap* map,
                                    const SgMixture& mixture, const std::string& diffuse_method,
                                    const std::string& specular_method, int mixture_width = 512);

}  // namespace sglab::render
