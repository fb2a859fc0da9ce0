// Fuzz target: the Voyager scene-document parser (parse_voyager_document), as resolve_scene()
// calls it on a .svx.json file's text. Every malformed document must end in meshtour::InputError.
// Asset files whose name contains "on_disk" count as present, so that the choice of derivative
// is reached too; nothing is read from disk.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "scenes/voyager.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto exists = [](const std::filesystem::path& p) { return p.filename().string().find("on_disk") != std::string::npos; };
  try {
    const meshtour::VoyagerDocument doc = meshtour::parse_voyager_document(text, "fuzz.svx.json", "/nonexistent", "", exists);
    // A document the parser accepts gives a model file, a finite pose and a view direction.
    if (doc.model_file.empty() || !doc.transform.allFinite() || !doc.view_direction().allFinite()) __builtin_trap();
  } catch (const meshtour::InputError&) {
  }
  return 0;
}
