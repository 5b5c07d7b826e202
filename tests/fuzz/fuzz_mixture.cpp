// libFuzzer target: the mixture record reader of `envmap render`, `envmap make mixture` and scenes'
// environments (mixture_record.hpp, parse_mixture). Any input must give either a mixture whose
// every lobe has a unit axis and a sharpness and amplitude within the record's bounds, or the
// reader's EnvironmentError with a short message; anything else (another exception, a crash, a
// sanitizer report) is a finding. See docs/testing.md.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.hpp"
#include "sglab/render/mixture_record.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sglab::render;
  try {
    const sglab::SgMixture m = parse_mixture(std::string_view(reinterpret_cast<const char*>(data), size), "<fuzz>");
    if (m.empty() || m.size() > kMaxMixtureLobes) sglab::fuzz::fail("a lobe count outside [1, kMaxMixtureLobes]");
    for (const auto& l : m) {
      if (!(std::fabs(l.axis.norm() - 1) < 1e-12)) sglab::fuzz::fail("a lobe axis that is not a unit vector");
      if (!(l.sharpness >= 0 && l.sharpness <= kMaxMixtureSharpness))
        sglab::fuzz::fail("a sharpness outside its bounds");
      for (double a : l.amplitude)
        if (!(a >= 0 && a <= kMaxMixtureAmplitude)) sglab::fuzz::fail("an amplitude outside its bounds");
    }
  } catch (const EnvironmentError& e) {
    sglab::fuzz::check_message(e.what());
  }
  return 0;
}
