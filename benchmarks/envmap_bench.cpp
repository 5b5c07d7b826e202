// SG environment-map fits side by side in one process: the Ceres fit (fit/envmap.hpp: sparse tiles,
// CGNR steps, lobe ladder) and the simple alternative, EM for a von Mises–Fisher mixture, both at
// N lobes on a 512 × 256 map (the generated sky with its sun, the studio of area lights, and the
// shipped synthetic mixture). Each iteration times one whole fit (pyramid, initialisation, solves;
// not the error evaluation), as EnvFitResult::seconds does; compare the two methods' ratio, the
// machine being shared. The fits' errors are reported as counters.
#include <benchmark/benchmark.h>

#include "envmap.hpp"
#include "sglab/render/environment.hpp"

namespace {

const sglab::EnvMap& environment(int kind) {
  static const sglab::EnvMap maps[3] = {
      sglab::render::make_sky({}),
      sglab::render::make_studio({}),
      sglab::rasterize_mixture(sglab::render::synthetic_mixture(), 512, 256, 4),
  };
  return maps[kind];
}

void BM_EnvFit(benchmark::State& state, bool ceres) {
  sglab::fit::EnvFitOptions o;
  o.lobes = int(state.range(1));
  o.init = "kmeans";
  const auto& map = environment(int(state.range(0)));
  sglab::fit::EnvFitResult r;
  for (auto _ : state) {
    r = ceres ? sglab::fit::fit_envmap_ceres(map, o) : sglab::fit::fit_envmap_vmf_em(map, o);
    state.SetIterationTime(r.seconds);
  }
  state.counters["relative_error"] = r.error.relative;
  state.SetLabel(std::string(state.range(0) == 0   ? "sky"
                             : state.range(0) == 1 ? "studio"
                                                   : "mixture") +
                 " 512x256, fitted on " + std::to_string(r.fit_width) + "x" + std::to_string(r.fit_height));
}

// (environment: 0 sky, 1 studio, 2 mixture; lobes)
void args(benchmark::internal::Benchmark* b) {
  for (int env = 0; env < 3; ++env) b->Args({env, 32});
  b->Unit(benchmark::kSecond)->UseManualTime()->Iterations(1);
}

BENCHMARK_CAPTURE(BM_EnvFit, ceres, true)->Apply(args);
BENCHMARK_CAPTURE(BM_EnvFit, vmf_em, false)->Apply(args);

}  // namespace

BENCHMARK_MAIN();
