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
  for (int N : sizes) {
    EnvFitOptions fo;
    fo.lobes = N;
    fo.init = "kmeans";
    fo.seed = o.seed;
    fo.threads = o.threads;
    fo.sparse = o.sparse;
    out.push_back(basis_fit_from("vmf-em", fit_envmap_vmf_em(map, fo)));
  }
  return out;
}

}  // namespace

EnvBasis vmf_em_basis() {
  return {"vmf-em",
          "N",
          {""},
          {4, 8, 16, 32, 64, 128},
          six_floats_per_lobe,
          "EM for a von Mises–Fisher mixture (Banerjee et al. 2005) on Ω·(mean RGB)-weighted texel directions, "
          "k-means++ start, then NNLS RGB amplitudes; 6N floats",
          fit_vmf_em};
}

}  // namespace sglab::fit
