// The vectorized batch evaluators (docs/simd.md): run-time choice of the instruction set, and the
// installation of the kernels of simd/simd_kernels.hpp (diffuse) and simd/simd_specular.hpp as the
// registry's batch_float/batch_double of the diffuse and specular methods (and of their bound
// versions, whose constants are passed to the kernel),
// and the `specular` methods' f0 = 0 / f0 = 1 pair evaluators (simd/simd_fresnel_pair.hpp).
// The scalar templates stay the definition: eval_float/eval_double/eval_mp50 are untouched.
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

#include "sglab/brdf.hpp"
#include "sglab/clamped_cosine.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/specular_sglab.hpp"
#include "sglab/registry_mp50.hpp"
#include "sglab/simd.hpp"
#include "sglab/simd_specular_pair.hpp"
#include "sglab/text_limits.hpp"
#include "simd/simd_table.hpp"

namespace sglab {
namespace simd {

std::string_view isa_name(Isa isa) {
  switch (isa) {
    case Isa::sse2: return "sse2";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "?";
}

std::optional<Isa> parse_isa(std::string_view name) {
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_name(isa) == name) return isa;
  return std::nullopt;
}

namespace {

// Whether this build has the kernels of `isa` (SGLAB_SIMD_KERNELS, core/CMakeLists.txt: `host`
// compiles only those the building machine can run, `best` only the widest of them).
constexpr bool built(Isa isa) {
  switch (isa) {
    case Isa::sse2: return SGLAB_KERNELS_SSE2;
    case Isa::avx2: return SGLAB_KERNELS_AVX2;
    case Isa::avx512: return SGLAB_KERNELS_AVX512;
  }
  return false;
}

bool cpu_runs(Isa isa) {
  __builtin_cpu_init();
  switch (isa) {
    case Isa::sse2: return true;  // every x86-64 CPU
    case Isa::avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    // The flags simd_avx512.cpp is compiled with (libgcc also checks that the OS saves the
    // AVX-512 state).
    case Isa::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }
  return false;
}

// Why `isa` cannot run here, for the errors of SGLAB_SIMD and force_isa.
std::string why_not(Isa isa) {
  if (!cpu_runs(isa)) return "this CPU cannot run it";
  return "this build has no " + std::string(isa_name(isa)) +
         " kernels (configured with SGLAB_SIMD_KERNELS=best, or =host on a machine without it; reconfigure with "
         "-DSGLAB_SIMD_KERNELS=host, or =all)";
}

// For a table switch's sets that this build left out: isa_supported is false for them, so
// active_isa and force_isa never name them.
[[noreturn]] void not_built(Isa isa) {
  throw std::logic_error("sglab: no " + std::string(isa_name(isa)) + " kernels in this build");
}

}  // namespace

bool isa_supported(Isa isa) { return built(isa) && cpu_runs(isa); }

std::vector<Isa> supported_isas() {
  std::vector<Isa> out;
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) out.push_back(isa);
  return out;
}

namespace {

const simd_detail::KernelTable& table_of(Isa isa) {
  switch (isa) {
#if SGLAB_KERNELS_SSE2
    case Isa::sse2: return simd_detail::kernels_sse2();
#endif
#if SGLAB_KERNELS_AVX2
    case Isa::avx2: return simd_detail::kernels_avx2();
#endif
#if SGLAB_KERNELS_AVX512
    case Isa::avx512: return simd_detail::kernels_avx512();
#endif
    default: break;
  }
  not_built(isa);
}

std::atomic<const simd_detail::KernelTable*> g_table{nullptr};
std::atomic<int> g_isa{-1};

Isa initial_isa() {
  if (const char* env = std::getenv("SGLAB_SIMD"); env && *env) {
    const auto isa = parse_isa(env);
    if (!isa) throw std::invalid_argument("SGLAB_SIMD='" + clip_text(env) + "': expected sse2, avx2 or avx512");
    if (!isa_supported(*isa)) throw std::invalid_argument("SGLAB_SIMD='" + clip_text(env) + "': " + why_not(*isa));
    return *isa;
  }
  const std::vector<Isa> runnable = supported_isas();
  if (runnable.empty())  // SGLAB_SIMD_KERNELS=best on a machine wider than this one
    throw std::runtime_error(
        "this CPU runs none of this build's vector kernels (configured with "
        "SGLAB_SIMD_KERNELS=best on another machine); reconfigure with -DSGLAB_SIMD_KERNELS=host "
        "here, or build with -DSGLAB_SIMD_KERNELS=all to run on any x86-64");
  return runnable.back();
}

const simd_detail::KernelTable& active_table() {
  const simd_detail::KernelTable* t = g_table.load(std::memory_order_acquire);
  if (t) return *t;
  const Isa isa = initial_isa();
  g_isa.store(static_cast<int>(isa));
  t = &table_of(isa);
  g_table.store(t, std::memory_order_release);
  return *t;
}

}  // namespace

Isa active_isa() {
  active_table();
  return static_cast<Isa>(g_isa.load());
}

void force_isa(Isa isa) {
  if (!isa_supported(isa))
    throw std::invalid_argument("force_isa: " + std::string(isa_name(isa)) + ": " + why_not(isa));
  g_isa.store(static_cast<int>(isa));
  g_table.store(&table_of(isa), std::memory_order_release);
}

}  // namespace simd

namespace simd_detail {
const KernelTable& active_kernels() { return simd::active_table(); }
}  // namespace simd_detail

namespace {

using simd_detail::Kernel;
using Params = std::span<const double>;

// The kernel's constants in T, as the scalar registration forms them: T(value) for each, plus
// what the scalar code derives from them (sg-cosine's π/A(λ_d), tokuyoshi2022's α(λc)).
// `published`: the values are the published ones (tokuyoshi2022 then takes the published α, as
// clamped_cosine_tokuyoshi2022 does, instead of recomputing it).
template <class T>
std::array<T, simd_detail::kKernelParams> kernel_params(Kernel k, Params v, bool published) {
  std::array<T, simd_detail::kKernelParams> p{};
  for (std::size_t i = 0; i < v.size() && i < p.size(); ++i) p[i] = T(v[i]);
  switch (k) {
    case Kernel::cc_sg_cosine: p[1] = pi<T>() / sg_integral(p[0]); break;
    case Kernel::cc_tokuyoshi2022: p[4] = published ? tokuyoshi2022_alpha_c<T>() : tokuyoshi2022_alpha(p[0]); break;
    default: break;
  }
  if (simd_detail::kernel_arity(k) == 6) {
    // The specular kernels: the floors of brdf.hpp first, then the method's own constants.
    std::array<T, simd_detail::kKernelParams> q{T(kMinRoughness), T(kMinWarpCosine)};
    for (std::size_t i = 0; i < v.size() && i + 2 < q.size(); ++i) q[i + 2] = T(v[i]);
    if (k == Kernel::spec_sglab) {  // after its six constants: its roughness ceiling and exponent cap
      q[8] = T(kSglabSpecularMaxRoughness);
      q[9] = T(kSglabSpecularMaxExponent);
    }
    return q;
  }
  return p;
}

thread_local std::uint64_t t_vectorized_batch_calls = 0;

template <class T>
BatchFn<T> simd_batch(Kernel k, std::array<T, simd_detail::kKernelParams> p) {
  return [k, p](std::span<const T> args, std::size_t arity, std::span<T> out) {
    ++t_vectorized_batch_calls;
    if (arity != simd_detail::kernel_arity(k) || args.size() < arity * out.size())
      throw std::invalid_argument("vectorized batch evaluator: expected rows of " +
                                  std::to_string(simd_detail::kernel_arity(k)) + " values, got " +
                                  std::to_string(arity));
    const auto& t = simd::active_table();
    const int i = static_cast<int>(k);
    if constexpr (std::is_same_v<T, float>) t.f[i](args.data(), out.data(), out.size(), p.data());
    else t.d[i](args.data(), out.data(), out.size(), p.data());
  };
}

template <class T>
ColumnsBatchFn<T> simd_columns(Kernel k, std::array<T, simd_detail::kKernelParams> p) {
  return [k, p](std::span<const T* const> columns, std::span<T> out) {
    ++t_vectorized_batch_calls;
    if (columns.size() != simd_detail::kernel_arity(k))
      throw std::invalid_argument("vectorized column evaluator: expected " +
                                  std::to_string(simd_detail::kernel_arity(k)) + " columns, got " +
                                  std::to_string(columns.size()));
    const auto& t = simd::active_table();
    const int i = static_cast<int>(k);
    if constexpr (std::is_same_v<T, float>) t.columns_f[i](columns.data(), out.data(), out.size(), p.data());
    else t.columns_d[i](columns.data(), out.data(), out.size(), p.data());
  };
}

void set_simd_batches(Method& m, Kernel k, Params values, bool published) {
  const auto pf = kernel_params<float>(k, values, published);
  const auto pd = kernel_params<double>(k, values, published);
  m.batch_float = simd_batch<float>(k, pf);
  m.batch_double = simd_batch<double>(k, pd);
  m.columns_float = simd_columns<float>(k, pf);
  m.columns_double = simd_columns<double>(k, pd);
  m.batch_path = BatchPath::vectorized;
}

struct Entry {
  const char* quantity;
  const char* method;
  Kernel kernel;
};
constexpr Entry kEntries[] = {
// The diffuse methods: each line of their list (simd/diffuse_kernels.def).
#define SGLAB_DIFFUSE_KERNEL(id, quantity, method, ...) {quantity, method, Kernel::id},
#include "simd/diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL
    {"specular", "sg-warp", Kernel::spec_sg_warp},
    {"specular", "sg-warp-product-axis", Kernel::spec_sg_warp_product_axis},
    {"specular", "sg-warp-iwasaki", Kernel::spec_sg_warp_iwasaki},
    {"specular", "sg-warp-th2019", Kernel::spec_sg_warp_th2019},
    {"specular", "asg", Kernel::spec_asg},
    {"specular", "sg-warp-dvn", Kernel::spec_sg_warp_dvn},
    {"specular", "sglab", Kernel::spec_sglab},
    {"specular-gaussian-ndf", "sg-warp", Kernel::gndf_sg_warp},
    {"specular-gaussian-ndf", "sg-warp-meder", Kernel::gndf_sg_warp_meder},
};

// The constants a kernel takes that its method does not declare as parameters (the published
// values the scalar template uses by default): sg-warp-meder's clamped_cosine_meder.
std::vector<double> builtin_constants(Kernel k) {
  if (k == Kernel::gndf_sg_warp_meder)
    return {MederCosineSg::amplitude, MederCosineSg::sharpness, MederCosineSg::offset, MederLogistic::p1,
            MederLogistic::p2,        MederLogistic::p3,        MederLogistic::p4};
  return {};
}

// The constants the kernel of `m` takes for its published form.
std::vector<double> published_constants(const Method& m, Kernel k) {
  if (m.parameters.empty()) return builtin_constants(k);
  std::vector<double> published;
  for (const auto& p : m.parameters) published.push_back(p.published);
  return published;
}

const simd_detail::SpecularPairTable& pair_table_of(simd::Isa isa) {
  switch (isa) {
#if SGLAB_KERNELS_SSE2
    case simd::Isa::sse2: return simd_detail::specular_pairs_sse2();
#endif
#if SGLAB_KERNELS_AVX2
    case simd::Isa::avx2: return simd_detail::specular_pairs_avx2();
#endif
#if SGLAB_KERNELS_AVX512
    case simd::Isa::avx512: return simd_detail::specular_pairs_avx512();
#endif
    default: break;
  }
  simd::not_built(isa);
}

}  // namespace

static_assert(simd::kSpecularPairArity == simd_detail::kSpecularPairArity);

namespace {

// The pair table index of `method` and its kernel's constants, when it is one of the registry's
// own vectorized `specular` methods.
struct PairKernel {
  int index;
  std::array<double, simd_detail::kKernelParams> params;
};
std::optional<PairKernel> pair_kernel_of(const Method& method) {
  const Quantity* q = find_quantity("specular");
  if (!q || std::none_of(q->methods.begin(), q->methods.end(), [&](const Method& m) { return &m == &method; }))
    return std::nullopt;
  for (const auto& e : kEntries) {
    if (e.quantity != q->name || e.method != method.name) continue;
    const int i = static_cast<int>(e.kernel) - static_cast<int>(Kernel::spec_sg_warp);
    if (i < 0 || i >= simd_detail::kSpecularPairKernels) return std::nullopt;
    return PairKernel{i, kernel_params<double>(e.kernel, published_constants(method, e.kernel), true)};
  }
  return std::nullopt;
}

}  // namespace

simd::SpecularPairColumnsFn simd::specular_pair_columns_evaluator(const Method& method) {
  const std::optional<PairKernel> k = pair_kernel_of(method);
  if (!k) return {};
  return [k = *k](const SpecularPairColumns& rows, std::size_t lights, double* at0, double* at1) {
    const double* const receivers[simd_detail::kSpecularReceiverColumns] = {rows.roughness, rows.view_cos};
    const double* const columns[simd_detail::kSpecularLightColumns] = {rows.light_sharpness, rows.light_cos,
                                                                       rows.axis_t, rows.axis_b};
    pair_table_of(active_isa()).columns[k.index](receivers, columns, rows.receivers, lights, at0, at1, k.params.data());
  };
}

simd::SpecularPairFn simd::specular_pair_evaluator(const Method& method) {
  const std::optional<PairKernel> k = pair_kernel_of(method);
  if (!k) return {};
  return [k = *k](std::span<const double> args, std::span<double> at0, std::span<double> at1) {
    const std::size_t n = args.size() / kSpecularPairArity;
    if (args.size() != n * kSpecularPairArity || at0.size() < n || at1.size() < n)
      throw std::invalid_argument("specular pair evaluator: expected rows of " + std::to_string(kSpecularPairArity) +
                                  " values and an output per row");
    pair_table_of(active_isa()).d[k.index](args.data(), at0.data(), at1.data(), n, k.params.data());
  };
}

std::uint64_t simd::vectorized_batch_calls() { return t_vectorized_batch_calls; }

const std::vector<std::string>& simd::vectorized_methods() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& e : kEntries) out.push_back(std::string(e.quantity) + "/" + e.method);
    return out;
  }();
  return names;
}

void install_simd_batch_evaluators(std::vector<Quantity>& quantities) {
  for (auto& q : quantities) {
    for (auto& m : q.methods) {
      for (const auto& e : kEntries) {
        if (q.name != e.quantity || m.name != e.method) continue;
        set_simd_batches(m, e.kernel, published_constants(m, e.kernel), true);
        if (m.bind) {
          m.bind = [scalar_bind = m.bind, k = e.kernel](std::span<const double> values) {
            Method b = scalar_bind(values);
            set_simd_batches(b, k, values, false);
            return b;
          };
        }
      }
    }
  }
}

}  // namespace sglab
