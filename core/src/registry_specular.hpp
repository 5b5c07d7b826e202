// The columns shared by the quantities of specular reflection of an SG light (`specular`, GGX;
// `specular-gaussian-ndf`): one list, so that both read their rows alike (specular_input).
#pragma once

#include <string>
#include <vector>

#include "sglab/registry.hpp"

namespace sglab {

// roughness, light_sharpness, light_cos, view_cos, light_azimuth, f0 in this order; only the
// roughness's meaning differs between the BRDFs (`roughness` describes it). In registry_glossy.cpp.
std::vector<Column> specular_columns(std::string roughness);

// The `specular` quantity's method `sglab` (this project's own), registered last among its methods
// by registry_glossy.cpp. In registry_specular_sglab.cpp, apart from the published methods.
Method specular_sglab_method();

}  // namespace sglab
