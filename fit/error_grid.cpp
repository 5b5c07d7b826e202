// The standard error grids of `sglab error-vs-time` (fit/error_grid.hpp).
#include "error_grid.hpp"

#include <cmath>
#include <map>
#include <mutex>
#include <span>
#include <string>

#include <tbb/parallel_for.h>

#include "sglab/error_metrics.hpp"
#include "sglab/scalar.hpp"

namespace sglab::fit {

DiffuseAxes diffuse_grid_axes(bool quick) {
  const int per_decade = quick ? 2 : 4, cos_steps = quick ? 20 : 40;
  DiffuseAxes a;
  for (int i = 0; i <= 7 * per_decade; ++i) a.sharpnesses.push_back(std::pow(10.0, -3 + double(i) / per_decade));
  for (int j = 0; j <= cos_steps; ++j) a.cosines.push_back(-1 + 2.0 * j / cos_steps);
  return a;
}

SpecularGridPoints specular_grid_points(bool quick) {
  SpecularGridPoints p;
  p.roughnesses = quick ? std::vector<double>{0.05, 0.2, 0.5, 1}
                        : std::vector<double>{0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1};
  p.light_sharpnesses = quick ? std::vector<double>{10, 100} : std::vector<double>{1, 10, 100, 1000};
  const std::vector<double> views = {0.9, 0.5, 0.2};
  const std::vector<double> tilts = {0, 0.1, 0.3, 0.6};  // radians from the mirror direction
  const double f0 = 0.04;
  const double pi = sglab::pi<double>();
  for (double a : p.roughnesses)
    for (double l : p.light_sharpnesses)
      for (double v : views)
        for (double d : tilts) {
          // Mirror of ωo = (√(1−v²), 0, v) is at polar angle θ = acos v, azimuth π. Tilting by d
          // towards the normal gives polar angle θ − d (through the normal if d > θ: azimuth 0).
          const double theta = std::acos(v) - d;
          p.args.insert(p.args.end(), {a, l, std::cos(theta), v, theta >= 0 ? pi : 0.0, f0});
        }
  p.per_peak = tilts.size();
  return p;
}

void fill_reference(ReferenceGrid& g, const Method& ref) {
  const std::size_t n = g.args.size() / g.arity;
  g.reference.assign(n, 0);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) {
    g.reference[k] = ref.eval_double(std::span<const double>(&g.args[g.arity * k], g.arity));
  });
}

ReferenceGrid diffuse_reference_grid(const Method& ref, bool quick) {
  ReferenceGrid g;
  g.arity = 2;
  const DiffuseAxes axes = diffuse_grid_axes(quick);
  const std::vector<double>& ls = axes.sharpnesses;
  const std::vector<double>& cs = axes.cosines;
  for (double l : ls)
    for (double c : cs) g.args.insert(g.args.end(), {l, c});
  fill_reference(g, ref);
  for (std::size_t i = 0; i < ls.size(); ++i)
    for (std::size_t j = 0; j < cs.size(); ++j) g.scale.push_back(g.reference[i * cs.size() + cs.size() - 1]);
  return g;
}

GridError standard_grid_error(const Quantity& q, const Method& m) {
  static std::mutex mutex;
  static std::map<std::string, ReferenceGrid> grids;
  const ReferenceGrid* g;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = grids.find(q.name);
    if (it == grids.end()) it = grids.emplace(q.name, diffuse_reference_grid(*q.find(q.reference_method), false)).first;
    g = &it->second;
  }
  metrics::RootMeanSquare rms;
  for (std::size_t k = 0; k < g->size(); ++k) {
    const std::span<const double> a(&g->args[g->arity * k], g->arity);
    if (m.domain_error && m.domain_error(a)) continue;
    const double v = m.eval_double(a);
    if (!std::isfinite(v)) continue;
    rms.add(std::fabs(v - g->reference[k]) / g->scale[k]);
  }
  return {rms.max, rms.rms()};
}

}  // namespace sglab::fit
