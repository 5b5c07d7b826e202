// OpenEXR encoding and decoding (exr.hpp).
#include "sglab/render/exr.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>

#include <fmt/format.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfVersion.h>

#include "sglab/text_limits.hpp"

namespace sglab::render {
namespace {

// An Imf::OStream into a std::string (OpenEXR seeks back to write the line offset table).
class MemoryStream : public Imf::OStream {
 public:
  MemoryStream() : Imf::OStream("<memory>") {}
  void write(const char c[], int n) override {
    if (position_ + std::size_t(n) > data_.size()) data_.resize(position_ + std::size_t(n));
    std::memcpy(data_.data() + position_, c, std::size_t(n));
    position_ += std::size_t(n);
  }
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t position) override { position_ = position; }
  std::string take() { return std::move(data_); }

 private:
  std::string data_;
  std::size_t position_ = 0;
};

}  // namespace

std::string encode_exr(int width, int height, const std::vector<ImageLayer>& layers,
                       const std::vector<std::pair<std::string, std::string>>& attributes) {
  const std::size_t n = std::size_t(width) * std::size_t(height);
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
  // Planar float copies of every channel (the frame buffer points into them).
  std::vector<std::vector<float>> planes;
  planes.reserve(3 * layers.size());
  Imf::FrameBuffer frame;
  for (const auto& layer : layers) {
    if (layer.pixels.size() != n) throw std::runtime_error("encode_exr: layer '" + layer.name + "' has the wrong size");
    for (int c = 0; c < 3; ++c) {
      // An unnamed layer is the plain R, G, B channels (what image tools read as the colour).
      const std::string name = layer.name.empty() ? std::string(1, "RGB"[c]) : layer.name + "." + "RGB"[c];
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      std::vector<float> plane(n);
      for (std::size_t k = 0; k < n; ++k) plane[k] = float(layer.pixels[k](c));
      planes.push_back(std::move(plane));
      frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes.back().data()), sizeof(float),
                                    sizeof(float) * std::size_t(width)));
    }
  }
  MemoryStream stream;
  try {
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("encode_exr: ") + e.what());
  }
  return stream.take();
}

namespace {

// An Imf::IStream over bytes in memory (read_exr_bytes).
class MemoryInput : public Imf::IStream {
 public:
  MemoryInput(std::string_view bytes, const std::string& name) : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || std::size_t(n) > bytes_.size() - position_) throw std::runtime_error("unexpected end of file");
    std::memcpy(c, bytes_.data() + position_, std::size_t(n));
    position_ += std::size_t(n);
    return position_ < bytes_.size();
  }
  uint64_t tellg() override { return position_; }
  void seekg(uint64_t position) override {
    if (position > bytes_.size()) throw std::runtime_error("seek past the end of the file");
    position_ = std::size_t(position);
  }
  void clear() override {}

 private:
  std::string_view bytes_;
  std::size_t position_ = 0;
};

// OpenEXR's own header checks refuse larger images while the header is read (before it allocates
// its line offset table); decode() checks the same and the channel count before allocating planes.
void limit_header_sizes() {
  static std::once_flag once;
  std::call_once(once, [] { Imf::Header::setMaxImageSize(int(kMaxExrWidth), int(kMaxExrHeight)); });
}

// The float planes of `file_bytes` bytes of EXR can hold at most this many bytes per file byte
// (plus kExrSlackBytes): deflate (ZIP) expands at most 1032:1, RLE 64:1; 4096 leaves room for
// the other codecs. A header that claims more pixels than its file could hold is refused before
// anything is allocated for it.
constexpr long long kMaxExrOrigin = 1LL << 24;
constexpr unsigned long long kExrExpansion = 4096, kExrSlackBytes = 16ULL << 20;

// Reads the (first) header of the EXR on `in` and checks it against the reader's limits, before
// Imf::InputFile allocates its line buffers and offset tables from it (which it sizes from the
// header's data window alone). Leaves `in` at the start.
void check_header(Imf::IStream& in, unsigned long long file_bytes) {
  char start[8];
  in.read(start, 8);
  if (!Imf::isImfMagic(start)) throw std::runtime_error("not an OpenEXR file (no magic number)");
  int version = int((unsigned char)start[4]) | int((unsigned char)start[5]) << 8 | int((unsigned char)start[6]) << 16 |
                int((unsigned char)start[7]) << 24;
  if (version & Imf::MULTI_PART_FILE_FLAG)
    throw std::runtime_error("a multi-part EXR (sglab reads single-part images)");
  if (version & Imf::NON_IMAGE_FLAG) throw std::runtime_error("a deep-data EXR (sglab reads flat images)");
  Imf::Header header;
  header.readFrom(in, version);
  const Imath::Box2i window = header.dataWindow();
  const long long w = (long long)window.max.x - window.min.x + 1, h = (long long)window.max.y - window.min.y + 1;
  std::size_t channel_count = 0;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) ++channel_count;
  if (w < 1 || h < 1 || w > kMaxExrWidth || h > kMaxExrHeight || w * h > kMaxExrPixels)
    throw std::runtime_error(fmt::format("the header says {} × {} pixels; the limit is {} × {} and {} pixels", w, h,
                                         kMaxExrWidth, kMaxExrHeight, kMaxExrPixels));
  if (channel_count > kMaxExrChannels)
    throw std::runtime_error(
        fmt::format("the header lists {} channels; the limit is {}", channel_count, kMaxExrChannels));
  // The frame buffer is addressed from the window's origin: keep it near 0 (no pointer overflow).
  if (std::llabs(window.min.x) > kMaxExrOrigin || std::llabs(window.min.y) > kMaxExrOrigin)
    throw std::runtime_error(
        fmt::format("the data window starts at ({}, {}); the limit is ±{}", window.min.x, window.min.y, kMaxExrOrigin));
  const unsigned long long need = (unsigned long long)(w * h) * std::max<std::size_t>(channel_count, 1) * sizeof(float);
  if (need > kMaxExrPlaneBytes)
    throw std::runtime_error(
        fmt::format("{} × {} pixels in {} channels need {:.3g} GB as float; the limit is {:.3g} GB", w, h,
                    channel_count, double(need) / 1e9, double(kMaxExrPlaneBytes) / 1e9));
  if (need > kExrSlackBytes + kExrExpansion * file_bytes)
    throw std::runtime_error(
        fmt::format("the header says {} × {} pixels in {} channels ({:.3g} MB as float), more than a "
                    "file of {} bytes can hold",
                    w, h, channel_count, double(need) / 1e6, file_bytes));
  in.seekg(0);
}

// The pixels of a file whose header check_header accepted.
ExrImage decode(Imf::InputFile& file) {
  ExrImage image;
  const Imath::Box2i window = file.header().dataWindow();
  const long long w = (long long)window.max.x - window.min.x + 1, h = (long long)window.max.y - window.min.y + 1;
  image.width = int(w);
  image.height = int(h);
  const std::size_t n = std::size_t(w) * std::size_t(h);
  Imf::FrameBuffer frame;
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
    auto& plane = image.channels[it.name()];
    plane.assign(n, 0.0f);
    char* base = reinterpret_cast<char*>(plane.data()) -
                 (std::ptrdiff_t(window.min.x) + std::ptrdiff_t(window.min.y) * image.width) *
                     std::ptrdiff_t(sizeof(float));
    frame.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * std::size_t(image.width)));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  for (auto it = file.header().begin(); it != file.header().end(); ++it)
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
      image.attributes[it.name()] = s->value();
  return image;
}

}  // namespace

ExrImage read_exr(const std::string& path) {
  limit_header_sizes();
  try {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    Imf::StdIFStream in(path.c_str());
    check_header(in, ec ? 0 : bytes);
    Imf::InputFile file(in);
    return decode(file);
  } catch (const std::exception& e) {
    throw std::runtime_error("read_exr: " + quote(path) + ": " + bounded_message(e.what(), 400));
  }
}

ExrImage read_exr_bytes(std::string_view bytes, const std::string& name) {
  limit_header_sizes();
  try {
    MemoryInput in(bytes, name);
    check_header(in, bytes.size());
    Imf::InputFile file(in);
    return decode(file);
  } catch (const std::exception& e) {
    throw std::runtime_error("read_exr: " + quote(name) + ": " + bounded_message(e.what(), 400));
  }
}

}  // namespace sglab::render
