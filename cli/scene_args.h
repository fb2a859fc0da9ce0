#pragma once
// The command-line side of a tour: the INPUT positional and the registry options a command takes,
// resolved by the tour library (tour/tour.h).
#include <CLI/CLI.hpp>

#include <string>
#include <string_view>

#include "options/cli_options.h"
#include "tour/tour.h"

namespace meshtour::cli {

/// Which tour to render: the input and every registry value the command line gave.
struct SceneArgs {
  std::string input;  // mesh or .json scene; empty = built-in default scene
  options::Values values;
};

/// Adds the INPUT positional (when `with_input`) and every registry row `command` takes to `cmd`.
void add_scene_options(CLI::App& cmd, SceneArgs& args, options::Command command, bool with_input = true);

/// The scene the arguments describe (tour/tour.h's resolve_scene).
inline Scene resolve_scene(const SceneArgs& args, std::string_view codec = "h264") {
  return meshtour::resolve_scene(args.input, args.values, codec);
}

}  // namespace meshtour::cli
