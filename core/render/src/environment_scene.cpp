// A distant environment in a rendered scene (environment_scene.hpp).
#include "sglab/render/environment_scene.hpp"

#include <cmath>
#include <fstream>
#include <functional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sglab/render/pipeline.hpp"

namespace sglab::render {

namespace {

// The hit pixels of one object, in environment coordinates.
EnvImage object_image(const GBuffer& g, int object) {
  EnvImage im{g.width, g.height, {}};
  for (std::size_t k = 0; k < g.points.size(); ++k)
    if (g.hit[k] && g.object[k] == object)
      im.points.push_back({int(k), scene_to_environment(g.points[k].normal), scene_to_environment(g.points[k].view)});
  return im;
}

// Adds weight · layer over the image's pixels to `out` (per channel).
void add_weighted(std::vector<Rgb>& out, const std::vector<Rgb>& layer, const EnvImage& im, const Rgb& weight) {
  for (const auto& p : im.points) out[std::size_t(p.pixel)] += weight * layer[std::size_t(p.pixel)];
}

// One layer: Σ over objects of albedo · diffuse(im) + the specular layer with the object's f0.
using Diffuse = std::function<std::vector<Rgb>(const EnvImage&)>;
using Specular = std::function<std::vector<Rgb>(const EnvImage&, double roughness, double f0)>;

std::vector<Rgb> layer(const Scene& scene, const std::vector<EnvImage>& images, const Diffuse& diffuse,
                       const Specular& specular) {
  const std::size_t n = std::size_t(scene.camera.width) * std::size_t(scene.camera.height);
  std::vector<Rgb> out(n, Rgb::Zero());
  for (std::size_t o = 0; o < images.size(); ++o) {
    const auto& im = images[o];
    if (im.points.empty()) continue;
    const Material& mat = scene.objects[o].material;
    add_weighted(out, diffuse(im), im, mat.albedo);
    if (!mat.glossy()) continue;
    if (mat.f0(0) == mat.f0(1) && mat.f0(1) == mat.f0(2)) {
      add_weighted(out, specular(im, mat.roughness, mat.f0(0)), im, Rgb::Ones());
    } else {  // Schlick's F is linear in f0
      add_weighted(out, specular(im, mat.roughness, 0.0), im, Rgb::Ones() - mat.f0);
      add_weighted(out, specular(im, mat.roughness, 1.0), im, mat.f0);
    }
  }
  return out;
}

}  // namespace

EnvironmentLayers shade_environment(const Scene& scene, const GBuffer& gbuffer, const EnvMap* map, const SgMixture& m,
                                    const std::string& diffuse_method, const std::string& specular_method,
                                    int mixture_width) {
  EnvironmentLayers r;
  std::vector<EnvImage> images;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) images.push_back(object_image(gbuffer, int(o)));
  r.image = {gbuffer.width, gbuffer.height, {}};
  for (const auto& im : images) r.image.points.insert(r.image.points.end(), im.points.begin(), im.points.end());
  const int rw = map ? map->width : mixture_width;
  const EnvMap recon = rasterize_mixture(m, rw, rw / 2, 4);
  if (map) {
    auto map_layer = [&](int ss) {
      return layer(
          scene, images, [&](const EnvImage& im) { return integrate_diffuse(*map, im, ss); },
          [&](const EnvImage& im, double a, double f0) { return integrate_specular(*map, im, a, f0, ss); });
    };
    r.map = map_layer(2);
    r.quadrature_change = shading_error(map_layer(1), r.map, r.image).relative_l2;
  }
  r.mixture = layer(
      scene, images, [&](const EnvImage& im) { return mixture_diffuse_reference(m, im); },
      [&](const EnvImage& im, double a, double f0) { return integrate_specular(recon, im, a, f0, 2); });
  r.approximation = layer(
      scene, images, [&](const EnvImage& im) { return mixture_diffuse_method(m, im, diffuse_method); },
      [&](const EnvImage& im, double a, double f0) { return mixture_specular_method(m, im, specular_method, a, f0); });
  return r;
}

}  // namespace sglab::render
