// The scene's shapes as the renderer's ray-casting kernels read them (simd/render_table.hpp
// Occluders): the VPL visibility of the reference (reference.cpp) and the shadow maps' depth
// (shadow_map.cpp). Internal to sglab_render.
#pragma once

#include <variant>
#include <vector>

#include "sglab/render/scene.hpp"
#include "simd/render_table.hpp"

namespace sglab::render {

struct OccluderArrays {
  std::vector<double> box, rectangle, sphere;
  explicit OccluderArrays(const Scene& scene) {
    for (const auto& object : scene.objects) {
      if (const auto* b = std::get_if<Box>(&object.shape)) {
        box.insert(box.end(), {b->min.x(), b->min.y(), b->min.z(), b->max.x(), b->max.y(), b->max.z()});
      } else if (const auto* r = std::get_if<Rectangle>(&object.shape)) {
        const Vec3 n = r->edge_u.cross(r->edge_v).normalized();  // as intersect(Rectangle) has it
        rectangle.insert(rectangle.end(), {r->corner.x(), r->corner.y(), r->corner.z(), r->edge_u.x(), r->edge_u.y(),
                                           r->edge_u.z(), r->edge_v.x(), r->edge_v.y(), r->edge_v.z(), n.x(), n.y(),
                                           n.z(), r->edge_u.squaredNorm(), r->edge_v.squaredNorm()});
      } else if (const auto* sp = std::get_if<Sphere>(&object.shape)) {
        sphere.insert(sphere.end(), {sp->center.x(), sp->center.y(), sp->center.z(), sp->radius});
      }
    }
  }
  simd_detail::Occluders view() const {
    return {box.size() / 6, rectangle.size() / 14, sphere.size() / 4, box.data(), rectangle.data(), sphere.data()};
  }
};

}  // namespace sglab::render
