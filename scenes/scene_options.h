#pragma once
// The tour's settings given as registry values (the command line, a batch manifest: checked,
// canonical text), applied over a scene: each row's text is parsed once, here at the edge, into
// the Scene's typed field (the binding table in scenes/scene.cpp). The one place where a tour
// setting given on the command line, in a scene file or in a batch manifest takes effect; nothing
// past it sees the text.
#include <string>
#include <string_view>

#include "options/option_registry.h"
#include "scenes/scene.h"

namespace meshtour {

/// Which tour to render: the input (mesh or .json scene; empty = built-in default scene) and the
/// registry values given for it (command line, manifest).
struct SceneArgs {
  std::string input;
  options::Values values;
};

/// Applies one registry value (checked text, see options::check_value) to the scene: the row's
/// binding. Rows that are not settings of the tour (is_scene_setting) are ignored.
/// \throw InputError when the value is valid alone but not for this scene (--seconds x --fps
/// beyond the frame limit).
void apply_option(Scene& scene, const options::Option& option, const std::string& text);
/// Applies every value of `values` in registry order (so that --seconds sees the final --fps and
/// look values land on the preset), then points the ground under the up axis.
void apply_options(Scene& scene, const options::Values& values);
/// Whether the row is a setting of the tour, bound to a field of Scene.
bool is_scene_setting(const options::Option& option);
/// The value of the tone-mapping row (one of tone_mapping_names(), checked): the scene's look and
/// encode's EXR frames read it alike.
ToneMapping parse_tone_mapping(const std::string& text);

/// The scene of `input` (a scene file, a mesh with the default scene's settings, or "" for the
/// built-in default scene) with `values` applied on top; a crf is checked for `codec` (the video
/// the job makes).
Scene resolve_scene(const std::string& input, const options::Values& values, std::string_view codec = "h264");
inline Scene resolve_scene(const SceneArgs& args, std::string_view codec = "h264") {
  return resolve_scene(args.input, args.values, codec);
}

}  // namespace meshtour
