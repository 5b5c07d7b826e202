// Two timings compared on a shared machine: `rounds` rounds of one run of each, interleaved (A B,
// then B A, …, so that a slow spell of the machine falls on both); per round the ratio A/B. Used by
// `sglab error-vs-time`'s speed verdicts and `sglab_core_bench --versus`.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace sglab::runner {

struct InterleavedRatios {
  std::vector<double> sorted;  // the rounds' ratios A/B, ascending
  // The ratio at fraction q of the sorted rounds (0.5: the median; 0.25, 0.75: the quartiles).
  double quantile(double q) const { return sorted[std::size_t(std::lround(q * double(sorted.size() - 1)))]; }
};

// run_a() and run_b() each time one run and return its time; on_round(k, a, b) sees round k's times
// as they come (a progress line). `rounds` ≥ 1.
template <class RunA, class RunB, class OnRound>
InterleavedRatios interleaved_ratios(RunA&& run_a, RunB&& run_b, int rounds, OnRound&& on_round) {
  InterleavedRatios r;
  for (int k = 0; k < rounds; ++k) {
    double a, b;
    if (k % 2 == 0) a = run_a(), b = run_b();
    else b = run_b(), a = run_a();
    r.sorted.push_back(a / b);
    on_round(k, a, b);
  }
  std::sort(r.sorted.begin(), r.sorted.end());
  return r;
}

template <class RunA, class RunB>
InterleavedRatios interleaved_ratios(RunA&& run_a, RunB&& run_b, int rounds) {
  return interleaved_ratios(run_a, run_b, rounds, [](int, double, double) {});
}

}  // namespace sglab::runner
