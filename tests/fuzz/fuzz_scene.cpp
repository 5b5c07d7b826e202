// libFuzzer target: the scene reader of `render`, `filter` and `sweep render` (scene.hpp): JSON
// text, then optionally one `--set KEY=VALUE` override (the bytes after the first NUL of the
// input), validation, and the serialisation of the accepted document. Any input must give either
// a Scene or the reader's own SceneError with a short message; anything else (another exception, a
// crash, a sanitizer report) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "sglab/render/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  const std::string text = input.substr(0, nul);
  try {
    nlohmann::json document = sglab::render::parse_scene_text(text, "<fuzz>");
    if (nul != std::string::npos) sglab::render::apply_override(document, input.substr(nul + 1));
    const sglab::render::Scene scene = sglab::render::parse_scene(document);
    if (scene.camera.width < 1 || scene.camera.height < 1) sglab::fuzz::fail("a scene with an empty image");
    if (scene.objects.empty()) sglab::fuzz::fail("a scene without objects");
    // The commands serialise the accepted document (stats, sweep fingerprints): it must dump.
    (void)document.dump();
  } catch (const sglab::render::SceneError& e) {
    sglab::fuzz::check_message(e.what());
  }
  return 0;
}
