// The stability atlas's verdicts, tallies, cells and grids (stability_atlas.hpp).
#include "stability_atlas.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sglab/stiff_cases.hpp"

namespace sglab::experiments::atlas {

std::string_view flag_name(Flag f) {
  switch (f) {
    case Flag::ok: return "ok";
    case Flag::out_of_domain: return "out-of-domain";
    case Flag::wrong_relative: return "wrong-relative";
    case Flag::wrong: return "wrong";
    case Flag::throws: return "throws";
    case Flag::negative: return "negative";
    case Flag::inf: return "inf";
    case Flag::nan: return "nan";
  }
  return "?";
}

double tiny_of(Precision p) {
  return p == Precision::float32 ? double(std::numeric_limits<float>::min()) : std::numeric_limits<double>::min();
}

Assessment assess(const Evaluation& e, double tiny) {
  Assessment a;
  if (e.out_of_domain) {
    a.flag = Flag::out_of_domain;
    return a;
  }
  if (e.threw) {
    a.flag = Flag::throws;
    return a;
  }
  if (std::isnan(e.value)) {
    a.flag = Flag::nan;
    return a;
  }
  if (std::isinf(e.value)) {
    a.flag = Flag::inf;
    return a;
  }
  // Every quantity of the atlas is the integral (or the parameter) of a non-negative function;
  // a reference below 0 would mean the "true value" is negative and a negative output no flaw.
  a.negative = e.value < 0 && !(e.reference < 0);
  if (std::isfinite(e.reference)) {
    const double diff = std::fabs(e.value - e.reference);
    const double scale = std::max(std::fabs(e.reference), tiny);
    a.rel_error = diff / scale;
    // Without a peak (no cosine axis, or the reference only on a subset) the peak is |ref| itself.
    const double peak = std::isfinite(e.peak) ? std::max(e.peak, scale) : scale;
    a.peak_error = diff / peak;
    a.wrong_relative = a.rel_error > kWrongTolerance;
    a.wrong_peak = a.peak_error > kWrongTolerance;
  }
  if (std::isfinite(e.exact)) {
    const double diff = std::fabs(e.value - e.exact);
    a.rounding_rel = diff / std::max(std::fabs(e.exact), tiny);
    if (std::isfinite(e.self_peak)) a.rounding_peak = diff / std::max({e.self_peak, std::fabs(e.exact), tiny});
  }
  a.flag = a.negative         ? Flag::negative
           : a.wrong_peak     ? Flag::wrong
           : a.wrong_relative ? Flag::wrong_relative
                              : Flag::ok;
  return a;
}

namespace {
void keep_worst(Worst& w, double error, std::size_t row, double value, double target) {
  if (std::isnan(error) || error <= w.error) return;  // strictly larger: the first row wins ties
  w.error = error;
  w.row = row;
  w.value = value;
  w.target = target;
}
}  // namespace

void Tally::add(std::size_t row, const Evaluation& e, double tiny) {
  if (e.skipped) return;
  const Assessment a = assess(e, tiny);
  ++points;
  switch (a.flag) {
    case Flag::out_of_domain: ++out_of_domain; break;
    case Flag::throws: ++throws; break;
    case Flag::nan: ++nan; break;
    case Flag::inf: ++inf; break;
    default: break;
  }
  if (a.negative) ++negative;
  if (!std::isnan(a.rel_error)) {
    ++compared;
    if (a.wrong_relative) ++wrong_relative;
    if (a.wrong_peak) ++wrong_peak;
    keep_worst(rel_error, a.rel_error, row, e.value, e.reference);
    keep_worst(peak_error, a.peak_error, row, e.value, e.reference);
  }
  if (!std::isnan(a.rounding_rel)) {
    ++rounding_points;
    keep_worst(rounding_rel, a.rounding_rel, row, e.value, e.exact);
    keep_worst(rounding_peak, a.rounding_peak, row, e.value, e.exact);
  }
  if (int(a.flag) > int(worst_flag)) {
    worst_flag = a.flag;
    worst_flag_row = row;
  }
}

Tally tally(std::span<const Evaluation> evaluations, double tiny) {
  Tally t;
  for (std::size_t r = 0; r < evaluations.size(); ++r) t.add(r, evaluations[r], tiny);
  return t;
}

// ---- grids ----------------------------------------------------------------------------------

std::vector<double> Grid::row(std::size_t r) const {
  std::vector<double> out(values.size());
  for (std::size_t c = 0; c < values.size(); ++c) out[c] = values[c][index(r, c)];
  return out;
}

std::size_t Grid::index(std::size_t r, std::size_t column) const {
  std::size_t stride = 1;
  for (std::size_t c = values.size(); c-- > column + 1;) stride *= values[c].size();
  return (r / stride) % values[column].size();
}

std::vector<std::size_t> Grid::y_line(std::size_t r) const {
  if (y_column < 0) return {r};
  std::size_t stride = 1;
  for (std::size_t c = values.size(); c-- > std::size_t(y_column) + 1;) stride *= values[c].size();
  const std::size_t first = r - y_index(r) * stride;
  std::vector<std::size_t> out;
  for (std::size_t j = 0; j < y_size(); ++j) out.push_back(first + j * stride);
  return out;
}

Grid make_grid(std::vector<std::string> names, std::vector<std::vector<double>> values, int x_column, int y_column,
               bool y_is_cosine) {
  Grid g;
  g.column_names = std::move(names);
  g.values = std::move(values);
  g.x_column = x_column;
  g.y_column = y_column;
  g.y_is_cosine = y_is_cosine;
  g.rows = 1;
  for (const auto& v : g.values) g.rows *= v.size();
  return g;
}

std::vector<double> column_values(ColumnKind kind, Level level) {
  constexpr double pi = std::numbers::pi;
  switch (kind) {
    case ColumnKind::sharpness:
    case ColumnKind::nonnegative: {
      // {0} ∪ 1e-8 … 1e8, then the extreme tail up to FLT_MAX and DBL_MAX (stiff_cases.hpp).
      std::vector<double> v = level == Level::full     ? stiff::sharpnesses(4)
                              : level == Level::coarse ? stiff::sharpnesses(1)
                                                       : std::vector<double>{0.0, 1e-8, 1e-2, 1.0, 1e2, 1e4, 1e8};
      const std::vector<double> tail = level == Level::full ? stiff::extreme_sharpnesses()
                                       : level == Level::coarse
                                           ? stiff::extreme_sharpnesses(true)
                                           : std::vector<double>{double(std::numeric_limits<float>::max()),
                                                                 std::numeric_limits<double>::max()};
      v.insert(v.end(), tail.begin(), tail.end());
      return v;
    }
    case ColumnKind::cosine: {
      if (level == Level::full) return stiff::cosines(32);
      if (level == Level::coarse) return stiff::cosines(8);
      const double f = stiff::float_after_one();
      return {-f, -1.0, -0.5, 0.0, 0.5, 1.0, f};
    }
    case ColumnKind::mean_length: return stiff::mean_lengths();
    case ColumnKind::positive:  // the GGX roughness α (the only positive column): α → 0 … 1
      if (level == Level::full) return {1e-4, 1e-3, 1e-2, 0.1, 0.5, 1.0};
      if (level == Level::coarse) return {1e-4, 1e-2, 0.2, 1.0};
      return {1e-4, 0.2, 1.0};
    case ColumnKind::unit_interval:  // view cosine (0 = grazing), f0
      if (level == Level::full) return {0.0, 1e-8, 0.04, 0.5, 1.0};
      if (level == Level::coarse) return {0.0, 1e-8, 0.5, 1.0};
      return {0.0, 0.5, 1.0};
    case ColumnKind::angle:
      if (level == Level::minimal) return {0.0, pi / 2, pi};
      return {0.0, pi / 2, pi, 3 * pi / 2, 2 * pi};
  }
  return {};
}

namespace {
Level lower(Level l) { return l == Level::full ? Level::coarse : Level::minimal; }

// The heat-map axes of a quantity: x = the first sharpness column (else the first column), y =
// the first cosine column (else the first other column).
std::pair<int, int> axes_of(const Quantity& q) {
  int x = -1, y = -1;
  for (std::size_t c = 0; c < q.columns.size(); ++c)
    if (x < 0 && q.columns[c].kind == ColumnKind::sharpness) x = int(c);
  if (x < 0) x = 0;
  for (std::size_t c = 0; c < q.columns.size(); ++c)
    if (y < 0 && int(c) != x && q.columns[c].kind == ColumnKind::cosine) y = int(c);
  for (std::size_t c = 0; c < q.columns.size(); ++c)
    if (y < 0 && int(c) != x) y = int(c);
  return {x, y};
}
}  // namespace

Grid registry_grid(const Quantity& q, bool quick) {
  const auto [x, y] = axes_of(q);
  const std::size_t n = q.columns.size();
  const Level axis = n <= 2 ? Level::full : Level::coarse;
  const Level other = n <= 3 ? Level::coarse : Level::minimal;
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
  for (std::size_t c = 0; c < n; ++c) {
    Level l = (int(c) == x || int(c) == y) ? axis : other;
    if (quick) l = lower(l);
    const Column& column = q.columns[c];
    names.push_back(column.name);
    if (column.stiff_values.empty()) values.push_back(column_values(column.kind, l));
    else
      values.push_back(quick && !column.stiff_values_quick.empty() ? column.stiff_values_quick : column.stiff_values);
  }
  const bool y_cos = y >= 0 && q.columns[std::size_t(y)].kind == ColumnKind::cosine;
  return make_grid(std::move(names), std::move(values), x, y, y_cos);
}

std::vector<char> spread_subset(std::span<const char> eligible, std::size_t n) {
  std::vector<std::size_t> pool;
  for (std::size_t r = 0; r < eligible.size(); ++r)
    if (eligible[r]) pool.push_back(r);
  std::vector<char> out(eligible.size(), 0);
  if (pool.size() <= n) {
    for (auto r : pool) out[r] = 1;
    return out;
  }
  // Weyl sequence frac(k/φ): equidistributed, and every prefix is spread over the whole pool.
  constexpr double inv_phi = 0.61803398874989484820;  // (√5 − 1)/2
  std::size_t chosen = 0;
  for (std::size_t k = 0; chosen < n; ++k) {
    const double u = std::fmod(0.5 + double(k) * inv_phi, 1.0);
    const std::size_t r = pool[std::min(pool.size() - 1, std::size_t(u * double(pool.size())))];
    if (!out[r]) {
      out[r] = 1;
      ++chosen;
    }
  }
  return out;
}

std::vector<double> line_peaks(const Grid& g, std::span<const double> values, bool require_complete) {
  std::vector<double> peak(g.rows, std::numeric_limits<double>::quiet_NaN());
  if (!g.y_is_cosine || values.size() != g.rows) return peak;
  for (std::size_t r = 0; r < g.rows; ++r) {
    if (g.y_index(r) != 0) continue;  // one pass per line, from its first row
    const auto line = g.y_line(r);
    double m = 0;
    std::size_t known = 0;
    for (auto k : line) {
      if (!std::isfinite(values[k])) continue;
      m = std::max(m, std::fabs(values[k]));
      ++known;
    }
    if (known == 0 || (require_complete && known < line.size())) continue;
    for (auto k : line) peak[k] = m;
  }
  return peak;
}

std::vector<Cell> cells(const Grid& g, std::span<const Evaluation> evaluations, double tiny) {
  std::vector<Cell> out(g.x_size() * g.y_size());
  for (std::size_t i = 0; i < g.x_size(); ++i)
    for (std::size_t j = 0; j < g.y_size(); ++j) {
      out[i * g.y_size() + j].x = i;
      out[i * g.y_size() + j].y = j;
    }
  auto fmax_nan = [](double& acc, double v) {
    if (std::isnan(v)) return;
    acc = std::isnan(acc) ? v : std::max(acc, v);
  };
  for (std::size_t r = 0; r < g.rows; ++r) {
    if (evaluations[r].skipped) continue;
    Cell& c = out[g.x_index(r) * g.y_size() + g.y_index(r)];
    const Assessment a = assess(evaluations[r], tiny);
    ++c.points;
    if (!std::isnan(a.rel_error)) ++c.compared;
    if (int(a.flag) > int(c.flag)) c.flag = a.flag;
    fmax_nan(c.max_rel_error, a.rel_error);
    fmax_nan(c.max_peak_error, a.peak_error);
    fmax_nan(c.max_rounding_rel, a.rounding_rel);
  }
  return out;
}

}  // namespace sglab::experiments::atlas
