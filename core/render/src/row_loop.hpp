// The renderer's row-parallel loops and its stage timer, shared by the pipeline (pipeline.cpp) and
// the passes over indirect light (filtering.cpp, denoise.cpp). Private to the renderer's sources.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <string_view>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/render/reference.hpp"

namespace sglab::render {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Runs row_body(j) for every j in [0, rows), in parallel over rows, reporting progress(stage, ·) at 0,
// in 5 % steps and at 1 (none when progress is empty).
template <class RowBody>
void for_each_row(int rows, std::string_view stage, const std::function<void(std::string_view, double)>& progress,
                  const RowBody& row_body) {
  std::atomic<int> done{0}, reported{0};
  if (progress) progress(stage, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j < r.end(); ++j) {
      row_body(j);
      const int n = ++done;
      if (progress) {
        const int step = 20 * n / rows;  // 0 … 20
        int last = reported.load();
        while (step > last && !reported.compare_exchange_weak(last, step)) {
        }
        if (step > last && step < 20) progress(stage, step / 20.0);
      }
    }
  });
  if (progress) progress(stage, 1.0);
}

// Runs body(k, i, j) for k = j·width + i, i in [0, width), j in [0, rows): for_each_row over the rows.
template <class Body>
void for_each_pixel(int width, int rows, std::string_view stage,
                    const std::function<void(std::string_view, double)>& progress, const Body& body) {
  for_each_row(rows, stage, progress, [&](int j) {
    for (int i = 0; i < width; ++i) body(std::size_t(j) * std::size_t(width) + std::size_t(i), i, j);
  });
}

// out[k] = reference_radiance(*point_of(k), vpls, visibility_scene, precision) for every pixel k
// = j·width + i whose point_of(k) is not null, rows in parallel: each row's points go through
// reference_radiances in order, so neighbours of the same kind share a pass over the VPLs.
template <class PointOf>
void reference_rows(int width, int rows, std::string_view stage,
                    const std::function<void(std::string_view, double)>& progress, const VplList& vpls,
                    const Scene* visibility_scene, Precision precision, const PointOf& point_of,
                    std::vector<Rgb>& out) {
  for_each_row(rows, stage, progress, [&](int j) {
    thread_local std::vector<const ShadingPoint*> points;
    thread_local std::vector<std::size_t> pixels;
    thread_local std::vector<Rgb> values;
    points.clear();
    pixels.clear();
    for (int i = 0; i < width; ++i) {
      const std::size_t k = std::size_t(j) * std::size_t(width) + std::size_t(i);
      if (const ShadingPoint* p = point_of(k)) {
        points.push_back(p);
        pixels.push_back(k);
      }
    }
    values.resize(points.size());
    reference_radiances(points, vpls, values, visibility_scene, precision);
    for (std::size_t n = 0; n < points.size(); ++n) out[pixels[n]] = values[n];
  });
}

}  // namespace sglab::render
