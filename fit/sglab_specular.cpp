// sglab-specular: the six constants of this project's own specular approximation (core
// specular_sglab.hpp; write-up paper_tables/own_specular.md): nu_slope, inflation, light_weight,
// light_floor, horizon_depth, horizon_rate.
//
// Grid: the rows of `sglab sweep specular` (core specular_grid.hpp: α ∈ {0.01 … 1} 9 values × λ ∈
// {1 … 1e4} × view_cos ∈ {1, 0.7, 0.3, 0.1} × the light positions above the horizon, f0 = 0.04),
// references by the adaptive quadrature of glossy_reference.hpp. The targets are the sweep's own
// measures, so the fit minimizes what the table reports:
//   J = mean over points of Σ|v − r|/Σr  (brightness-weighted error)
//     + mean over bright rows (r ≥ 10 % of the point's peak) of |v − r|/r   (≈ bright SMAPE).
// Why L1 and not minimax: the brightness weighting is the quantity a renderer sees; a minimax over
// relative errors would be ruled by dim tail rows (a light three widths off the lobe), which the
// weighting rightly discounts. J is a sum of absolute values: it is solved by iteratively
// reweighted least squares (each round one Ceres Levenberg–Marquardt solve of Σ c_k e_k²/|e_k'|,
// e_k' the previous round's residual, floored at 1e-4), the round with the smallest J kept.
// Stiff points (the stability atlas's grid) are not in the objective: the form is finite and ≥ 0
// by construction (its clamps), which tests/specular_test.cpp checks on the stiff grid.
// Start: the values of the exploratory Nelder–Mead fit of the same objective (scipy), rounded.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>

#include <tbb/parallel_for.h>

#include "fits.hpp"
#include "sglab/error_metrics.hpp"
#include "sglab/registry.hpp"
#include "sglab/specular_sglab.hpp"
#include "sglab/specular_grid.hpp"

namespace sglab::fit {
namespace sglab_specular_detail {

constexpr int kRounds = 12;
constexpr double kResidualFloor = 1e-4;
constexpr double kBrightCutoff = 0.1;  // as the sweep's bright SMAPE (sweep_specular.hpp)

struct Row {
  std::array<double, 6> in;  // roughness, light_sharpness, light_cos, view_cos, light_azimuth, f0
  double reference;
  std::size_t point;
};

struct Data {
  std::vector<Row> rows;
  std::vector<double> point_sum;   // Σ r over each point's rows
  std::vector<double> point_peak;  // max r over each point's rows
  std::size_t bright_rows = 0;
};

Data make_data(bool quick) {
  Data out;
  const SpecularGrid g = specular_grid(quick);
  std::size_t point = 0;
  for (double a : g.roughness)
    for (double l : g.light_sharpness)
      for (double v : g.view_cos) {
        for (const auto& p : specular_light_positions(a, l, v))
          out.rows.push_back({{a, l, p.light_cos, v, p.light_azimuth, g.f0}, 0.0, point});
        ++point;
      }
  // The references through the process's kept values: `sweep specular` integrates the same rows
  // (its quick grid is this fit's quick grid), so a `sglab reproduce` integrates them once.
  const Quantity& specular = *find_quantity("specular");
  tbb::parallel_for(std::size_t(0), out.rows.size(), [&](std::size_t i) {
    out.rows[i].reference = reference_value(specular, out.rows[i].in);
  });
  out.point_sum.assign(point, 0.0);
  out.point_peak.assign(point, 0.0);
  for (const auto& r : out.rows) {
    out.point_sum[r.point] += r.reference;
    out.point_peak[r.point] = std::max(out.point_peak[r.point], r.reference);
  }
  for (const auto& r : out.rows)
    if (r.reference >= kBrightCutoff * out.point_peak[r.point]) ++out.bright_rows;
  return out;
}

// The rows of the full grid, or of the --quick grid (`sglab sweep specular --quick`'s), with their
// references, computed once.
const Data& data(bool quick) {
  if (quick) {
    static const Data coarse = make_data(true);
    return coarse;
  }
  static const Data full = make_data(false);
  return full;
}

// One residual entry: row `row` scaled by `scale` (1/Σr of its point, or 1/r for a bright row),
// with the objective's coefficient c (1/points or 1/bright rows).
struct Entry {
  std::size_t row;
  double scale, c;
};

struct Model {
  const Data* d;
  std::vector<Entry> entries;
  template <class T>
  T operator()(const T* p, std::size_t k) const {
    const Entry& e = entries[k];
    const auto& x = d->rows[e.row].in;
    const SpecularInput<T> in{T(x[0]), T(x[1]), T(x[2]), T(x[3]), T(x[4]), T(x[5])};
    const SglabSpecularParams<T> c{p[0], p[1], p[2], p[3], p[4], p[5]};
    return specular_sglab(in, c) * T(e.scale);
  }
};
using Residual = GridResidual<Model>;

Residual problem(const Data& d) {
  Residual f;
  f.model.d = &d;
  const double points = double(d.point_sum.size());
  for (std::size_t i = 0; i < d.rows.size(); ++i) {
    const Row& r = d.rows[i];
    f.model.entries.push_back({i, 1.0 / d.point_sum[r.point], 1.0 / points});
    if (r.reference >= kBrightCutoff * d.point_peak[r.point])
      f.model.entries.push_back({i, 1.0 / r.reference, 1.0 / double(d.bright_rows)});
  }
  for (const auto& e : f.model.entries) {
    f.target.push_back(d.rows[e.row].reference * e.scale);
    f.sqrt_w.push_back(std::sqrt(e.c));
  }
  return f;
}

// The sweep's measures at x: brightness-weighted error, bright SMAPE, the worst roughness's
// brightness-weighted error.
struct Measures {
  double weighted = 0, bright_smape = 0, worst_roughness = 0;
};
Measures measures(const Data& d, const std::vector<double>& x) {
  const SglabSpecularParams<double> c{x[0], x[1], x[2], x[3], x[4], x[5]};
  std::vector<metrics::BrightnessWeighted> point(d.point_sum.size());
  Measures m;
  for (const auto& r : d.rows) {
    const auto& a = r.in;
    const double v = specular_sglab<double>({a[0], a[1], a[2], a[3], a[4], a[5]}, c);
    point[r.point].add(v, r.reference);
    if (r.reference >= kBrightCutoff * d.point_peak[r.point])
      m.bright_smape += metrics::smape(v, r.reference) / double(d.bright_rows);
  }
  std::map<double, std::pair<double, int>> by_alpha;
  for (const auto& r : d.rows) by_alpha[r.in[0]];  // the roughness values
  std::vector<bool> seen(point.size(), false);
  for (const auto& r : d.rows) {
    if (seen[r.point]) continue;
    seen[r.point] = true;
    const double err = point[r.point].value();
    m.weighted += err / double(point.size());
    by_alpha[r.in[0]].first += err;
    by_alpha[r.in[0]].second += 1;
  }
  for (const auto& [a, s] : by_alpha) m.worst_roughness = std::max(m.worst_roughness, s.first / s.second);
  return m;
}

// The exploratory fit's values (see the header), the start of the first round.
const std::vector<double> kStart = {2.9, 0.98, 1.2, 2.0, 0.42, 1.0};

// Bounds of nu_slope, inflation, light_weight, light_floor, horizon_depth, horizon_rate.
FitStatement stated() {
  return {"sglab-specular",
          "sglab's own specular approximation (an SG light off GGX): the t-smoothing, light and horizon constants",
          "sglab (this project); start: an exploratory Nelder-Mead fit of the same objective",
          {"l1-weighted"},
          fitted_parameters<SglabSpecular>({{1e-2, 100}, {0, 10}, {0, 5}, {0, 50}, {0, 0.95}, {1e-2, 20}})};
}

FitSpec make_spec(const std::vector<double>& start, bool quick = false) {
  FitSpec spec = fit_spec(stated());
  spec.objective =
      "L1: brightness-weighted error + bright relative error on the sweep grid, IRLS of Ceres least squares";
  const SpecularGrid g = specular_grid(quick);
  spec.domain = "the rows of `sglab sweep specular" + std::string(quick ? " --quick" : "") + "` (" +
                std::to_string(g.roughness.size()) + " roughness x " + std::to_string(g.light_sharpness.size()) +
                " light sharpness x " + std::to_string(g.view_cos.size()) + " view_cos x light positions, f0 = 0.04)";
  spec.starts = {start};
  return spec;
}

FitResult solve_irls(const Data& d, bool quick) {
  Residual f = problem(d);
  std::string trajectory;
  std::vector<Measures> by_round;
  const std::vector<double> c = [&] {
    std::vector<double> out;
    for (const auto& e : f.model.entries) out.push_back(e.c);
    return out;
  }();
  const auto irls = [&](int round, const std::vector<double>& x) {
    const Measures m = by_round.emplace_back(measures(d, x));
    char buf[96];
    std::snprintf(buf, sizeof buf, "%sround %d: %.4f + %.4f", trajectory.empty() ? "" : "; ", round, m.weighted,
                  m.bright_smape);
    trajectory += buf;
    // IRLS toward Σ c_k|e_k|: weights c_k/|e_k|.
    for (std::size_t k = 0; k < c.size(); ++k) {
      const double e = std::abs(f.model(x.data(), k) - f.target[k]);
      f.sqrt_w[k] = std::sqrt(c[k] / std::max(e, kResidualFloor));
    }
    return m.weighted + m.bright_smape;
  };
  ReweightedFit best = solve_reweighted<6>(
      f, kStart, kRounds, [&](const std::vector<double>& x) { return make_spec(x, quick); }, irls);
  const Measures& best_m = by_round[std::size_t(best.round)];
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "on the fit grid (%zu rows, %zu points): brightness-weighted error %.4f, bright SMAPE %.4f, worst "
                "roughness's brightness-weighted error %.4f",
                d.rows.size(), d.point_sum.size(), best_m.weighted, best_m.bright_smape, best_m.worst_roughness);
  best.result.notes.push_back(buf);
  best.result.notes.push_back("IRLS (brightness-weighted + bright SMAPE) by round: " + trajectory);
  return best.result;
}

}  // namespace sglab_specular_detail

Fitter sglab_specular_fitter() {
  using namespace sglab_specular_detail;
  return fitter(stated(), [](const FitOptions& o) { return solve_irls(data(o.quick), o.quick); });
}

}  // namespace sglab::fit
