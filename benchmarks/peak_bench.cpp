// This machine's clock and vector arithmetic throughput (peak.hpp), on one core: the denominator
// of the VPL sum's arithmetic bound. One line per instruction set on stderr, a JSON line on
// stdout. Run: build/benchmarks/sglab_peak_bench
#include <cstdio>

#include "peak.hpp"

int main() {
  using namespace sglab::bench;
  __builtin_cpu_init();
  const double hz = clock_hz();
  std::fprintf(stderr, "clock: %.3f GHz (dependent integer multiplies)\n", hz / 1e9);
  const bool avx512 = __builtin_cpu_supports("avx512f"), avx2 = __builtin_cpu_supports("avx2");
  std::printf("{\"clock_ghz\": %.4f", hz / 1e9);
  for (int isa = 0; isa < 2; ++isa) {
    if ((isa == 0 && !avx2) || (isa == 1 && !avx512)) continue;
    const Rates r = isa == 0 ? rates_avx2() : rates_avx512();
    const char* name = isa == 0 ? "avx2" : "avx512";
    std::fprintf(
        stderr,
        "%s: mul+add %.1f Gflop/s (%.2f per cycle), mul alone %.1f, add alone %.1f, div %.2f G/s (%.3f per cycle), "
        "sqrt %.2f G/s (%.3f per cycle)\n",
        name, r.mul_add / 1e9, r.mul_add / hz, r.mul / 1e9, r.add / 1e9, r.div / 1e9, r.div / hz, r.sqrt / 1e9,
        r.sqrt / hz);
    std::fprintf(stderr,
                 "%s float: mul+add %.1f Gflop/s, mul alone %.1f, add alone %.1f, div %.2f G/s, sqrt %.2f G/s\n", name,
                 r.mul_add_f / 1e9, r.mul_f / 1e9, r.add_f / 1e9, r.div_f / 1e9, r.sqrt_f / 1e9);
    std::printf(
        ", \"%s\": {\"mul_add_per_s\": %.4e, \"mul_per_s\": %.4e, \"add_per_s\": %.4e, \"div_per_s\": %.4e, "
        "\"sqrt_per_s\": %.4e, \"float_mul_add_per_s\": %.4e, \"float_mul_per_s\": %.4e, \"float_add_per_s\": %.4e, "
        "\"float_div_per_s\": %.4e, \"float_sqrt_per_s\": %.4e}",
        name, r.mul_add, r.mul, r.add, r.div, r.sqrt, r.mul_add_f, r.mul_f, r.add_f, r.div_f, r.sqrt_f);
  }
  std::printf("}\n");
  return 0;
}
