// The stability atlas's evaluations (stability_atlas.hpp): a method over a grid in float or
// double, the same method in 50 digits for its rounding error, and whether that is affordable.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <type_traits>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "stability_atlas.hpp"
#include "sglab/registry_mp50.hpp"

namespace sglab::experiments::atlas {

namespace {
// The one place a run-time precision picks the scalar type of the evaluations.
template <class F>
decltype(auto) with_scalar(Precision p, F&& f) {
  if (p == Precision::float32) return f(float{});
  return f(double{});
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
  std::vector<T> in(row.begin(), row.end());       // the input rounded to T
  std::vector<double> seen(in.begin(), in.end());  // … as the domain check and mp50 see it
  if (!valid_row(q, seen) || (m.domain_error && m.domain_error(seen))) {
    e.out_of_domain = true;
    return e;
  }
  try {
    e.value = double(eval_as<T>(m, std::span<const T>(in)));
  } catch (const std::exception&) {
    e.threw = true;
    return e;
  }
  if (rounding) add_exact<T>(m, g, r, e);
  return e;
}

template <class T>
std::vector<Evaluation> evaluate_in(const Quantity& q, const Method& m, const Grid& g,
                                    std::span<const double> reference, std::span<const double> peak,
                                    std::span<const char> rounding_rows, std::span<const char> rows) {
  std::vector<Evaluation> out(g.rows);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, g.rows, 16), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      if ((!rows.empty() && !rows[r]) || (std::is_same_v<T, float> && !representable_in_float(g, r))) {
        out[r].skipped = true;
        continue;
      }
      const bool rounding = !rounding_rows.empty() && rounding_rows[r];
      Evaluation e = evaluate_row<T>(q, m, g, r, rounding);
      if (!reference.empty()) e.reference = reference[r];
      if (!peak.empty()) e.peak = peak[r];
      out[r] = e;
    }
  });
  return out;
}

template <class T>
void measure_rounding_in(const Method& m, const Grid& g, std::vector<Evaluation>& evaluations,
                         std::span<const char> rows) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, g.rows, 4), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t r = range.begin(); r != range.end(); ++r)
      if (!rows.empty() && rows[r]) add_exact<T>(m, g, r, evaluations[r]);
  });
}
}  // namespace

std::vector<Evaluation> evaluate(const Quantity& q, const Method& m, Precision p, const Grid& g,
                                 std::span<const double> reference, std::span<const double> peak,
                                 std::span<const char> rounding_rows, std::span<const char> rows) {
  return with_scalar(p,
                     [&](auto t) { return evaluate_in<decltype(t)>(q, m, g, reference, peak, rounding_rows, rows); });
}

void measure_rounding(const Method& m, Precision p, const Grid& g, std::vector<Evaluation>& evaluations,
                      std::span<const char> rows) {
  with_scalar(p, [&](auto t) { measure_rounding_in<decltype(t)>(m, g, evaluations, rows); });
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

// ---- rounding probe -------------------------------------------------------------------------

namespace {
using Clock = std::chrono::steady_clock;

// Probe rows: the middle value of every column, then a quarter and three quarters along, those
// inside the method's domain.
std::vector<std::vector<double>> probe_rows(const Method& m, const Grid& g) {
  std::vector<std::vector<double>> rows;
  for (double frac : {0.5, 0.25, 0.75}) {
    std::vector<double> row;
    for (const auto& v : g.values) row.push_back(v[std::min(v.size() - 1, std::size_t(frac * double(v.size())))]);
    if (m.domain_error && m.domain_error(row)) continue;
    rows.push_back(row);
  }
  return rows;
}

// Seconds per double evaluation at `row`: the first call warms up (thread-local quadrature
// tables); the fastest of the next three is timed, against scheduling noise.
double double_seconds(const Method& m, const std::vector<double>& row) {
  const auto t0 = Clock::now();
  (void)m.eval_double(row);
  const double warm = std::chrono::duration<double>(Clock::now() - t0).count();
  double seconds = warm;
  for (int k = 0; k < 3 && warm < 1; ++k) {
    const auto t1 = Clock::now();
    (void)m.eval_double(row);
    const double s = std::chrono::duration<double>(Clock::now() - t1).count();
    seconds = k == 0 ? s : std::min(seconds, s);
  }
  return seconds;
}
}  // namespace

RoundingProbe probe_rounding(const Method& m, const Grid& g, double max_seconds) {
  RoundingProbe p;
  const std::vector<std::vector<double>> rows = probe_rows(m, g);
  if (rows.empty()) {
    p.reason = "no probe row inside the method's domain";
    return p;
  }
  // A method whose double evaluation takes milliseconds (the 2D glossy quadratures) has a
  // converted double result or a 2D quadrature as its mp50 evaluator: not swept.
  if (const double seconds = double_seconds(m, rows[0]); seconds > 5e-3) {
    p.reason = fmt::format("a quadrature ({:.2g} s per point in double): its 50-digit form is not swept", seconds);
    return p;
  }
  // The 50-digit evaluator: one call (it includes lazy initialization of Boost's 50-digit
  // constants; the 1D quadratures take ~0.5 s here and stop the probe), then the fastest of the
  // probe rows against max_seconds (closed forms take 20–500 µs).
  int converted = 0;
  double seconds = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k <= rows.size(); ++k) {
    const auto& row = rows[k == 0 ? 0 : k - 1];
    const std::vector<mp50> a(row.begin(), row.end());
    const auto t0 = Clock::now();
    mp50 v;
    try {
      v = m.eval_mp50(a);
    } catch (const std::exception& e) {
      p.reason = std::string("the 50-digit evaluation throws: ") + e.what();
      return p;
    }
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
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

}  // namespace sglab::experiments::atlas
