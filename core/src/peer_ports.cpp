// The table of the naive peer ports (peer_port_table.hpp): each port's batch loop, instantiated
// here once for float and double.
#include "sglab/peer_ports.hpp"

namespace sglab::peer {
namespace {

#define SGLAB_PEER_PORT(q, m, fn) \
  Port { q, m, &port_batch<float, fn<float>>, &port_batch<double, fn<double>> }
constexpr Port kPorts[] = {
    SGLAB_PEER_PORT("clamped-cosine", "punctual", cc_punctual),
    SGLAB_PEER_PORT("clamped-cosine", "punctual-approx", cc_punctual_approx),
    SGLAB_PEER_PORT("clamped-cosine", "sg-cosine", cc_sg_cosine),
    SGLAB_PEER_PORT("clamped-cosine", "cosine-lobe-sg", cc_cosine_lobe_sg),
    SGLAB_PEER_PORT("clamped-cosine", "hill-fitted", cc_hill_fitted),
    SGLAB_PEER_PORT("clamped-cosine", "meder", cc_meder),
    SGLAB_PEER_PORT("clamped-cosine", "tokuyoshi2022", cc_tokuyoshi2022),
    SGLAB_PEER_PORT("clamped-cosine", "tokuyoshi2024", cc_tokuyoshi2024),
    SGLAB_PEER_PORT("clamped-cosine", "sglab", cc_sglab),
    SGLAB_PEER_PORT("hemispherical", "meder", hemi_meder),
    SGLAB_PEER_PORT("hemispherical", "tokuyoshi2022", hemi_tokuyoshi2022),
    SGLAB_PEER_PORT("hemispherical", "vmf-tokuyoshi2024", hemi_vmf_tokuyoshi2024),
#define SGLAB_PEER_PORT6(q, m, fn) \
  Port { q, m, &port_batch6<float, fn<float>>, &port_batch6<double, fn<double>> }
    SGLAB_PEER_PORT6("specular", "sg-warp", spec_sg_warp),
    SGLAB_PEER_PORT6("specular", "sg-warp-product-axis", spec_sg_warp_product_axis),
    SGLAB_PEER_PORT6("specular", "sg-warp-iwasaki", spec_sg_warp_iwasaki),
    SGLAB_PEER_PORT6("specular", "sg-warp-th2019", spec_sg_warp_th2019),
    SGLAB_PEER_PORT6("specular", "asg", spec_asg),
    SGLAB_PEER_PORT6("specular", "sg-warp-dvn", spec_sg_warp_dvn),
    SGLAB_PEER_PORT6("specular", "sglab", spec_sglab),
    SGLAB_PEER_PORT6("specular-gaussian-ndf", "sg-warp", gndf_sg_warp),
    SGLAB_PEER_PORT6("specular-gaussian-ndf", "sg-warp-meder", gndf_sg_warp_meder),
};
#undef SGLAB_PEER_PORT6
#undef SGLAB_PEER_PORT

}  // namespace

std::span<const Port> ports() { return kPorts; }

const Port* find_port(std::string_view quantity, std::string_view method) {
  for (const auto& p : kPorts)
    if (p.quantity == quantity && p.method == method) return &p;
  return nullptr;
}

}  // namespace sglab::peer
