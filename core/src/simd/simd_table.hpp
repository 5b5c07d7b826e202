// The table of vectorized batch evaluators one instruction set's two translation units provide
// (simd_sse2.cpp, simd_avx2.cpp, simd_avx512.cpp: the diffuse kernels; simd_specular_sse2.cpp, …:
// the specular ones). Internal to sglab_core: registry_simd.cpp
// picks a table at run time and installs its entries as the registry's batch evaluators.
// Deliberately free of any other header: the per-ISA units are compiled with -mavx2/-mavx512f, and
// an inline non-template function odr-used there could be picked by the linker for the whole
// program (and then execute AVX-512 code on a machine without it).
#pragma once

#include <cstddef>
#include <cstdint>

namespace sglab::simd_detail {

// One entry per vectorized (quantity, method). Order is the table's index. The diffuse ones come
// from their one list, diffuse_kernels.def (an X-macro list of ids, methods and templates).
enum class Kernel : int {
#define SGLAB_DIFFUSE_KERNEL(id, quantity, method, params, ...) id,
#include "diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL
  // The specular quantities: rows of (roughness, light_sharpness, light_cos, view_cos,
  // light_azimuth, f0) (simd_specular.hpp).
  spec_sg_warp,
  spec_sg_warp_product_axis,
  spec_sg_warp_iwasaki,
  spec_sg_warp_th2019,
  spec_asg,
  spec_sg_warp_dvn,
  spec_sglab,          // p: the floors, nu_slope … horizon_rate, the roughness ceiling and exponent cap
  gndf_sg_warp,        // `specular-gaussian-ndf`
  gndf_sg_warp_meder,  // p: the Meder cosine SG's amplitude, sharpness, offset, p1…p4
  count
};

// The diffuse kernels come first: entries 0 … kDiffuseKernels − 1 (simd_kernels.hpp); the
// specular ones after them (simd_specular.hpp, then simd_gaussian_ndf.hpp), each kind compiled in
// a unit of its own.
constexpr int kDiffuseKernels = static_cast<int>(Kernel::spec_sg_warp);

// Constants per kernel (unused entries are 0).
constexpr int kKernelParams = 10;

// Values per row: 2 (sharpness, cosine) for the diffuse kernels, 6 for the specular ones.
constexpr std::size_t kernel_arity(Kernel k) { return k >= Kernel::spec_sg_warp ? 6 : 2; }

// Evaluates n rows of kernel_arity values (e.g. (sharpness, cosine)), interleaved in `args`, into
// `out`, with the method's constants `params` (already in T).
template <class T>
using KernelFn = void (*)(const T* args, T* out, std::size_t n, const T* params);

// The same rows as kernel_arity columns (columns[j][i]: row i's value of column j), read as they
// are: no interleaving by the caller, no transposition by the kernel; bit for bit the KernelFn's
// values.
template <class T>
using ColumnsKernelFn = void (*)(const T* const* columns, T* out, std::size_t n, const T* params);

// out[i] = std::exp(x[i]) bit for bit (simd_exp.hpp), with the 128-pair table exp_batch.cpp builds.
using ExpFn = void (*)(const double* x, double* out, std::size_t n, const std::uint64_t* table);

// An SG mixture as columns, per lobe: axis x, y, z, −½λ, RGB amplitude (sglab/envmap.hpp).
struct MixtureColumns {
  std::size_t lobes;
  const double *ax, *ay, *az, *h, *ar, *ag, *ab;
};
// mixture_eval at the n points (x[q], y[q], z[q]) into r, g, b, bit for bit (simd_mixture.hpp);
// `scratch` holds n doubles.
using MixturePointsFn = void (*)(const MixtureColumns& m, const double* x, const double* y, const double* z,
                                 std::size_t n, double* r, double* g, double* b, double* scratch);

// ggx_brdf_cosine(alpha, f0, ωo, ω) at the n directions ω = (x[q], y[q], z[q]) into out, bit for bit
// (simd_ggx_points.hpp); wo holds ωo's three components.
using GgxPointsFn = void (*)(double alpha, double f0, const double* wo, const double* x, const double* y,
                             const double* z, double* out, std::size_t n);

struct KernelTable {
  const char* isa;  // "sse2", "avx2", "avx512"
  KernelFn<float> f[static_cast<int>(Kernel::count)];
  KernelFn<double> d[static_cast<int>(Kernel::count)];
  ColumnsKernelFn<float> columns_f[static_cast<int>(Kernel::count)];
  ColumnsKernelFn<double> columns_d[static_cast<int>(Kernel::count)];
  ExpFn exp_d;  // nullptr where the unit has no FMA (sse2): glibc's exp there rounds unfused
  MixturePointsFn mixture_points;
  GgxPointsFn ggx_points;
};

// The table of the active instruction set (sglab/simd.hpp: active_isa), from registry_simd.cpp.
const KernelTable& active_kernels();

const KernelTable& kernels_sse2();
const KernelTable& kernels_avx2();
const KernelTable& kernels_avx512();

// Fills the `specular` entries (spec_sg_warp … spec_sglab) of an instruction set's table: defined in
// that set's specular unit (simd_specular_<isa>.cpp), called by its diffuse unit's kernels_<isa>().
void add_specular_kernels_sse2(KernelTable& table);
void add_specular_kernels_avx2(KernelTable& table);
void add_specular_kernels_avx512(KernelTable& table);
// Fills the `specular-gaussian-ndf` entries (gndf_sg_warp, gndf_sg_warp_meder) likewise: defined in
// that set's Gaussian-NDF unit (simd_gaussian_ndf_<isa>.cpp).
void add_gaussian_ndf_kernels_sse2(KernelTable& table);
void add_gaussian_ndf_kernels_avx2(KernelTable& table);
void add_gaussian_ndf_kernels_avx512(KernelTable& table);

// The `specular` kernels (spec_sg_warp … spec_sglab) at f0 = 0 and f0 = 1 in one pass
// (simd_fresnel_pair.hpp): rows of the first 5 columns (no f0), in double.
constexpr std::size_t kSpecularPairArity = 5;
constexpr int kSpecularPairKernels = static_cast<int>(Kernel::spec_sglab) - static_cast<int>(Kernel::spec_sg_warp) + 1;
using SpecularPairFn = void (*)(const double* args, double* at_f0_zero, double* at_f0_one, std::size_t n,
                                const double* params);
// The same on columns (sglab/simd_specular_pair.hpp SpecularPairColumns): the receivers' two
// (roughness, view_cos), and the lights' four (light_sharpness, light_cos and the axis' tangent
// components axis_t, axis_b) of light_count × receiver_count rows, row j·receiver_count + g.
constexpr std::size_t kSpecularReceiverColumns = 2;
constexpr std::size_t kSpecularLightColumns = 4;
using SpecularPairColumnsFn = void (*)(const double* const* receivers, const double* const* lights,
                                       std::size_t receiver_count, std::size_t light_count, double* at_f0_zero,
                                       double* at_f0_one, const double* params);
struct SpecularPairTable {
  SpecularPairFn d[kSpecularPairKernels];
  SpecularPairColumnsFn columns[kSpecularPairKernels];
};

const SpecularPairTable& specular_pairs_sse2();
const SpecularPairTable& specular_pairs_avx2();
const SpecularPairTable& specular_pairs_avx512();

}  // namespace sglab::simd_detail
