// A mixture record: the JSON `sglab fit envmap --json` writes ({"fit": "envmap", "parameters":
// {"lobe<k>.<field>": …}}), read by `envmap render`, `envmap make mixture` and scenes'
// "environment": {"mixture": …}. A record is untrusted text: it is read only when it is a regular
// file of at most kMaxJsonBytes, and every key and value is checked.
#pragma once

#include <string>
#include <string_view>

#include "sglab/envmap.hpp"
#include "sglab/render/environment.hpp"

namespace sglab::render {

// The fields of lobe k in a mixture record: parameters "lobe<k>.<field>".
inline constexpr const char* kMixtureLobeFields[7] = {"axis_x", "axis_y", "axis_z", "sharpness", "r", "g", "b"};

// Bounds of a lobe read from a record. 4096 lobes: four times the most a scene fits (1024).
// Amplitude ≤ 1e30: the sum of 4096 such lobes (≤ 4.1e33) stays a finite float texel (FLT_MAX
// ≈ 3.4e38) and its square a finite double. Sharpness ≤ 1e6: a lobe 1/√1e6 = 1e-3 rad wide, about
// the texel of the largest map sglab reads (16384 wide: 3.8e-4 rad); a sharper one is a point the
// texel quadratures cannot resolve, and its exp(−λ…) products underflow in the shading statistics.
inline constexpr std::size_t kMaxMixtureLobes = 4096;
inline constexpr double kMaxMixtureAmplitude = 1e30;
inline constexpr double kMaxMixtureSharpness = 1e6;

// Reads a mixture record from its text; `name` names it in messages. Throws EnvironmentError
// naming the record (clipped) and the bad key or value: not JSON, nested too deep, not an object,
// "fit" other than "envmap", no "parameters" object, a key that is not "lobe<k>.<field>" or names
// a lobe past the last, a lobe missing a field, a value not a finite number, an all-zero axis
// (axes are normalised without overflow: (0, 0, 1e200) is +z), a sharpness outside [0, 1e6], an
// amplitude outside [0, 1e30], no lobes, more than 4096, or a "lobes" count that disagrees.
SgMixture parse_mixture(std::string_view text, const std::string& name);
// The same from a file (a regular file of at most kMaxJsonBytes; text_limits.hpp).
SgMixture load_mixture(const std::string& path);

}  // namespace sglab::render
