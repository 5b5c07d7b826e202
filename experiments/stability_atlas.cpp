// The stability atlas computation (stability_atlas.hpp).
#include "stability_atlas.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <numbers>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/sg.hpp"
#include "sglab/stiff_cases.hpp"
#include "sglab/vsgl.hpp"

namespace sglab::atlas {

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
  a.flag = a.negative ? Flag::negative : a.wrong_peak ? Flag::wrong : a.wrong_relative ? Flag::wrong_relative : Flag::ok;
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
    case ColumnKind::nonnegative:
    {
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
    names.push_back(q.columns[c].name);
    values.push_back(column_values(q.columns[c].kind, l));
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

// ---- evaluation -----------------------------------------------------------------------------

namespace {
template <class T>
T eval_in(const Method& m, std::span<const T> a) {
  if constexpr (std::is_same_v<T, float>) return m.eval_float(a);
  else return m.eval_double(a);
}

bool valid_row(const Quantity& q, std::span<const double> row) {
  for (std::size_t c = 0; c < row.size() && c < q.columns.size(); ++c)
    if (column_value_error(q.columns[c], row[c])) return false;
  return true;
}

// The same method in 50 digits at row r rounded to T (every T value is exactly an mp50 value).
template <class T>
void add_exact(const Method& m, const Grid& g, std::size_t r, Evaluation& e) {
  if (e.skipped || e.out_of_domain || e.threw || !std::isfinite(e.value)) return;
  const std::vector<double> row = g.row(r);
  std::vector<mp50> in;
  for (double v : row) in.emplace_back(static_cast<T>(v));
  try {
    const double exact = static_cast<double>(m.eval_mp50(in));
    if (std::isfinite(exact)) e.exact = exact;
  } catch (const std::exception&) {
    // the 50-digit evaluation failing leaves the rounding error unmeasured at this row
  }
}

// Whether every input of row r is within float's range: the float grid stops at FLT_MAX (a
// larger double input would round to Inf, which is not a float input but an overflow).
bool representable_in_float(const Grid& g, std::size_t r) {
  for (double v : g.row(r))
    if (std::isfinite(v) && std::fabs(v) > double(std::numeric_limits<float>::max())) return false;
  return true;
}

template <class T>
Evaluation evaluate_row(const Quantity& q, const Method& m, const Grid& g, std::size_t r, bool rounding) {
  Evaluation e;
  const std::vector<double> row = g.row(r);
  std::vector<T> in(row.begin(), row.end());   // the input rounded to T
  std::vector<double> seen(in.begin(), in.end());  // … as the domain check and mp50 see it
  if (!valid_row(q, seen) || (m.domain_error && m.domain_error(seen))) {
    e.out_of_domain = true;
    return e;
  }
  try {
    e.value = double(eval_in<T>(m, std::span<const T>(in)));
  } catch (const std::exception&) {
    e.threw = true;
    return e;
  }
  if (rounding) add_exact<T>(m, g, r, e);
  return e;
}
}  // namespace

std::vector<Evaluation> evaluate(const Quantity& q, const Method& m, Precision p, const Grid& g,
                                 std::span<const double> reference, std::span<const double> peak,
                                 std::span<const char> rounding_rows, std::span<const char> rows) {
  std::vector<Evaluation> out(g.rows);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, g.rows, 16), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      if ((!rows.empty() && !rows[r]) || (p == Precision::float32 && !representable_in_float(g, r))) {
        out[r].skipped = true;
        continue;
      }
      const bool rounding = !rounding_rows.empty() && rounding_rows[r];
      Evaluation e = p == Precision::float32 ? evaluate_row<float>(q, m, g, r, rounding)
                                             : evaluate_row<double>(q, m, g, r, rounding);
      if (!reference.empty()) e.reference = reference[r];
      if (!peak.empty()) e.peak = peak[r];
      out[r] = e;
    }
  });
  return out;
}

void measure_rounding(const Method& m, Precision p, const Grid& g, std::vector<Evaluation>& evaluations,
                      std::span<const char> rows) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, g.rows, 4), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      if (rows.empty() || !rows[r]) continue;
      if (p == Precision::float32) add_exact<float>(m, g, r, evaluations[r]);
      else add_exact<double>(m, g, r, evaluations[r]);
    }
  });
}

bool float_is_rounded_double(const Grid& g, std::span<const Evaluation> f, std::span<const Evaluation> d) {
  long compared = 0;
  for (std::size_t r = 0; r < f.size() && r < d.size(); ++r) {
    const Evaluation &a = f[r], &b = d[r];
    bool exact_in_float = true;
    for (double v : g.row(r)) exact_in_float = exact_in_float && double(float(v)) == v;
    if (!exact_in_float) continue;
    if (a.skipped || b.skipped || a.out_of_domain || b.out_of_domain || a.threw || b.threw) continue;
    const float rounded = static_cast<float>(b.value);
    if (std::isnan(a.value) && std::isnan(rounded)) continue;
    if (float(a.value) != rounded) return false;
    ++compared;
  }
  return compared > 0;
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

// ---- rounding probe -------------------------------------------------------------------------

RoundingProbe probe_rounding(const Method& m, const Grid& g, double max_seconds) {
  using clock = std::chrono::steady_clock;
  RoundingProbe p;
  // Probe rows: the middle value of every column, then a quarter and three quarters along.
  std::vector<std::vector<double>> rows;
  for (double frac : {0.5, 0.25, 0.75}) {
    std::vector<double> row;
    for (const auto& v : g.values) row.push_back(v[std::min(v.size() - 1, std::size_t(frac * double(v.size())))]);
    if (m.domain_error && m.domain_error(row)) continue;
    rows.push_back(row);
  }
  if (rows.empty()) {
    p.reason = "no probe row inside the method's domain";
    return p;
  }
  // A method whose double evaluation takes milliseconds (the 2D glossy quadratures) has a
  // converted double result or a 2D quadrature as its mp50 evaluator: not swept. The first call
  // warms up (thread-local quadrature tables); the fastest of the next three is timed.
  {
    const auto t0 = clock::now();
    (void)m.eval_double(rows[0]);
    const double warm = std::chrono::duration<double>(clock::now() - t0).count();
    double seconds = warm;
    for (int k = 0; k < 3 && warm < 1; ++k) {  // the fastest of three, against scheduling noise
      const auto t1 = clock::now();
      (void)m.eval_double(rows[0]);
      const double s = std::chrono::duration<double>(clock::now() - t1).count();
      seconds = k == 0 ? s : std::min(seconds, s);
    }
    if (seconds > 5e-3) {
      p.reason = fmt::format("a quadrature ({:.2g} s per point in double): its 50-digit form is not swept", seconds);
      return p;
    }
  }
  // The 50-digit evaluator: one call (it includes lazy initialization of Boost's 50-digit
  // constants; the 1D quadratures take ~0.5 s here and stop the probe), then the fastest of the
  // probe rows against max_seconds (closed forms take 20–500 µs).
  int converted = 0;
  double seconds = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k <= rows.size(); ++k) {
    const auto& row = rows[k == 0 ? 0 : k - 1];
    const std::vector<mp50> a(row.begin(), row.end());
    const auto t0 = clock::now();
    mp50 v;
    try {
      v = m.eval_mp50(a);
    } catch (const std::exception& e) {
      p.reason = std::string("the 50-digit evaluation throws: ") + e.what();
      return p;
    }
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    if (k == 0) {
      if (s > 0.1) {
        p.seconds_per_point = s;
        p.reason = fmt::format("50-digit evaluation too slow to sweep ({:.2g} s per point)", s);
        return p;
      }
      continue;
    }
    seconds = std::min(seconds, s);
    const double d = m.eval_double(row);
    if (v == mp50(d) && d != 0) ++converted;
  }
  p.seconds_per_point = seconds;
  if (seconds > max_seconds) {
    p.reason = fmt::format("50-digit evaluation too slow to sweep ({:.2g} s per point)", seconds);
    return p;
  }
  if (converted == int(rows.size())) {
    p.reason = "the 50-digit evaluator converts the double result (no independent 50-digit evaluation)";
    return p;
  }
  p.usable = true;
  return p;
}

std::string describe_row(const Grid& g, std::size_t r, Precision p) {
  std::string s;
  const auto row = g.row(r);
  for (std::size_t c = 0; c < row.size(); ++c) {
    if (!s.empty()) s += "; ";
    s += g.column_names[c] + "=";
    s += p == Precision::float32 ? fmt::format("{:.9g}", double(float(row[c]))) : fmt::format("{:.17g}", row[c]);
  }
  return s;
}

// ---- registry cases -------------------------------------------------------------------------

namespace {

std::size_t column_of(const Quantity& q, std::string_view name) {
  for (std::size_t c = 0; c < q.columns.size(); ++c)
    if (q.columns[c].name == name) return c;
  return q.columns.size();
}

// Quantities whose reference is a double quadrature too slow to run on the whole grid.
struct ReferenceBudget {
  std::string_view quantity;
  std::size_t rows_full, rows_quick;
  std::string_view why;
};
constexpr ReferenceBudget kReferenceBudgets[] = {
    {"specular", 16, 4,
     "the reference (adaptive 2D quadrature) takes 0.02–2 s per point and ~100 s at α = 1e-4 with grazing view, so "
     "it is compared on {} rows spread over those with roughness ≥ 0.1 and light sharpness ≤ 1e4"},
    {"specular-gaussian-ndf", 16, 4,
     "the reference (adaptive 2D quadrature) takes 0.01–1 s per point, more at small m with grazing view, so it is "
     "compared on {} rows spread over those with roughness ≥ 0.1 and light sharpness ≤ 1e4"},
    {"asg-sg-product-integral", 40, 10,
     "the reference (2D quadrature, 20–200 ms per point) is compared on {} rows spread over the grid"},
};

}  // namespace

double hemispherical_large_lambda(double lambda, double cosine) {
  const double c = std::clamp(cosine, -1.0, 1.0);
  return 2 * std::numbers::pi / lambda * 0.5 * std::erfc(-c * std::sqrt(lambda / 2));
}

double clamped_cosine_large_lambda(double lambda, double cosine) {
  const double c = std::clamp(cosine, -1.0, 1.0);
  const double tail = std::exp(-lambda * c * c / 2) / std::sqrt(2 * std::numbers::pi * lambda);
  return 2 * std::numbers::pi / lambda * (c * 0.5 * std::erfc(-c * std::sqrt(lambda / 2)) + tail);
}

std::vector<Case> registry_cases(bool quick) {
  std::vector<Case> out;
  for (const Quantity& q : quantities()) {
    Case c{q, registry_grid(q, quick), {}, "", {}};
    if (!q.reference_method.empty()) {
      std::vector<char> eligible(c.grid.rows, 1);
      c.reference_rows = eligible;
      c.note = "reference on every row";
      // Rows whose sharpness-like inputs exceed the quadrature's reach.
      std::vector<char> reachable(c.grid.rows, 1);
      bool any_unreachable = false;
      for (std::size_t r = 0; r < c.grid.rows; ++r) {
        const auto row = c.grid.row(r);
        for (std::size_t k = 0; k < row.size(); ++k)
          if ((q.columns[k].kind == ColumnKind::sharpness || q.columns[k].kind == ColumnKind::nonnegative) &&
              row[k] > kQuadratureMaxSharpness)
            reachable[r] = 0;
        any_unreachable = any_unreachable || !reachable[r];
      }
      const bool quadrature = q.name == "hemispherical" || q.name == "clamped-cosine";
      if (quadrature && any_unreachable) {
        // The 1D quadrature references stop at λ = 1e8; past it, the closed-form large-λ limit.
        c.reference_rows = reachable;
        c.limit_reference.assign(c.grid.rows, std::numeric_limits<double>::quiet_NaN());
        for (std::size_t r = 0; r < c.grid.rows; ++r) {
          if (reachable[r]) continue;
          const auto row = c.grid.row(r);
          c.limit_reference[r] = q.name == "hemispherical" ? hemispherical_large_lambda(row[0], row[1])
                                                           : clamped_cosine_large_lambda(row[0], row[1]);
        }
        c.note = fmt::format(
            "reference: the quadrature for λ ≤ {:.0e}; past it (where the quadrature cannot reach) the closed-form "
            "large-λ limit {} (relative error O(1/λ + λc⁴), ≤ 1e-8 on this grid)",
            kQuadratureMaxSharpness,
            q.name == "hemispherical" ? "(2π/λ)·½erfc(−c√(λ/2)) (→ 2π/λ at c > 0)"
                                      : "(2π/λ)(c·½erfc(−c√(λ/2)) + e^{−λc²/2}/√(2πλ)) (→ 2π⟨c⟩/λ)");
      }
      for (const auto& b : kReferenceBudgets) {
        if (b.quantity != q.name) continue;
        for (std::size_t r = 0; r < c.grid.rows; ++r) eligible[r] = reachable[r];
        if (q.name == "specular" || q.name == "specular-gaussian-ndf") {
          const std::size_t ra = column_of(q, "roughness"), rl = column_of(q, "light_sharpness");
          for (std::size_t r = 0; r < c.grid.rows; ++r) {
            const auto row = c.grid.row(r);
            eligible[r] = (eligible[r] && ra < row.size() && row[ra] >= 0.1 && rl < row.size() && row[rl] <= 1e4) ? 1 : 0;
          }
        }
        const std::size_t n = quick ? b.rows_quick : b.rows_full;
        c.reference_rows = spread_subset(eligible, n);
        c.note = fmt::format(fmt::runtime(std::string(b.why)), n);
      }
    } else {
      c.note = "no reference method: counts and 50-digit rounding only";
    }
    out.push_back(std::move(c));
  }
  return out;
}

// ---- extra cases (docs/math.md §10, not registry quantities) ----------------------------------------

namespace {

using DomainFn = std::function<std::optional<std::string>(std::span<const double>)>;

// ξ1 = (0, 0, 1) and ξ2 at angle δ from −ξ1.
template <class T>
std::pair<Vec3<T>, Vec3<T>> opposite_axes(const T& delta) {
  using std::cos;
  using std::sin;
  return {Vec3<T>(T(0), T(0), T(1)), Vec3<T>(T(sin(delta)), T(0), T(-cos(delta)))};
}

// The product of two SGs of equal sharpness λ on (nearly) opposite axes, by the definition in
// 50 digits: v = λξ1 + λξ2, λ3 = ‖v‖, L = λ3 − 2λ (the cancellation costs ≤ 8 of 50 digits at
// λ = 1e8), ∫ = e^L·2π(1 − e^{−2λ3})/λ3 (4π e^L at λ3 = 0). Independent of sg.hpp's stable forms.
mp50 opposite_integral_definition(const mp50& lambda, const mp50& delta) {
  const auto [x1, x2] = opposite_axes<mp50>(delta);
  const Vec3<mp50> v = lambda * x1 + lambda * x2;
  const mp50 l3 = sqrt(v.squaredNorm());
  const mp50 L = l3 - 2 * lambda;
  if (l3 == 0) return 2 * two_pi<mp50>() * exp(L);
  return two_pi<mp50>() * exp(L) * (-expm1(-2 * l3)) / l3;
}

Method make_pseudo(std::string name, std::string source, DomainFn domain, std::function<float(std::span<const float>)> f,
                   std::function<double(std::span<const double>)> d, std::function<mp50(std::span<const mp50>)> m) {
  Method out;
  out.name = std::move(name);
  out.source = std::move(source);
  out.domain_error = std::move(domain);
  out.eval_float = std::move(f);
  out.eval_double = std::move(d);
  out.eval_mp50 = std::move(m);
  return out;
}

template <class F>
Method generic_pseudo(std::string name, std::string source, DomainFn domain, F f) {
  return make_pseudo(std::move(name), std::move(source), std::move(domain), [f](std::span<const float> a) { return f(a); },
                     [f](std::span<const double> a) { return f(a); }, [f](std::span<const mp50> a) { return f(a); });
}

Case opposite_integral_case(bool quick) {
  Quantity q;
  q.name = "sg-product-opposite";
  q.description = "∫ G(ω; ξ1, λ) G(ω; ξ2, λ) dω with ξ2 at angle δ from −ξ1 (docs/math.md §1, §10: product sharpness → 0)";
  q.columns = {{"sharpness", ColumnKind::sharpness, "λ1 = λ2 = λ"},
               {"delta", ColumnKind::angle, "angle of ξ2 from −ξ1 (radians); 0 = exactly opposite"}};
  q.reference_method = "definition";
  q.methods.push_back(generic_pseudo("definition", "v = λξ1 + λξ2, λ3 = ‖v‖, e^{λ3−2λ}·A(λ3), in 50 digits", nullptr, [](auto a) {
    using T = typename decltype(a)::value_type;
    return T(opposite_integral_definition(mp50(a[0]), mp50(a[1])));
  }));
  q.methods.push_back(generic_pseudo("sg_product", "sg.hpp sg_product(ξ1, λ, ξ2, λ): e^{L}·A(λ3) from the vector form; NaN if the axis is not finite",
                                     nullptr, [](auto a) {
                                       using T = typename decltype(a)::value_type;
                                       using std::exp;
                                       using std::isfinite;
                                       const auto [x1, x2] = opposite_axes<T>(a[1]);
                                       const SgProduct<T> p = sg_product(x1, a[0], x2, a[0]);
                                       for (int k = 0; k < 3; ++k)
                                         if (!isfinite(p.axis(k))) return T(std::numeric_limits<double>::quiet_NaN());
                                       return T(exp(p.log_amplitude) * sg_integral(p.sharpness));
                                     }));
  q.methods.push_back(generic_pseudo("product_integral_exact", "sg.hpp product_integral_exact(λ, λ, ξ1·ξ2), the scalar stable form",
                                     nullptr, [](auto a) {
                                       using T = typename decltype(a)::value_type;
                                       const auto [x1, x2] = opposite_axes<T>(a[1]);
                                       return product_integral_exact(a[0], a[0], T(x1.dot(x2)));
                                     }));
  q.methods.push_back(generic_pseudo("iwasaki", "sg.hpp product_integral_iwasaki(λ, λ, ξ1·ξ2) (Iwasaki et al. 2012)",
                                     [](std::span<const double> a) -> std::optional<std::string> {
                                       if (a[0] > 0) return std::nullopt;
                                       return std::string("undefined at λ1 + λ2 = 0");
                                     },
                                     [](auto a) {
                                       using T = typename decltype(a)::value_type;
                                       const auto [x1, x2] = opposite_axes<T>(a[1]);
                                       return product_integral_iwasaki(a[0], a[0], T(x1.dot(x2)));
                                     }));
  std::vector<double> deltas{0.0, 1e-12, 1e-8, 1e-6, 1e-4, 1e-2, 0.1, 1.0};
  Case c{q, make_grid({"sharpness", "delta"}, {stiff::sharpnesses(quick ? 1 : 2), deltas}, 0, 1, false), {}, "", {}};
  c.reference_rows.assign(c.grid.rows, 1);
  c.note = "reference: the definition in 50 digits (no stable-form rewriting) at the same input";
  return c;
}

Case opposite_value_case(bool quick) {
  Quantity q;
  q.name = "sg-product-opposite-value";
  q.description = "G(ξ1; ξ1, λ)·G(ξ1; ξ2, λ) = e^{−λ(1 + cos δ)} through the product SG e^{L}G(ξ1; ξ3, λ3) (uses its axis)";
  q.columns = {{"sharpness", ColumnKind::sharpness, "λ1 = λ2 = λ"},
               {"delta", ColumnKind::angle, "angle of ξ2 from −ξ1 (radians); 0 = exactly opposite"}};
  q.reference_method = "definition";
  q.methods.push_back(generic_pseudo("definition", "e^{λ(ξ1·ξ2 − 1)} = e^{−λ(1 + cos δ)} in 50 digits", nullptr, [](auto a) {
    using T = typename decltype(a)::value_type;
    const mp50 l(a[0]), d(a[1]);
    return T(exp(-l * (1 + cos(d))));
  }));
  q.methods.push_back(generic_pseudo("sg_product", "sg.hpp sg_product: e^{L}·sg_eval(ξ1, ξ3, λ3)", nullptr, [](auto a) {
    using T = typename decltype(a)::value_type;
    using std::exp;
    const auto [x1, x2] = opposite_axes<T>(a[1]);
    const SgProduct<T> p = sg_product(x1, a[0], x2, a[0]);
    return T(exp(p.log_amplitude) * sg_eval(x1, p.axis, p.sharpness));
  }));
  std::vector<double> deltas{0.0, 1e-12, 1e-8, 1e-6, 1e-4, 1e-2, 0.1, 1.0};
  Case c{q, make_grid({"sharpness", "delta"}, {stiff::sharpnesses(quick ? 1 : 2), deltas}, 0, 1, false), {}, "", {}};
  c.reference_rows.assign(c.grid.rows, 1);
  c.note = "reference: e^{−λ(1 + cos δ)} in 50 digits";
  return c;
}

// Nine VPLs on a 3 × 3 grid of spacing h in a plane at distance D from the origin:
// y_ij = D·(0.6, 0.8, 0) + h·(i·(0, 0, 1) + j·(−0.8, 0.6, 0)), i, j ∈ {−1, 0, 1}, unit weights.
// σ² = E‖y − μ‖² = 4h²/3 exactly (each in-plane axis has variance 2h²/3); h = 0 is a single point
// (nine coincident VPLs, σ² = 0). `origin_at_first` selects the reference point o of the sums:
// 0 (the papers' E‖y‖² − ‖μ‖²) or the first VPL (vsgl.hpp's remedy).
template <class T>
T patch_variance(const T& distance, const T& spacing, bool origin_at_first) {
  const Vec3<T> centre = distance * Vec3<T>(T(0.6), T(0.8), T(0));
  const Vec3<T> e1(T(0), T(0), T(1)), e2(T(-0.8), T(0.6), T(0));
  VsglPositionSums<T> sums;
  Vec3<T> origin = Vec3<T>::Zero();
  bool first = true;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) {
      const Vec3<T> y = centre + spacing * (T(i) * e1 + T(j) * e2);
      if (first && origin_at_first) origin = y;
      first = false;
      add_position(sums, T(1), y, origin);
    }
  return vsgl_position(sums, origin).variance;
}

Case vsgl_variance_case() {
  Quantity q;
  q.name = "vsgl-variance";
  q.description = "σ_v² of nine VPLs on a 3×3 patch of spacing h at distance D from the origin (vsgl.hpp; docs/math.md §7, §10)";
  q.columns = {{"distance", ColumnKind::nonnegative, "D, the patch's distance from the origin"},
               {"spacing", ColumnKind::nonnegative, "h, the grid spacing (0: a single point)"}};
  q.reference_method = "exact";
  q.methods.push_back(generic_pseudo("exact", "4h²/3 (closed form)", nullptr, [](auto a) {
    using T = typename decltype(a)::value_type;
    return T(4) * a[1] * a[1] / T(3);
  }));
  q.methods.push_back(generic_pseudo("origin-zero", "sums relative to o = 0: σ² = E‖y‖² − ‖E y‖² (the papers' form)", nullptr,
                                     [](auto a) { return patch_variance(a[0], a[1], false); }));
  q.methods.push_back(generic_pseudo("origin-first-vpl", "sums relative to o = the first VPL (vsgl.hpp's reference point)", nullptr,
                                     [](auto a) { return patch_variance(a[0], a[1], true); }));
  Case c{q, make_grid({"distance", "spacing"}, {{0.0, 1.0, 1e2, 1e4, 1e6, 1e8}, {0.0, 1e-6, 1e-3, 1.0, 1e3}}, 0, 1, false), {}, "", {}};
  c.reference_rows.assign(c.grid.rows, 1);
  c.note = "reference: the exact variance 4h²/3 of the patch (0 for a single point); a relative error where it is 0 "
           "means any non-zero σ²";
  return c;
}

// Diffuse shading from one VSGL whose positional mean μ is `distance` from the shading point:
// μ = (1, 2, 3), y_p = μ − distance·u, u = (0.6, 0, 0.8); lobe axis ξ_v = −u, λ_v = 10; normal
// (0, 0, 1); the clamped-cosine integral by `d`. Returns ∫ L_in⟨ω·n⟩dω / c_v (vsgl.hpp).
template <class T, class D>
T on_top_shading(const T& distance, const T& variance, const D& d) {
  const Vec3<T> u(T(0.6), T(0), T(0.8));
  const Vec3<T> mean(T(1), T(2), T(3));
  const Vec3<T> yp = mean - distance * u;
  const VsglPositionalSg<T> pos = vsgl_positional_sg(mean, variance, yp);
  const VsglIncomingSg<T> in = vsgl_incoming_sg(pos, Vec3<T>(-u), T(10));
  return vsgl_clamped_cosine(in, Vec3<T>(T(0), T(0), T(1)), d);
}

template <class T>
T registry_d(const Method& m, const T& lambda, const T& cosine) {
  const T a[2] = {lambda, cosine};
  if constexpr (std::is_same_v<T, float>) return m.eval_float(a);
  else if constexpr (std::is_same_v<T, double>) return m.eval_double(a);
  else return m.eval_mp50(a);
}

Case vsgl_on_top_case() {
  const Quantity* cc = find_quantity("clamped-cosine");
  Quantity q;
  q.name = "vsgl-on-top";
  q.description = "∫ L_in⟨ω·n⟩ dω / c_v of one VSGL (λ_v = 10) at a shading point `distance` from μ_v, σ_v² = variance "
                  "(vsgl.hpp Eq. 7; docs/math.md §10: λ_σ → 0, ξ_μ undefined on top of μ_v; σ² = 0 a point light)";
  q.columns = {{"distance", ColumnKind::nonnegative, "‖μ_v − y_p‖"}, {"variance", ColumnKind::nonnegative, "σ_v²"}};
  q.reference_method = cc ? cc->reference_method : "reference";
  if (cc) {
    for (const Method& m : cc->methods) {
      const Method* mp = &m;
      DomainFn domain = nullptr;
      if (m.domain_error) {
        // The method's own domain check at the (λ_in, c) it would be called with.
        domain = [mp](std::span<const double> a) -> std::optional<std::string> {
          std::optional<std::string> why;
          on_top_shading(a[0], a[1], [&](double l, double c) {
            const double in[2] = {l, c};
            if (!why) why = mp->domain_error(in);
            return 0.0;
          });
          return why;
        };
      }
      auto shade = [mp](auto a) {
        using T = typename decltype(a)::value_type;
        return on_top_shading(a[0], a[1], [mp](const T& l, const T& c) { return registry_d(*mp, l, c); });
      };
      Method pm = generic_pseudo(m.name, "vsgl.hpp vsgl_clamped_cosine with clamped-cosine/" + m.name, domain, shade);
      if (m.name == q.reference_method) {
        // The reference pipeline is a yardstick computed in double (its float is the double rounded,
        // like the registry's references).
        pm.eval_float = [shade](std::span<const float> a) {
          const double d[2] = {a[0], a[1]};
          return float(shade(std::span<const double>(d)));
        };
      }
      q.methods.push_back(std::move(pm));
    }
  }
  Case c{q, make_grid({"distance", "variance"}, {{0.0, 1e-12, 1e-8, 1e-4, 1.0, 1e4}, {0.0, 1e-12, 1e-6, 1.0, 1e6}}, 0, 1, false),
         {}, "", {}};
  c.reference_rows.assign(c.grid.rows, 1);
  c.note = "reference: the same VSGL pipeline in double with the clamped-cosine reference; float positions (μ = (1, 2, 3)) "
           "cannot resolve distances below ~1e-7, so float sees the shading point on top of μ_v there";
  return c;
}

}  // namespace

std::vector<Case> extra_cases(bool quick) {
  std::vector<Case> out;
  out.push_back(opposite_integral_case(quick));
  out.push_back(opposite_value_case(quick));
  out.push_back(vsgl_variance_case());
  out.push_back(vsgl_on_top_case());
  return out;
}

}  // namespace sglab::atlas
