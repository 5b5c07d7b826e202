// Time of each Ceres fit (the target: each fit well under a second, `sglab fit all` under 30 s).
// Targets are set up once per process (static grids of exact references) before timing starts,
// so each iteration times the solve from the default starts, as FitResult::seconds does.
#include <benchmark/benchmark.h>

#include "fits.hpp"

namespace {

void BM_Fit(benchmark::State& state, const sglab::fit::Fitter* f) {
  sglab::fit::FitOptions o;
  o.objective = f->objectives.front();
  benchmark::DoNotOptimize(f->run(o));  // warm-up: builds the reference grids
  for (auto _ : state) benchmark::DoNotOptimize(f->run(o));
}

void BM_FitAll(benchmark::State& state) {
  for (auto _ : state) {
    for (const auto& f : sglab::fit::fitters()) {
      sglab::fit::FitOptions o;
      o.objective = f.objectives.front();
      benchmark::DoNotOptimize(f.run(o));
    }
  }
}

// lambda-d alone on its grid, as `sglab fit lambda-d` runs it (three starts, tight tolerances).
void BM_LambdaD(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(sglab::fit::fit_lambda_d("l2-solid-angle"));
}

// The number compared with benchmarks/lambda_d_scipy.py: same grid, start and tolerances.
void BM_LambdaDLikeScipy(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(sglab::fit::fit_lambda_d_like_scipy());
}

const int registered = [] {
  for (const auto& f : sglab::fit::fitters()) {
    benchmark::RegisterBenchmark(("fit/" + f.name).c_str(), BM_Fit, &f)->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("fit/all", BM_FitAll)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("lambda-d/ceres", BM_LambdaD)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("lambda-d/ceres-like-scipy", BM_LambdaDLikeScipy)->Unit(benchmark::kMicrosecond);
  return 0;
}();

}  // namespace

BENCHMARK_MAIN();
