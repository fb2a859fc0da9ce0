// The named looks (presets). Light directions are in camera space: x right, y up, z towards the
// viewer, so the lighting travels with the camera.
#include "core/error.h"
#include "tracer/tracer.h"

namespace meshtour {

Shading look_preset(const std::string& name) {
  Shading sh;
  sh.preset = name;
  if (name == "studio") {
    // Classic three-point lighting: a warm key above-left of the camera (its soft shadow falls
    // down-right, where the viewer expects it), a cool dim fill from the right to open the
    // shadows, a rim from behind-above that separates the silhouette from the background.
    Light key{{-0.55f, 0.85f, 0.6f}, {1.0f, 0.96f, 0.90f}, 1.15f, 22.0f};
    Light fill{{0.85f, 0.15f, 0.55f}, {0.90f, 0.95f, 1.0f}, 0.3f, 45.0f};
    Light rim{{0.2f, 1.3f, -0.7f}, {1.0f, 1.0f, 1.0f}, 0.6f, 15.0f};
    sh.lights = {key, fill, rim};
    sh.shadows = true;
    sh.ambient = {0.22f, 0.23f, 0.25f};
    sh.ambient_occlusion = true;
    sh.ground = true;
    sh.background = BackgroundKind::gradient;
    sh.background_top = {0.50f, 0.51f, 0.53f};
    sh.background_bottom = {0.13f, 0.13f, 0.14f};
    sh.tone_mapping = ToneMapping::filmic;
    return sh;
  }
  if (name == "plain") {
    // Even light for catalogues: from just above the camera, plus a strong sky, no shadows.
    Light front{{0.0f, 0.35f, 1.0f}, {1.0f, 1.0f, 1.0f}, 0.9f, 0.0f};
    sh.lights = {front};
    sh.shadows = false;
    sh.ambient = {0.55f, 0.55f, 0.55f};
    sh.ambient_occlusion = false;
    sh.ground = false;
    sh.background = BackgroundKind::gradient;
    sh.background_top = {1.6f, 1.6f, 1.6f};
    sh.background_bottom = {1.6f, 1.6f, 1.6f};
    sh.tone_mapping = ToneMapping::filmic;
    return sh;
  }
  throw InputError("unknown look preset '" + name + "'; the presets are: " + look_preset_names());
}

std::string look_preset_names() { return "studio, plain"; }

}  // namespace meshtour
