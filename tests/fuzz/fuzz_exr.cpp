// libFuzzer target: the OpenEXR reader of `fit envmap`, `envmap render|lobes` and scenes'
// environments (exr.hpp, read_exr_bytes: the same decoding as read_exr on a file). Any input must
// give either an image within the reader's limits whose every channel holds width × height values,
// or the reader's std::runtime_error with a short message; anything else (another exception, a
// crash, a sanitizer report, an allocation beyond the limits) is a finding. See docs/testing.md.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_common.hpp"
#include "sglab/render/exr.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sglab::render;
  try {
    const ExrImage image = read_exr_bytes(std::string_view(reinterpret_cast<const char*>(data), size), "<fuzz>");
    if (image.width < 1 || image.height < 1 || image.width > kMaxExrWidth || image.height > kMaxExrHeight)
      sglab::fuzz::fail("an image outside the reader's limits");
    if (image.channels.size() > kMaxExrChannels) sglab::fuzz::fail("more channels than the limit");
    for (const auto& [name, plane] : image.channels)
      if (plane.size() != std::size_t(image.width) * std::size_t(image.height))
        sglab::fuzz::fail("a channel of the wrong size");
  } catch (const std::runtime_error& e) {
    sglab::fuzz::check_message(e.what());
  }
  return 0;
}
