// exp_batch (sglab/exp_batch.hpp): the table of glibc's exp, the check of the vectorized copy
// against std::exp, and the choice between it and the scalar loop.
#include "sglab/exp_batch.hpp"

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <boost/multiprecision/cpp_bin_float.hpp>

#include "sglab/simd.hpp"
#include "simd/simd_table.hpp"

namespace sglab {
namespace {

// glibc's __exp_data.tab (EXP_TABLE_BITS = 7), from its definition: 2^(k/128) = H_k (1 + T_k) with
// H_k the double nearest 2^(k/128) and T_k the double nearest the remainder (2^(k/128) − H_k)/H_k,
// both from 50-digit values; entry 2k holds T_k's bits, entry 2k + 1 H_k's bits minus k·2^45
// (the kernel adds k·2^45 back, with the exponent: scale = 2^(⌊k/128⌋) H_(k mod 128)). Every entry equals
// Debian 12's libm (glibc 2.36), and the check below would see any that did not.
const std::uint64_t* exp_table() {
  static const std::array<std::uint64_t, 256> table = [] {
    using mp = boost::multiprecision::cpp_bin_float_50;
    std::array<std::uint64_t, 256> t{};
    const mp ln2 = boost::multiprecision::log(mp(2));
    for (int k = 0; k < 128; ++k) {
      const mp exact = boost::multiprecision::exp(ln2 * k / 128);
      const double h = static_cast<double>(exact);
      const double tail = k == 0 ? 0.0 : static_cast<double>((exact - mp(h)) / mp(h));
      std::uint64_t hb, tb;
      std::memcpy(&hb, &h, sizeof hb);
      std::memcpy(&tb, &tail, sizeof tb);
      t[std::size_t(2 * k)] = tb;
      t[std::size_t(2 * k + 1)] = hb - (std::uint64_t(k) << 45);
    }
    return t;
  }();
  return table.data();
}

// The points of the check: exp's special values and the ends of its ranges, then 4096 seeded
// points across [−760, 720] (overflow, the fast path, the subnormal results and the underflow to 0),
// across [−40, 1] (what the fits evaluate) and at random bit patterns (every exponent field).
std::vector<double> check_points() {
  std::vector<double> x = {0.0, -0.0, 1.0, -1.0, 0x1p-54, -0x1p-54, 0x1.fffffffffffffp-55, 512.0, -512.0,
                           0x1.fffffffffffffp8, -0x1.fffffffffffffp8, 709.782712893384, 709.79, -708.39,
                           -745.1332191019411, -745.14, -746.0, -1024.0, 1024.0,
                           std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::denorm_min()};
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> wide(-760, 720), fits(-40, 1);
  for (int i = 0; i < 4096; ++i) {
    double v;
    if (i % 3 == 0) {
      v = wide(rng);
    } else if (i % 3 == 1) {
      v = fits(rng);
    } else {
      const std::uint64_t b = rng();
      std::memcpy(&v, &b, sizeof v);
    }
    x.push_back(v);
  }
  return x;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

bool agrees_with_std_exp(simd_detail::ExpFn fn) {
  const std::vector<double> x = check_points();
  std::vector<double> out(x.size());
  fn(x.data(), out.data(), x.size(), exp_table());
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!same_bits(out[i], std::exp(x[i]))) return false;
  return true;
}

// The check's verdict per instruction set: −1 not yet checked, 0 differs, 1 agrees.
std::array<std::atomic<int>, 3> g_verdict{-1, -1, -1};

simd_detail::ExpFn vectorized_exp() {
  const simd_detail::KernelTable& table = simd_detail::active_kernels();
  if (!table.exp_d) return nullptr;
  std::atomic<int>& verdict = g_verdict[static_cast<std::size_t>(simd::active_isa())];
  int v = verdict.load(std::memory_order_acquire);
  if (v < 0) {
    v = agrees_with_std_exp(table.exp_d) ? 1 : 0;  // the same answer whichever thread computes it
    verdict.store(v, std::memory_order_release);
  }
  return v == 1 ? table.exp_d : nullptr;
}

}  // namespace

void exp_batch(const double* x, double* out, std::size_t n) {
  if (const simd_detail::ExpFn fn = vectorized_exp()) {
    fn(x, out, n, exp_table());
    return;
  }
  for (std::size_t i = 0; i < n; ++i) out[i] = std::exp(x[i]);
}

bool exp_batch_vectorized() { return vectorized_exp() != nullptr; }

}  // namespace sglab
