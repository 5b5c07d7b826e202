// OpenEXR encoding and decoding (exr.hpp).
#include "sglab/render/exr.hpp"

#include <cstring>
#include <stdexcept>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

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

ExrImage read_exr(const std::string& path) {
  ExrImage image;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    const std::size_t n = std::size_t(image.width) * std::size_t(image.height);
    Imf::FrameBuffer frame;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      auto& plane = image.channels[it.name()];
      plane.assign(n, 0.0f);
      char* base = reinterpret_cast<char*>(plane.data()) -
                   (std::ptrdiff_t(window.min.x) + std::ptrdiff_t(window.min.y) * image.width) * std::ptrdiff_t(sizeof(float));
      frame.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * std::size_t(image.width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    for (auto it = file.header().begin(); it != file.header().end(); ++it)
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) image.attributes[it.name()] = s->value();
  } catch (const std::exception& e) {
    throw std::runtime_error("read_exr: " + path + ": " + e.what());
  }
  return image;
}

}  // namespace sglab::render
