#include "cli/scene_args.h"

namespace meshtour::cli {

void add_scene_options(CLI::App& cmd, SceneArgs& args, options::Command command, const options::Bindings& bound,
                       bool with_input) {
  if (with_input)
    cmd.add_option("input", args.input, "Mesh (" + supported_mesh_formats() + ") or scene file (.json); default: built-in scene");
  options::add_command_options(cmd, command, args.values, bound);
}

void add_mesh_argument(CLI::App& cmd, std::string& mesh) {
  cmd.add_option("mesh", mesh, "Mesh file (" + supported_mesh_formats() + ")")->required()->type_name("MESH");
}

}  // namespace meshtour::cli
