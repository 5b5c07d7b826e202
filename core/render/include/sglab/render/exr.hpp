// Multi-layer OpenEXR images: one RGB layer per named image, channels
// `LAYER.R`, `LAYER.G`, `LAYER.B` (OpenEXR's layer naming convention), 32-bit float, ZIP
// compression. encode_exr() produces the file's bytes in memory so that the caller can write them
// atomically (temporary file + rename); read_exr() reads any scan-line EXR's channels back
// (used by tests and tools).
#pragma once

#include <map>
#include <string>
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
// Throws std::runtime_error for an unreadable file.
ExrImage read_exr(const std::string& path);

}  // namespace sglab::render
