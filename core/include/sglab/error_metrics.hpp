// The error measures every table of sglab reports, defined once. A value v is compared with its
// reference r (a method against the exact reference, a render against the exact VPL sum, a fit
// against its map); each measure below is used by the renderer (core/render), the fits' reports
// (fit/) and the experiments, so that one name means one formula in every table.
//
//   smape(v, r)       = 2|v − r|/(|v| + |r|) ∈ [0, 2], 0 when v = r = 0 — the symmetric absolute
//                       percentage error (Makridakis 1993, "Accuracy measures: theoretical and
//                       practical concerns", Int. J. Forecasting 9(4), as the M3 competition's
//                       sMAPE without the factor 100). A table's "SMAPE" is its mean over points.
//   relative L2       = ‖v − r‖₂/‖r‖₂ = √(Σ (v − r)²/Σ r²) (optionally with weights w: Σ w(v − r)²
//                       /Σ w r², the solid-angle weighted error of an environment map); 0 when both
//                       sums are 0, +∞ when only Σ r² is (an error against a zero reference).
//   brightness-weighted error = Σ|v − r|/Σ|r|: the relative L1 error, each point weighted by how
//                       bright its reference is (a renderer sees absolute errors where the image is
//                       bright); 0 when Σ|r| = 0.
//   RMSE              = √(mean (v − r)²); with a per-point scale s, of (v − r)/s.
//
// The accumulators add terms in the order they are given: a table's numbers depend only on the
// points and their order, never on which accumulator summed them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace sglab::metrics {

// 2|v − r|/(|v| + |r|), 0 when v = r = 0.
template <class T>
T smape(T value, T reference) {
  using std::abs;
  const T s = abs(value) + abs(reference);
  return s > T(0) ? T(2) * abs(value - reference) / s : T(0);
}

// √(error_sq/reference_sq): the relative L2 error from its two sums (0/0 → 0, x/0 → +∞).
template <class T>
T relative_l2(T error_sq, T reference_sq) {
  using std::sqrt;
  if (reference_sq > T(0)) return sqrt(error_sq / reference_sq);
  return error_sq > T(0) ? std::numeric_limits<T>::infinity() : T(0);
}

// Σ (v − r)², Σ r², Σ smape, max |v − r| and the count over (value, reference) pairs; an optional
// weight w multiplies the squared terms (w (v − r)², w r²).
struct ErrorSums {
  double error_sq = 0, reference_sq = 0, smape_sum = 0, max_abs = 0;
  std::size_t samples = 0;

  void add(double value, double reference) {
    const double d = std::fabs(value - reference);
    error_sq += d * d;
    reference_sq += reference * reference;
    smape_sum += metrics::smape(value, reference);
    max_abs = std::max(max_abs, d);
    ++samples;
  }
  // Weighted squared terms only (no SMAPE, no maximum): the solid-angle weighted L2 of a map.
  void add_weighted(double value, double reference, double weight) {
    const double d = value - reference;
    error_sq += weight * d * d;
    reference_sq += weight * reference * reference;
    ++samples;
  }
  double relative_l2() const { return metrics::relative_l2(error_sq, reference_sq); }
  double l2() const { return std::sqrt(error_sq); }
  // Means over the samples: 0 with none (an empty image compares as equal).
  double rmse() const { return samples ? std::sqrt(error_sq / double(samples)) : 0.0; }
  double mean_smape() const { return samples ? smape_sum / double(samples) : 0.0; }
};

// The brightness-weighted error Σ|v − r|/Σ|r|. add_terms takes a point's |v − r| and |r| already
// summed (over a pixel's channels), so that a caller keeps its own order of summation.
struct BrightnessWeighted {
  double abs_error = 0, abs_reference = 0;

  void add(double value, double reference) { add_terms(std::fabs(value - reference), std::fabs(reference)); }
  void add_terms(double error_magnitude, double reference_magnitude) {
    abs_error += error_magnitude;
    abs_reference += reference_magnitude;
  }
  bool has_reference() const { return abs_reference > 0; }
  double value() const { return abs_reference > 0 ? abs_error / abs_reference : 0.0; }
};

// Root mean square and maximum of errors e (already scaled): √(mean e²), max e; NaN with none.
struct RootMeanSquare {
  double sum_sq = 0, max = 0;
  std::size_t count = 0;

  void add(double e) {
    sum_sq += e * e;
    ++count;
    max = std::max(max, e);
  }
  double rms() const { return count ? std::sqrt(sum_sq / double(count)) : std::numeric_limits<double>::quiet_NaN(); }
};

// Statistics of a method against a reference over the points of a sweep group.
// A point's reference is "significant" when reference ≥ near_zero · scale, where `scale` is the
// size of the quantity around that point (e.g. the largest reference of the point's group): only
// significant points enter the relative statistics, so a reference that is ~0 (a light behind the
// surface) never produces an infinite relative error; the others are counted in `near_zero`.
// Every point with a value (and scale > 0) enters `max_scaled` = max |value − reference| / scale
// and `rmse_scaled`, which measure an error where the reference is ~0 too, weighted by how much it
// shows next to the largest value around it.
struct ErrorStats {
  std::size_t points = 0;     // points added (with or without a value)
  std::size_t relative = 0;   // points in the relative statistics (significant, with a value)
  std::size_t near_zero = 0;  // points with a value whose reference is not significant
  std::size_t missing = 0;    // points without a value (out of the method's domain, non-finite)
  double rmse_relative = std::numeric_limits<double>::quiet_NaN();  // √(mean of ((v − r)/r)²)
  double max_relative = std::numeric_limits<double>::quiet_NaN();   // max |v − r|/r
  double smape = std::numeric_limits<double>::quiet_NaN();          // mean of smape(v, r) ∈ [0, 2]
  double max_scaled = std::numeric_limits<double>::quiet_NaN();     // max |v − r|/scale, all points with a value
  double rmse_scaled = std::numeric_limits<double>::quiet_NaN();    // √(mean of ((v − r)/scale)²), the same points
  std::size_t worst = std::numeric_limits<std::size_t>::max();      // tag of the (first) max_relative point
};

class ErrorAccumulator {
 public:
  explicit ErrorAccumulator(double near_zero) : near_zero_(near_zero) {}
  // `has_value` false: the method gave no value at this point. `tag` identifies the point
  // (reported as ErrorStats::worst).
  void add(bool has_value, double value, double reference, double scale, std::size_t tag) {
    ++s_.points;
    if (!has_value || !std::isfinite(value)) {
      ++s_.missing;
      return;
    }
    const double error = std::fabs(value - reference);
    if (scale > 0 && std::isfinite(scale)) {
      const double scaled = error / scale;
      if (!(scaled <= s_.max_scaled)) s_.max_scaled = scaled;  // also replaces the initial NaN
      sum_sq_scaled_ += scaled * scaled;
      ++scaled_;
    }
    if (!(scale > 0 && reference > 0 && reference >= near_zero_ * scale)) {
      ++s_.near_zero;
      return;
    }
    const double relative = error / reference;
    ++s_.relative;
    sum_sq_ += relative * relative;
    sum_smape_ += metrics::smape(value, reference);  // reference > 0: the denominator too
    if (s_.relative == 1 || relative > s_.max_relative) {
      s_.max_relative = relative;
      s_.worst = tag;
    }
  }
  ErrorStats stats() const {
    ErrorStats s = s_;
    if (s.relative > 0) {
      s.rmse_relative = std::sqrt(sum_sq_ / double(s.relative));
      s.smape = sum_smape_ / double(s.relative);
    }
    if (scaled_ > 0) s.rmse_scaled = std::sqrt(sum_sq_scaled_ / double(scaled_));
    return s;
  }

 private:
  double near_zero_;
  ErrorStats s_;
  double sum_sq_ = 0, sum_smape_ = 0, sum_sq_scaled_ = 0;
  std::size_t scaled_ = 0;
};

}  // namespace sglab::metrics
