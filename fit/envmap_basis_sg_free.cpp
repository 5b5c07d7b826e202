// Basis `sg-free`: the Ceres free-lobe fit (fit_envmap_ceres, envmap.hpp: axes, sharpnesses and
// RGB amplitudes by Levenberg–Marquardt, lobe ladder N/2 → N); one fit at the largest N gives
// every smaller N of its ladder (each rung's time counts from the start of that fit); 6N floats.
#include <algorithm>
#include <map>
#include <stdexcept>

#include "envmap.hpp"
#include "envmap_basis.hpp"

namespace sglab::fit {
namespace {

EnvBasisFit from_result(const EnvFitResult& r) { return basis_fit_from("sg-free", r); }

std::vector<EnvBasisFit> fit_sg_free(const EnvMap& map, const std::vector<int>& sizes, const std::string&,
                                     const EnvBasisOptions& o) {
  std::map<int, EnvBasisFit> fits;
  auto fit_n = [&](int n, bool ladder) {
    EnvFitOptions fo = mixture_fit_options(n, o);
    fo.max_iterations = o.max_iterations;
    if (ladder) fo.on_stage = [&](const EnvFitResult& r) { fits.emplace(int(r.mixture.size()), from_result(r)); };
    const EnvFitResult r = fit_envmap_ceres(map, fo);
    fits.emplace(int(r.mixture.size()), from_result(r));
  };
  if (sizes.empty()) return {};
  fit_n(*std::max_element(sizes.begin(), sizes.end()), true);
  std::vector<EnvBasisFit> out;
  for (int n : sizes) {
    if (!fits.count(n)) fit_n(n, false);
    out.push_back(fits.at(n));
  }
  return out;
}

}  // namespace

EnvBasis sg_free_basis() {
  return {
      "sg-free",
      "N",
      {""},
      kMixtureLobeCounts,
      six_floats_per_lobe,
      "the Ceres free-lobe fit of `sglab fit envmap` (axes, sharpnesses, RGB amplitudes; k-means start, lobe ladder); "
      "6N floats",
      fit_sg_free};
}

}  // namespace sglab::fit
