// ns per evaluation of every method of the core quantities, in float and double.
// Methods come from the registry and run through their batch evaluators (one indirect call per
// batch of 4096 seeded inputs), so the numbers are the methods' own cost. Beside each vectorized
// method: `/scalar`, its scalar template in an inlined loop (what the batch evaluator was before
// vectorization), and `/port`, the naive peer (core/include/sglab/peer_ports.hpp: the printed
// formulas with std:: math), on the same inputs. Run:
//   build/benchmarks/sglab_core_bench [--benchmark_filter=clamped-cosine]
//   build/benchmarks/sglab_core_bench --ratios   (one table: medians of CPU time, every ISA, ratios)
//   build/benchmarks/sglab_core_bench --points 1000000   (batches of N seeded rows, not 4096)
//   build/benchmarks/sglab_core_bench --versus specular sglab asg [--rounds 31]
//     (two methods' batch evaluators interleaved on the same inputs, float and double: per-round
//     ratios of CPU ns per evaluation, their median and quartiles)
//   build/benchmarks/sglab_core_bench --benchmark_filter=specular-reference
//     (the GGX specular reference, its rules' nodes on vector registers and one at a time)
// SGLAB_SIMD=sse2|avx2|avx512 forces the vectorized evaluators' instruction set.
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "interleaved.hpp"
#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/exp_batch.hpp"
#include "sglab/gaussian_ndf.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/peer_ports.hpp"
#include "sglab/registry.hpp"
#include "sglab/simd.hpp"
#include "sglab/specular.hpp"
#include "sglab/specular_sglab.hpp"
#include "sglab/specular_grid.hpp"

namespace {

// Rows per batch: 4096 by default (they stay in cache, and a batch is repeated, so that the branch
// predictor may learn a scalar method's branches on them); `--points N` times N rows instead (the
// Python module's bench passes its own N, so that both sides pay the same memory traffic and the
// same unpredictable branches).
std::size_t g_batch = 4096;
constexpr std::uint64_t kSeed = 20261122;  // fixed: every run times the same inputs

// One pass of `batch` over the g_batch inputs (into `out`) per iteration under Google Benchmark,
// reported as items per second and ns per evaluation.
template <class T, class F>
void time_batch(benchmark::State& state, std::vector<T>& out, F&& batch) {
  for (auto _ : state) {
    batch();
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * g_batch));
  state.counters["ns/eval"] = benchmark::Counter(static_cast<double>(state.iterations() * g_batch),
                                                 benchmark::Counter::kIsRate | benchmark::Counter::kInvert,
                                                 benchmark::Counter::kIs1000);
}

// λ log-uniform in [1e-3, 1e4] and c uniform in [−1, 1] (the error grid's range); other column
// kinds get values in their natural range.
std::vector<double> make_inputs(const sglab::Quantity& q) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> args;
  args.reserve(g_batch * q.columns.size());
  for (std::size_t i = 0; i < g_batch; ++i) {
    for (const auto& col : q.columns) {
      switch (col.kind) {
        case sglab::ColumnKind::sharpness: args.push_back(std::pow(10.0, -3 + 7 * u(rng))); break;
        case sglab::ColumnKind::cosine: args.push_back(-1 + 2 * u(rng)); break;
        // The specular columns: roughness log-uniform in [1e-2, 1], the azimuth over a turn.
        case sglab::ColumnKind::positive: args.push_back(std::pow(10.0, -2 * u(rng))); break;
        case sglab::ColumnKind::angle: args.push_back(sglab::two_pi<double>() * u(rng)); break;
        default: args.push_back(u(rng)); break;
      }
    }
  }
  return args;
}

template <class T>
void run(benchmark::State& state, const sglab::Method* m, std::size_t arity, const std::vector<double>& in) {
  std::vector<T> args(in.begin(), in.end());
  std::vector<T> out(g_batch);
  const auto& batch = [&]() -> const sglab::BatchFn<T>& {
    if constexpr (std::is_same_v<T, float>) return m->batch_float;
    else return m->batch_double;
  }();
  time_batch(state, out, [&] { batch(args, arity, out); });
}

// Scalar: the method's template called directly per (λ, c) on the same seeded inputs, inlined as
// in a shader or the renderer (no std::function per call or per batch). Registered only for
// sglab's own method and tokuyoshi2024, the peer it must not be slower than.
template <class T, class F>
void run_scalar(benchmark::State& state, F f, const std::vector<double>& in) {
  std::vector<T> args(in.begin(), in.end());
  std::vector<T> out(g_batch);
  time_batch(state, out, [&] {
    for (std::size_t i = 0; i < g_batch; ++i) out[i] = f(args[2 * i], args[2 * i + 1]);
  });
}

template <class T>
void register_scalar(const std::vector<double>& in) {
  const std::string p = std::is_same_v<T, float> ? "float" : "double";
  benchmark::RegisterBenchmark(("clamped-cosine/tokuyoshi2024/" + p + "/scalar").c_str(), [&in](benchmark::State& s) {
    run_scalar<T>(
        s, [](const T& l, const T& c) { return sglab::clamped_cosine_tokuyoshi2024(l, c); }, in);
  });
  benchmark::RegisterBenchmark(("clamped-cosine/sglab/" + p + "/scalar").c_str(), [&in](benchmark::State& s) {
    run_scalar<T>(
        s, [](const T& l, const T& c) { return sglab::clamped_cosine_sglab(l, c); }, in);
  });
}

// The scalar templates of the vectorized methods in an inlined loop: the registry's batch
// evaluators before vectorization (set_evaluators' loop), for the before/after columns. A loop
// calls its template through a captureless lambda, inlined into the port's batch loop:
// SCALAR(quantity, method, fn) calls fn(λ, c) (its default constants), CLAMPED_COSINE(method, f) and
// HEMISPHERICAL(method, f) call clamped_cosine_f and hemispherical_f so; SCALAR6(quantity, method,
// call) evaluates `call` on the SpecularInput `in` of a row of (α, λ, light_cos, view_cos, φ, f0).
#define SCALAR_LOOP(T, fn) &sglab::peer::port_batch<T, +[](T l, T c) { return fn(l, c); }>
#define SCALAR(q, m, fn) \
  sglab::peer::Port { q, m, SCALAR_LOOP(float, fn), SCALAR_LOOP(double, fn) }
#define CLAMPED_COSINE(m, fn) SCALAR("clamped-cosine", m, sglab::clamped_cosine_##fn)
#define HEMISPHERICAL(m, fn) SCALAR("hemispherical", m, sglab::hemispherical_##fn)
#define SCALAR6_LOOP(T, ...)                                           \
  &sglab::peer::port_batch6<T, +[](T a, T l, T lc, T v, T phi, T f0) { \
    const sglab::SpecularInput<T> in{a, l, lc, v, phi, f0};            \
    return __VA_ARGS__;                                                \
  }>
#define SCALAR6(q, m, ...) \
  sglab::peer::Port { q, m, SCALAR6_LOOP(float, __VA_ARGS__), SCALAR6_LOOP(double, __VA_ARGS__) }
const sglab::peer::Port kScalarLoops[] = {
    CLAMPED_COSINE("punctual", punctual),
    CLAMPED_COSINE("punctual-approx", punctual_approx),
    CLAMPED_COSINE("sg-cosine", sg_cosine),
    CLAMPED_COSINE("cosine-lobe-sg", cosine_lobe_sg),
    CLAMPED_COSINE("hill-fitted", hill_fitted),
    CLAMPED_COSINE("meder", meder),
    CLAMPED_COSINE("tokuyoshi2022", tokuyoshi2022),
    CLAMPED_COSINE("tokuyoshi2024", tokuyoshi2024),
    CLAMPED_COSINE("sglab", sglab),
    HEMISPHERICAL("meder", meder),
    HEMISPHERICAL("tokuyoshi2022", tokuyoshi2022),
    HEMISPHERICAL("vmf-tokuyoshi2024", vmf_tokuyoshi2024),
    SCALAR6("specular", "sg-warp", sglab::specular_sg_warp(in)),
    SCALAR6("specular", "sg-warp-product-axis",
            sglab::specular_sg_warp(in, sglab::SgProductForm::exact, false, sglab::FactorAt::product_axis)),
    SCALAR6("specular", "sg-warp-iwasaki", sglab::specular_sg_warp(in, sglab::SgProductForm::iwasaki)),
    SCALAR6("specular", "sg-warp-th2019", sglab::specular_sg_warp(in, sglab::SgProductForm::exact, true)),
    SCALAR6("specular", "asg", sglab::specular_asg(in)),
    SCALAR6("specular", "sg-warp-dvn", sglab::specular_sg_warp_dvn(in)),
    SCALAR6("specular", "sglab", sglab::specular_sglab(in)),
    SCALAR6("specular-gaussian-ndf", "sg-warp", sglab::specular_gaussian_ndf_sg_warp(in)),
    SCALAR6("specular-gaussian-ndf", "sg-warp-meder", sglab::specular_gaussian_ndf_sg_meder(in)),
};
#undef SCALAR6
#undef SCALAR6_LOOP
#undef HEMISPHERICAL
#undef CLAMPED_COSINE
#undef SCALAR
#undef SCALAR_LOOP
const sglab::peer::Port* find_scalar_loop(std::string_view q, std::string_view m) {
  for (const auto& p : kScalarLoops)
    if (p.quantity == q && p.method == m) return &p;
  return nullptr;
}

template <class T>
auto loop_of(const sglab::peer::Port& p) {
  if constexpr (std::is_same_v<T, float>) return p.batch_float;
  else return p.batch_double;
}

// A raw batch loop (a port or a scalar loop) under Google Benchmark.
template <class T>
void run_loop(benchmark::State& state, void (*loop)(const T*, T*, std::size_t), const std::vector<double>& in) {
  std::vector<T> args(in.begin(), in.end());
  std::vector<T> out(g_batch);
  time_batch(state, out, [&] { loop(args.data(), out.data(), g_batch); });
}

// ---- --ratios: one table, medians of thread CPU time ---------------------------------------------
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// A batch timed in runs of ≥ 20 ms of CPU time: after a warm-up, the calls per run double until
// one run lasts that long. run(): CPU ns per evaluation of one run.
class CpuTimer {
 public:
  explicit CpuTimer(std::function<void()> batch, std::size_t evals = g_batch)
      : batch_(std::move(batch)), evals_(evals) {
    batch_();
    for (;;) {
      const double t0 = thread_cpu_seconds();
      for (int i = 0; i < calls_; ++i) batch_();
      if (thread_cpu_seconds() - t0 >= 0.02 || calls_ >= (1 << 16)) break;
      calls_ *= 2;
    }
  }
  double run() const {
    const double t0 = thread_cpu_seconds();
    for (int i = 0; i < calls_; ++i) batch_();
    return 1e9 * (thread_cpu_seconds() - t0) / (double(calls_) * double(evals_));
  }

 private:
  std::function<void()> batch_;
  std::size_t evals_;
  int calls_ = 1;
};

// Median over `reps` runs of CPU ns per evaluation.
double median_ns(const std::function<void()>& batch, int reps) {
  const CpuTimer timer(batch);
  std::vector<double> ns;
  for (int r = 0; r < reps; ++r) ns.push_back(timer.run());
  std::nth_element(ns.begin(), ns.begin() + reps / 2, ns.end());
  return ns[reps / 2];
}

void print_ratios() {
  const int reps = 9;
  const auto isas = sglab::simd::supported_isas();
  std::printf("| method | precision | scalar loop (before) |");
  for (auto isa : isas) std::printf(" sglab %s |", std::string(sglab::simd::isa_name(isa)).c_str());
  std::printf(" naive port | port / sglab %s | scalar / sglab %s |\n|---|---|---|",
              std::string(sglab::simd::isa_name(isas.back())).c_str(),
              std::string(sglab::simd::isa_name(isas.back())).c_str());
  for (std::size_t i = 0; i < isas.size() + 3; ++i) std::printf("---|");
  std::printf("\n");
  for (const auto& port : sglab::peer::ports()) {
    const sglab::Quantity* q = sglab::find_quantity(port.quantity);
    const sglab::Method* m = q->find(port.method);
    const auto in = make_inputs(*q);
    const auto* scalar = find_scalar_loop(port.quantity, port.method);
    auto row = [&](auto zero) {
      using T = decltype(zero);
      std::vector<T> args(in.begin(), in.end());
      std::vector<T> out(g_batch);
      const double t_scalar = median_ns([&] { loop_of<T> (*scalar)(args.data(), out.data(), g_batch); }, reps);
      std::vector<double> t_isa;
      for (auto isa : isas) {
        sglab::simd::force_isa(isa);
        t_isa.push_back(median_ns(
            [&] {
              if constexpr (std::is_same_v<T, float>) m->batch_float(args, q->columns.size(), out);
              else m->batch_double(args, q->columns.size(), out);
            },
            reps));
      }
      const double t_port = median_ns([&] { loop_of<T>(port)(args.data(), out.data(), g_batch); }, reps);
      std::printf("| %s/%s | %s | %.1f |", std::string(port.quantity).c_str(), std::string(port.method).c_str(),
                  std::is_same_v<T, float> ? "float" : "double", t_scalar);
      for (double t : t_isa) std::printf(" %.1f |", t);
      std::printf(" %.1f | %.2f× | %.2f× |\n", t_port, t_port / t_isa.back(), t_scalar / t_isa.back());
      std::fflush(stdout);
    };
    row(0.0f);
    row(0.0);
  }
}

// ---- --versus: two methods interleaved ----------------------------------------------------------
// `rounds` rounds per precision, each one run of A and one of B on the same seeded inputs, in the
// order A B, then B A, … (a slow spell of the machine falls on both); per round the ratio A/B of
// CPU ns per evaluation. Prints every round, then the ratios' median and quartiles.
int print_versus(const std::string& quantity, const std::string& a_name, const std::string& b_name, int rounds) {
  const sglab::Quantity* q = sglab::find_quantity(quantity);
  const sglab::Method* a = q ? q->find(a_name) : nullptr;
  const sglab::Method* b = q ? q->find(b_name) : nullptr;
  if (!a || !b) {
    std::fprintf(stderr, "--versus: no method %s/%s\n", quantity.c_str(), (q && a ? b_name : a_name).c_str());
    return 2;
  }
  // specular: the rows `sglab error-vs-time` times (its ns/eval column); else this bench's inputs.
  const bool specular = quantity == "specular";
  const auto in = specular ? sglab::specular_timing_rows() : make_inputs(*q);
  const std::size_t arity = q->columns.size();
  const std::size_t n = in.size() / arity;
  std::printf(
      "%s: %s / %s, batch evaluators (%s), %zu inputs per batch (%s), %d interleaved rounds of >= 20 ms CPU time "
      "each\n",
      quantity.c_str(), a_name.c_str(), b_name.c_str(),
      std::string(sglab::simd::isa_name(sglab::simd::active_isa())).c_str(), n,
      specular ? "sglab::specular_timing_rows, error-vs-time's timing inputs" : "this bench's seeded inputs", rounds);
  auto precision = [&](auto zero) {
    using T = decltype(zero);
    const char* p = std::is_same_v<T, float> ? "float" : "double";
    std::vector<T> args(in.begin(), in.end());
    std::vector<T> out(n);
    auto timer = [&](const sglab::Method* m) {
      return CpuTimer(
          [m, arity, &args, &out] {
            if constexpr (std::is_same_v<T, float>) m->batch_float(args, arity, out);
            else m->batch_double(args, arity, out);
          },
          n);
    };
    const CpuTimer ta = timer(a), tb = timer(b);
    const sglab::runner::InterleavedRatios ratios = sglab::runner::interleaved_ratios(
        [&] { return ta.run(); }, [&] { return tb.run(); }, rounds,
        [&](int k, double na, double nb) {
          std::printf("%s round %2d: %s %.2f ns, %s %.2f ns, ratio %.3f\n", p, k + 1, a_name.c_str(), na,
                      b_name.c_str(), nb, na / nb);
          std::fflush(stdout);
        });
    std::printf("%s: %s / %s median %.3f (quartiles %.3f-%.3f, %d rounds)\n", p, a_name.c_str(), b_name.c_str(),
                ratios.quantile(0.5), ratios.quantile(0.25), ratios.quantile(0.75), rounds);
  };
  precision(0.0f);
  precision(0.0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--points") == 0) {
      const auto n = sglab::bench::integer_in(i + 1 < argc ? argv[i + 1] : nullptr, 1, 100000000);
      if (!n) {
        std::fprintf(stderr, "--points: expected an integer in [1, 1e8], got '%s'\n", i + 1 < argc ? argv[i + 1] : "");
        return 2;
      }
      g_batch = std::size_t(*n);
      std::copy(argv + i + 2, argv + argc + 1, argv + i);  // out of Google Benchmark's way (argv[argc] is null)
      argc -= 2;
      break;
    }
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--versus") == 0) {
      if (i + 3 >= argc) {
        std::fprintf(stderr, "--versus needs QUANTITY METHOD_A METHOD_B [--rounds N]\n");
        return 2;
      }
      int rounds = 31;
      if (i + 5 < argc && std::strcmp(argv[i + 4], "--rounds") == 0) {
        const auto r = sglab::bench::integer_in(argv[i + 5], 1, 10000);
        if (!r) {
          std::fprintf(stderr, "--rounds: expected an integer in [1, 10000], got '%s'\n", argv[i + 5]);
          return 2;
        }
        rounds = int(*r);
      }
      return print_versus(argv[i + 1], argv[i + 2], argv[i + 3], rounds);
    }
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--ratios") == 0) {
      std::printf("inputs: %zu per batch, seed %llu; ns per evaluation, median of 9 runs of thread CPU time\n\n",
                  g_batch, static_cast<unsigned long long>(kSeed));
      print_ratios();
      return 0;
    }
  static std::vector<std::vector<double>> inputs;  // kept alive for the registered lambdas
  inputs.reserve(sglab::quantities().size());
  for (const auto& q : sglab::quantities()) {
    bool core_kinds = true;
    for (const auto& c : q.columns)
      core_kinds = core_kinds && (c.kind == sglab::ColumnKind::sharpness || c.kind == sglab::ColumnKind::cosine ||
                                  c.kind == sglab::ColumnKind::mean_length);
    // Other modules time their own quantities; the specular methods are timed here too (the
    // Python module's bench, benchmarks/python_eval_bench.py, compares against them), not their
    // quadrature reference (0.02–2 s per evaluation).
    const bool specular = q.name == "specular";
    if (!core_kinds && !specular) continue;
    inputs.push_back(make_inputs(q));
    const auto& in = inputs.back();
    if (q.name == "clamped-cosine") {
      register_scalar<float>(in);
      register_scalar<double>(in);
    }
    for (const auto& m : q.methods) {
      if (specular && m.name == q.reference_method) continue;
      const std::size_t arity = q.columns.size();
      // The quadrature references are ~1e4× slower: fewer iterations keep the run short.
      const bool slow = (m.name == q.reference_method && q.reference_method == "reference");
      auto* bf = benchmark::RegisterBenchmark((q.name + "/" + m.name + "/float").c_str(),
                                              [&m, arity, &in](benchmark::State& s) { run<float>(s, &m, arity, in); });
      auto* bd = benchmark::RegisterBenchmark((q.name + "/" + m.name + "/double").c_str(),
                                              [&m, arity, &in](benchmark::State& s) { run<double>(s, &m, arity, in); });
      if (slow) {
        bf->Iterations(1);
        bd->Iterations(1);
      }
      // The vectorized methods: the scalar loop they replaced, and the naive peer.
      if (const auto* port = sglab::peer::find_port(q.name, m.name)) {
        const auto* scalar = find_scalar_loop(q.name, m.name);
        for (const char* p : {"float", "double"}) {
          const bool f = std::string(p) == "float";
          benchmark::RegisterBenchmark((q.name + "/" + m.name + "/" + p + "/scalar-loop").c_str(),
                                       [scalar, f, &in](benchmark::State& s) {
                                         if (f) run_loop<float>(s, scalar->batch_float, in);
                                         else run_loop<double>(s, scalar->batch_double, in);
                                       });
          benchmark::RegisterBenchmark((q.name + "/" + m.name + "/" + p + "/port").c_str(),
                                       [port, f, &in](benchmark::State& s) {
                                         if (f) run_loop<float>(s, port->batch_float, in);
                                         else run_loop<double>(s, port->batch_double, in);
                                       });
        }
      }
      // The run-time constants path (`--constants`): the method bound to its published values,
      // beside the published path above, to show what binding costs.
      if (!m.parameters.empty()) {
        static std::deque<sglab::Method> bound;
        std::vector<double> values;
        for (const auto& p : m.parameters) values.push_back(p.published);
        bound.push_back(m.bind(values));
        const sglab::Method* b = &bound.back();
        benchmark::RegisterBenchmark((q.name + "/" + m.name + "/bound/double").c_str(),
                                     [b, arity, &in](benchmark::State& s) { run<double>(s, b, arity, in); });
      }
    }
  }
  // exp_batch (sglab/exp_batch.hpp) beside its peer, the loop of std::exp whose values it returns
  // bit for bit, on g_batch seeded x in [−40, 0] (the fits' exponents).
  static std::vector<double> exp_in(g_batch), exp_out(g_batch);
  {
    std::mt19937_64 rng(kSeed);
    std::uniform_real_distribution<double> x(-40, 0);
    for (double& v : exp_in) v = x(rng);
  }
  benchmark::RegisterBenchmark("exp/exp_batch/double", [](benchmark::State& s) {
    time_batch<double>(s, exp_out, [] { sglab::exp_batch(exp_in.data(), exp_out.data(), g_batch); });
  });
  benchmark::RegisterBenchmark("exp/std-exp-loop/double", [](benchmark::State& s) {
    time_batch<double>(s, exp_out, [] {
      for (std::size_t i = 0; i < g_batch; ++i) exp_out[i] = std::exp(exp_in[i]);
    });
  });
  // The same inputs in rows of 8 with each row's maximum subtracted, as the vMF E step forms them
  // (fit/envmap_vmf_em.cpp): one exact 0 per row (glibc's tiny-argument branch, 1 + x).
  static std::vector<double> exp_rows(g_batch);
  for (std::size_t r = 0; r + 8 <= g_batch; r += 8) {
    const double mx = *std::max_element(exp_in.begin() + std::ptrdiff_t(r), exp_in.begin() + std::ptrdiff_t(r + 8));
    for (std::size_t k = r; k < r + 8; ++k) exp_rows[k] = exp_in[k] - mx;
  }
  benchmark::RegisterBenchmark("exp/exp_batch/rows-with-max-subtracted/double", [](benchmark::State& s) {
    time_batch<double>(s, exp_out, [] { sglab::exp_batch(exp_rows.data(), exp_out.data(), g_batch); });
  });
  benchmark::RegisterBenchmark("exp/std-exp-loop/rows-with-max-subtracted/double", [](benchmark::State& s) {
    time_batch<double>(s, exp_out, [] {
      for (std::size_t i = 0; i < g_batch; ++i) exp_out[i] = std::exp(exp_rows[i]);
    });
  });
  // The GGX specular reference (glossy_reference.hpp) with each quadrature rule's 15 nodes on
  // vector registers (GgxCosine::points), beside its peer, the same reference with the integrand
  // one node at a time (the same values, bit for bit): 16 seeded configurations, time per reference.
  static std::vector<sglab::SpecularConfig> refs;
  {
    std::mt19937_64 rng(kSeed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 16; ++i)
      refs.push_back({std::pow(10.0, -1.5 * u(rng)), std::pow(10.0, 3 * u(rng)), 2 * u(rng) - 1, u(rng),
                      M_PI * (2 * u(rng) - 1), u(rng)});
  }
  const auto time_refs = [](benchmark::State& s, const auto& reference) {
    for (auto _ : s) {
      double sum = 0;
      for (const auto& c : refs) sum += reference(c);
      benchmark::DoNotOptimize(sum);
    }
    // seconds / (iterations · references), printed with its SI prefix (e.g. 6.2ms)
    s.counters["per_reference"] = benchmark::Counter(
        double(refs.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  };
  benchmark::RegisterBenchmark("specular-reference/at-once/double", [time_refs](benchmark::State& s) {
    time_refs(s, [](const sglab::SpecularConfig& c) { return sglab::specular_reference(c); });
  })->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("specular-reference/node-by-node/double", [time_refs](benchmark::State& s) {
    time_refs(s, [](const sglab::SpecularConfig& c) {
      const sglab::GgxCosine g{c.roughness, c.f0, sglab::specular_view(c.view_cos)};
      return sglab::specular_reference_of(
          c, [&g](const sglab::Vec3d& w) { return g(w); }, sglab::SphereQuadrature{});
    });
  })->Unit(benchmark::kMillisecond);
  std::printf("inputs: %zu per batch, seed %llu; vectorized evaluators: %s\n", g_batch,
              static_cast<unsigned long long>(kSeed),
              std::string(sglab::simd::isa_name(sglab::simd::active_isa())).c_str());
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
