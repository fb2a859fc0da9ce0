// Fuzz target: the scene-file parser (parse_scene), as load_scene() calls it on a file's text.
// Every malformed document must end in meshtour::InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "scenes/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const meshtour::Scene scene = meshtour::parse_scene(text, "fuzz.json", "/nonexistent");
    // A scene the parser accepts must be one the renderer can take.
    if (scene.render.width < 2 || scene.render.height < 2 || scene.frames < 1 || scene.fps < 1) __builtin_trap();
  } catch (const meshtour::InputError&) {
  }
  return 0;
}
