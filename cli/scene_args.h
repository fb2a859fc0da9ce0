#pragma once
// The command-line side of a tour: the INPUT positional and the registry options a command takes,
// resolved by the tour library (tour/tour.h).
#include <CLI/CLI.hpp>

#include <string>
#include <string_view>

#include "options/cli_options.h"
#include "tour/tour.h"

namespace meshtour::cli {

/// Adds the INPUT positional (when `with_input`) and every registry row `command` takes to `cmd`.
void add_scene_options(CLI::App& cmd, SceneArgs& args, options::Command command, bool with_input = true);

}  // namespace meshtour::cli
