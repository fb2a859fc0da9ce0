#include "cli/scene_args.h"

namespace meshtour::cli {

void add_scene_options(CLI::App& cmd, SceneArgs& args, options::Command command, bool with_input) {
  if (with_input)
    cmd.add_option("input", args.input, "Mesh (" + supported_mesh_formats() + ") or scene file (.json); default: built-in scene");
  options::add_registered_options(cmd, command, args.values);
}

}  // namespace meshtour::cli
