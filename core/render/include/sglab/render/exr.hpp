// Multi-layer OpenEXR images: one RGB layer per named image, channels
// `LAYER.R`, `LAYER.G`, `LAYER.B` (OpenEXR's layer naming convention), 32-bit float, ZIP
// compression. encode_exr() produces the file's bytes in memory so that the caller can write them
// atomically (temporary file + rename); read_exr() reads any scan-line EXR's channels back
// (used by tests and tools).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sglab/render/vpl.hpp"

namespace sglab::render {

struct ImageLayer {
  std::string name;
  std::vector<Rgb> pixels;  // row-major, width × height, row 0 at the top
};

// The bytes of an EXR file holding every layer, plus string attributes in the header (e.g. the
// command that made it). Throws std::runtime_error (OpenEXR's message) on failure.
std::string encode_exr(int width, int height, const std::vector<ImageLayer>& layers,
                       const std::vector<std::pair<std::string, std::string>>& attributes = {});

struct ExrImage {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> channels;  // by full channel name, row-major
  std::map<std::string, std::string> attributes;       // string attributes of the header
};
// The largest image read_exr() decodes: a header is checked against these before any pixel memory
// is allocated, so a small file whose header claims 65536 × 32768 pixels is refused at once
// instead of allocating gigabytes. 16384 × 8192 is four times the largest map `sglab envmap make`
// writes (8192 × 4096); 64 channels are far more than any layered EXR of sglab (18).
inline constexpr long long kMaxExrWidth = 16384, kMaxExrHeight = 16384;
inline constexpr long long kMaxExrPixels = 16384LL * 8192;
inline constexpr std::size_t kMaxExrChannels = 64;
inline constexpr unsigned long long kMaxExrPlaneBytes = 2ULL << 30;  // all channels as float: 2 GiB

// Throws std::runtime_error for an unreadable file or one larger than the limits above (the
// message names the file, clipped, and the size its header claims).
ExrImage read_exr(const std::string& path);
// The same from the file's bytes in memory; `name` names it in messages.
ExrImage read_exr_bytes(std::string_view bytes, const std::string& name);

}  // namespace sglab::render
