// ns per evaluation of every method of the core quantities, in float and double.
// Methods come from the registry and run through their batch evaluators (one indirect call per
// batch of 4096 seeded inputs), so the numbers are the methods' own cost. Run:
//   build/benchmarks/sglab_core_bench [--benchmark_filter=clamped-cosine]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <deque>
#include <random>
#include <vector>

#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/registry.hpp"

namespace {

constexpr std::size_t kBatch = 4096;
constexpr std::uint64_t kSeed = 20261122;  // fixed: every run times the same inputs

// λ log-uniform in [1e-3, 1e4] and c uniform in [−1, 1] (the error grid's range); other column
// kinds get values in their natural range.
std::vector<double> make_inputs(const sglab::Quantity& q) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> args;
  args.reserve(kBatch * q.columns.size());
  for (std::size_t i = 0; i < kBatch; ++i) {
    for (const auto& col : q.columns) {
      switch (col.kind) {
        case sglab::ColumnKind::sharpness: args.push_back(std::pow(10.0, -3 + 7 * u(rng))); break;
        case sglab::ColumnKind::cosine: args.push_back(-1 + 2 * u(rng)); break;
        default: args.push_back(u(rng)); break;
      }
    }
  }
  return args;
}

template <class T>
void run(benchmark::State& state, const sglab::Method* m, std::size_t arity, const std::vector<double>& in) {
  std::vector<T> args(in.begin(), in.end());
  std::vector<T> out(kBatch);
  const auto& batch = [&]() -> const sglab::BatchFn<T>& {
    if constexpr (std::is_same_v<T, float>) return m->batch_float;
    else return m->batch_double;
  }();
  for (auto _ : state) {
    batch(args, arity, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kBatch));
  state.counters["ns/eval"] = benchmark::Counter(
      static_cast<double>(state.iterations() * kBatch), benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}

// Scalar: the method's template called directly per (λ, c) on the same seeded inputs, inlined as
// in a shader or the renderer (no std::function per call or per batch). Registered only for
// sglab's own method and tokuyoshi2024, the peer it must not be slower than.
template <class T, class F>
void run_scalar(benchmark::State& state, F f, const std::vector<double>& in) {
  std::vector<T> args(in.begin(), in.end());
  std::vector<T> out(kBatch);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) out[i] = f(args[2 * i], args[2 * i + 1]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kBatch));
  state.counters["ns/eval"] = benchmark::Counter(
      static_cast<double>(state.iterations() * kBatch), benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}

template <class T>
void register_scalar(const std::vector<double>& in) {
  const std::string p = std::is_same_v<T, float> ? "float" : "double";
  benchmark::RegisterBenchmark(("clamped-cosine/tokuyoshi2024/" + p + "/scalar").c_str(), [&in](benchmark::State& s) {
    run_scalar<T>(s, [](const T& l, const T& c) { return sglab::clamped_cosine_tokuyoshi2024(l, c); }, in);
  });
  benchmark::RegisterBenchmark(("clamped-cosine/sglab/" + p + "/scalar").c_str(), [&in](benchmark::State& s) {
    run_scalar<T>(s, [](const T& l, const T& c) { return sglab::clamped_cosine_sglab(l, c); }, in);
  });
}

}  // namespace

int main(int argc, char** argv) {
  static std::vector<std::vector<double>> inputs;  // kept alive for the registered lambdas
  inputs.reserve(sglab::quantities().size());
  for (const auto& q : sglab::quantities()) {
    bool core_kinds = true;
    for (const auto& c : q.columns)
      core_kinds = core_kinds && (c.kind == sglab::ColumnKind::sharpness || c.kind == sglab::ColumnKind::cosine ||
                                  c.kind == sglab::ColumnKind::mean_length);
    if (!core_kinds) continue;  // other modules time their own quantities
    inputs.push_back(make_inputs(q));
    const auto& in = inputs.back();
    if (q.name == "clamped-cosine") {
      register_scalar<float>(in);
      register_scalar<double>(in);
    }
    for (const auto& m : q.methods) {
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
  std::printf("inputs: %zu per batch, seed %llu\n", kBatch, static_cast<unsigned long long>(kSeed));
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
