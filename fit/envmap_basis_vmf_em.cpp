// Basis `vmf-em`: EM for a von Mises–Fisher mixture on the map's texel directions, then the RGB
// amplitudes by non-negative least squares (fit_envmap_vmf_em, envmap.hpp); 6N floats.
#include <stdexcept>

#include "envmap.hpp"
#include "envmap_basis.hpp"

namespace sglab::fit {
namespace {

std::vector<EnvBasisFit> fit_vmf_em(const EnvMap& map, const std::vector<int>& sizes, const std::string&,
                                    const EnvBasisOptions& o) {
  std::vector<EnvBasisFit> out;
  for (int N : sizes) out.push_back(basis_fit_from("vmf-em", fit_envmap_vmf_em(map, mixture_fit_options(N, o))));
  return out;
}

}  // namespace

EnvBasis vmf_em_basis() {
  return {"vmf-em",
          "N",
          {""},
          kMixtureLobeCounts,
          six_floats_per_lobe,
          "EM for a von Mises–Fisher mixture (Banerjee et al. 2005) on Ω·(mean RGB)-weighted texel directions, "
          "k-means++ start, then NNLS RGB amplitudes; 6N floats",
          fit_vmf_em};
}

}  // namespace sglab::fit
