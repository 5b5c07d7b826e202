// What the two passes over indirect light share (filtering.cpp: upsampling; denoise.cpp: filtering a
// noisy full-resolution image): the G-buffer samples with their lobes, the split of a VPL sum into its
// diffuse and specular parts, demodulation and the per-receiver errors (the row-parallel loop: row_loop.hpp).
// Private to the renderer's sources.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <string_view>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/render/filtering.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "row_loop.hpp"

namespace sglab::render::filtering_detail {

// The sample seen through image point (px, py) (full-resolution pixel units) with its lobes.
// pixel_angle: the angle one pixel of this sample's grid subtends (its footprint is depth × that).
FilterSample sample_at(const Scene& scene, double px, double py, double pixel_angle);

// The full-resolution G-buffer of the scene's camera: samples, hit and glossy masks.
void fill_full_gbuffer(const Scene& scene, const std::function<void(std::string_view, double)>& progress,
                       std::vector<FilterSample>& full, std::vector<char>& hit, std::vector<char>& glossy);

// The VPL sum of each part at a point: (diffuse, specular), each with the other layer switched off.
std::pair<Rgb, Rgb> split_vpl_sum(const ShadingPoint& point, const VplList& vpls);

// The exact VPL sum at every valid sample (0 elsewhere): `given` if not null (its size must be the
// samples'; std::invalid_argument otherwise), else computed, with `seconds` set to the seconds that
// took (left as it is when the reference was given: nothing was computed).
void fill_reference(const std::vector<FilterSample>& full, const VplList& vpls, const std::vector<Rgb>* given,
                    int width, const std::function<void(std::string_view, double)>& progress,
                    std::vector<Rgb>& reference, double& seconds);

// The scene's reflective shadow map at `resolution` and its VPLs,
// with `seconds` set to the seconds they took.
struct RsmVpls {
  ReflectiveShadowMap rsm;
  VplList vpls;
};
RsmVpls render_rsm_vpls(const Scene& scene, int resolution, double& seconds);

// Per-channel a/b with 0 where b is 0.
Rgb demodulate(const Rgb& value, const Rgb& reflectance);

bool has_part(const FilterSample& s, bool specular);

// image_error over all hit pixels, glossy receivers and the other (diffuse) receivers.
struct ReceiverErrors {
  ImageError all, glossy, diffuse;
};
ReceiverErrors receiver_errors(const std::vector<Rgb>& value, const std::vector<Rgb>& reference,
                               const std::vector<char>& hit, const std::vector<char>& glossy);

// Sets r.all, r.glossy and r.diffuse to the receiver errors of `value` against in.reference over
// in's hit and glossy masks.
template <class Result, class Inputs>
void set_receiver_errors(Result& r, const std::vector<Rgb>& value, const Inputs& in) {
  const ReceiverErrors e = receiver_errors(value, in.reference, in.hit, in.glossy);
  r.all = e.all;
  r.glossy = e.glossy;
  r.diffuse = e.diffuse;
}

}  // namespace sglab::render::filtering_detail
