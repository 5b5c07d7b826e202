// The exact VPL sum (reference.hpp).
#include "sglab/render/reference.hpp"

#include <cmath>
#include <algorithm>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "sglab/render/material_brdf.hpp"
#include "sglab/render/visibility.hpp"
#include "occluder_arrays.hpp"
#include "simd/render_table.hpp"

namespace sglab::render {
namespace {

// ---- the vectorized sum: the same terms over the VPL arrays (simd/render_kernels_vpl.hpp) ------

template <class T>
simd_detail::VplView<T> view_of(const VplArraysT<T>& a, const T* visible) {
  simd_detail::VplView<T> v;
  v.n = a.x.size();
  v.x = a.x.data(), v.y = a.y.data(), v.z = a.z.data(), v.nx = a.nx.data(), v.ny = a.ny.data(), v.nz = a.nz.data();
  v.ix = a.ix.data(), v.iy = a.iy.data(), v.iz = a.iz.data(), v.r2 = a.r2.data();
  v.lambert_r = a.lambert_r.data(), v.lambert_g = a.lambert_g.data(), v.lambert_b = a.lambert_b.data();
  v.flux_r = a.flux_r.data(), v.flux_g = a.flux_g.data(), v.flux_b = a.flux_b.data();
  v.f0_r = a.f0_r.data(), v.f0_g = a.f0_g.data(), v.f0_b = a.f0_b.data();
  v.alpha = a.alpha.data(), v.cos_incoming = a.cos_incoming.data(), v.smith_in = a.smith_in.data();
  v.visible = visible;
  return v;
}

// V(y_p, x_i) of every VPL in the arrays' order (each array padded with 0), by the vectorized ray
// casting of vpl_visible; 0 where the term is already 0 by its cosines.
template <class T>
struct VisibilityMasks {
  std::vector<T> lambert, glossy;
  std::vector<double> scratch;
  void fill(const VplList& list, const ShadingPoint& p, const Scene& scene) {
    const OccluderArrays shapes(scene);
    const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
    const double position[3] = {p.position.x(), p.position.y(), p.position.z()};
    const double normal[3] = {p.normal.x(), p.normal.y(), p.normal.z()};
    for (auto [arrays, mask] : {std::pair{&list.lambert, &lambert}, std::pair{&list.glossy, &glossy}}) {
      mask->resize(arrays->x.size());
      scratch.resize(8 * simd_detail::kVisibilityBlock);
      simd_detail::VplView<double> v{};
      v.n = arrays->x.size();
      v.x = arrays->x.data(), v.y = arrays->y.data(), v.z = arrays->z.data();
      v.nx = arrays->nx.data(), v.ny = arrays->ny.data(), v.nz = arrays->nz.data();
      if constexpr (std::is_same_v<T, float>)
        t.visibility_f(v, position, normal, shapes.view(), scratch.data(), mask->data());
      else t.visibility_d(v, position, normal, shapes.view(), scratch.data(), mask->data());
    }
  }
};

template <class T>
simd_detail::Receiver<T> receiver_of(const ShadingPoint& p) {
  simd_detail::Receiver<T> r{T(p.position.x()),
                             T(p.position.y()),
                             T(p.position.z()),
                             T(p.normal.x()),
                             T(p.normal.y()),
                             T(p.normal.z()),
                             T(p.view.x()),
                             T(p.view.y()),
                             T(p.view.z()),
                             {},
                             {},
                             T(p.roughness),
                             T(p.normal.dot(p.view))};
  for (int c = 0; c < 3; ++c) {
    r.rd[c] = T(p.diffuse_reflectance(c) / std::numbers::pi);
    r.f0[c] = T(p.f0(c));
  }
  return r;
}

template <class T>
void vpl_sums(const simd_detail::VplSumFn<T>* sum, const VplArraysT<T>& lambert, const VplArraysT<T>& glossy,
              const ShadingPoint& p, const VisibilityMasks<T>* masks, double* out) {
  const simd_detail::Receiver<T> r = receiver_of<T>(p);
  const int glossy_receiver = p.glossy() ? 1 : 0;
  sum[glossy_receiver](view_of(lambert, masks ? masks->lambert.data() : nullptr), r, out);
  sum[2 + glossy_receiver](view_of(glossy, masks ? masks->glossy.data() : nullptr), r, out);
}

// vpl_sums of two points of the same kind (p.glossy() == p2.glossy()) in one pass per array.
template <class T>
void vpl_sums2(const simd_detail::VplSum2Fn<T>* sum2, const VplArraysT<T>& lambert, const VplArraysT<T>& glossy,
               const ShadingPoint& p, const ShadingPoint& p2, const VisibilityMasks<T>* masks,
               const VisibilityMasks<T>* masks2, double* out, double* out2) {
  const simd_detail::Receiver<T> r = receiver_of<T>(p), r2 = receiver_of<T>(p2);
  const int glossy_receiver = p.glossy() ? 1 : 0;
  sum2[glossy_receiver](view_of(lambert, masks ? masks->lambert.data() : nullptr),
                        masks2 ? masks2->lambert.data() : nullptr, r, r2, out, out2);
  sum2[2 + glossy_receiver](view_of(glossy, masks ? masks->glossy.data() : nullptr),
                            masks2 ? masks2->glossy.data() : nullptr, r, r2, out, out2);
}

template <class T>
void put(std::vector<T>& c, double value) {
  c.push_back(T(value));
}

template <class T>
void push_padded(VplArraysT<T>& a, const Vpl* v) {
  if (!v) {  // padding: normal 0, so ⟨ω·n_i⟩ = 0 and the term is masked
    for (auto* c :
         {&a.x, &a.y, &a.z, &a.nx, &a.ny, &a.nz, &a.ix, &a.iy, &a.iz, &a.lambert_r, &a.lambert_g, &a.lambert_b})
      put(*c, 0.0);
    put(a.r2, 1.0);
    return;
  }
  put(a.x, v->position.x());
  put(a.y, v->position.y());
  put(a.z, v->position.z());
  put(a.nx, v->normal.x());
  put(a.ny, v->normal.y());
  put(a.nz, v->normal.z());
  put(a.ix, v->incoming.x());
  put(a.iy, v->incoming.y());
  put(a.iz, v->incoming.z());
  put(a.r2, v->footprint_radius * v->footprint_radius);
  const Rgb lambert = v->flux * v->diffuse_reflectance / std::numbers::pi;
  put(a.lambert_r, lambert(0));
  put(a.lambert_g, lambert(1));
  put(a.lambert_b, lambert(2));
}

template <class T>
void push_glossy(VplArraysT<T>& a, const Vpl* v) {
  put(a.flux_r, v ? v->flux(0) : 0.0);
  put(a.flux_g, v ? v->flux(1) : 0.0);
  put(a.flux_b, v ? v->flux(2) : 0.0);
  put(a.f0_r, v ? v->f0(0) : 0.0);
  put(a.f0_g, v ? v->f0(1) : 0.0);
  put(a.f0_b, v ? v->f0(2) : 0.0);
  put(a.alpha, v ? v->roughness : 1.0);
  put(a.cos_incoming, v ? v->normal.dot(v->incoming) : 0.0);
  a.smith_in.push_back(simd_detail::ggx_smith_root(T(a.alpha.back() * a.alpha.back()), a.cos_incoming.back()));
}

template <class T>
void fill_arrays(const std::vector<Vpl>& vpls, VplArraysT<T>& lambert, VplArraysT<T>& glossy) {
  lambert = VplArraysT<T>{};
  glossy = VplArraysT<T>{};
  for (const Vpl& v : vpls) {
    VplArraysT<T>& a = v.glossy() ? glossy : lambert;
    push_padded(a, &v);
    if (v.glossy()) push_glossy(a, &v);
    ++a.count;
  }
  for (VplArraysT<T>* a : {&lambert, &glossy}) {
    while (a->x.size() % VplArraysT<T>::kVplLanes != 0) {
      push_padded(*a, nullptr);
      if (a == &glossy) push_glossy(*a, nullptr);
    }
  }
}

}  // namespace

VplList prepare_vpls(const ReflectiveShadowMap& rsm) {
  VplList list;
  for (const Vpl& v : rsm.texels) {
    if (!v.valid || !(v.flux > 0).any()) continue;
    list.vpls.push_back(v);
    list.any_glossy = list.any_glossy || v.glossy();
  }
  prepare_vpl_arrays(list);
  return list;
}

void prepare_vpl_arrays(VplList& list) {
  fill_arrays(list.vpls, list.lambert, list.glossy);
  fill_arrays(list.vpls, list.lambert_float, list.glossy_float);
}

namespace {

template <class T>
Rgb sum_with(const simd_detail::VplSumFn<T>* sum, const VplArraysT<T>& lambert, const VplArraysT<T>& glossy,
             const ShadingPoint& p, const VplList& list, const Scene* visibility_scene) {
  double out[3] = {0, 0, 0};
  if (visibility_scene) {
    thread_local VisibilityMasks<T> masks;  // reused: one allocation per thread, not per point
    masks.fill(list, p, *visibility_scene);
    vpl_sums(sum, lambert, glossy, p, &masks, out);
  } else {
    vpl_sums<T>(sum, lambert, glossy, p, nullptr, out);
  }
  return Rgb(out[0], out[1], out[2]);
}

template <class T>
void sums_with(const simd_detail::VplSumFn<T>* sum, const simd_detail::VplSum2Fn<T>* sum2, const VplArraysT<T>& lambert,
               const VplArraysT<T>& glossy, std::span<const ShadingPoint* const> points, const VplList& list,
               const Scene* visibility_scene, std::span<Rgb> out) {
  thread_local VisibilityMasks<T> masks, masks2;
  std::size_t k = 0;
  while (k < points.size()) {
    const ShadingPoint& p = *points[k];
    if (k + 1 == points.size() || points[k + 1]->glossy() != p.glossy()) {
      out[k] = sum_with(sum, lambert, glossy, p, list, visibility_scene);
      ++k;
      continue;
    }
    const ShadingPoint& p2 = *points[k + 1];
    if (visibility_scene) {
      masks.fill(list, p, *visibility_scene);
      masks2.fill(list, p2, *visibility_scene);
    }
    double o[3] = {0, 0, 0}, o2[3] = {0, 0, 0};
    vpl_sums2(sum2, lambert, glossy, p, p2, visibility_scene ? &masks : nullptr, visibility_scene ? &masks2 : nullptr,
              o, o2);
    out[k] = Rgb(o[0], o[1], o[2]);
    out[k + 1] = Rgb(o2[0], o2[1], o2[2]);
    k += 2;
  }
}

// A list built by hand (its arrays not filled) as prepare_vpls would have prepared it.
bool prepared(const VplList& list) {
  return list.lambert.count + list.glossy.count == list.vpls.size() &&
         list.lambert_float.count + list.glossy_float.count == list.vpls.size();
}

}  // namespace

// One point: reference_radiances' lone-point path (sum_with).
Rgb reference_radiance(const ShadingPoint& p, const VplList& list, const Scene* visibility_scene, Precision precision) {
  const ShadingPoint* const points[1] = {&p};
  Rgb out[1];
  reference_radiances(points, list, out, visibility_scene, precision);
  return out[0];
}

void reference_radiances(std::span<const ShadingPoint* const> points, const VplList& list, std::span<Rgb> out,
                         const Scene* visibility_scene, Precision precision) {
  if (out.size() != points.size())
    throw std::invalid_argument("reference_radiances: " + std::to_string(points.size()) + " points, " +
                                std::to_string(out.size()) + " outputs");
  if (!prepared(list)) {  // built by hand: convert
    VplList copy = list;
    prepare_vpl_arrays(copy);
    return reference_radiances(points, copy, out, visibility_scene, precision);
  }
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  if (precision == Precision::single)
    sums_with(t.vpl_sum_f, t.vpl_sum2_f, list.lambert_float, list.glossy_float, points, list, visibility_scene, out);
  else sums_with(t.vpl_sum_d, t.vpl_sum2_d, list.lambert, list.glossy, points, list, visibility_scene, out);
}

}  // namespace sglab::render
