#pragma once
// The command-line side of a tour: the positional arguments naming the model, and the registry
// options a command takes: its own bound to its job's fields, the tour's settings gathered in
// SceneArgs and resolved into a Scene (scenes/scene_options.h) before the job runs.
#include <CLI/CLI.hpp>

#include <string>
#include <string_view>

#include "options/cli_options.h"
#include "scenes/scene_options.h"

namespace meshtour::cli {

/// Adds the INPUT positional (when `with_input`) and every registry row `command` takes to `cmd`:
/// the rows in `bound` to their fields, the tour's settings into args.values.
void add_scene_options(CLI::App& cmd, SceneArgs& args, options::Command command, const options::Bindings& bound,
                       bool with_input = true);

/// Adds the required MESH positional (path, evaluate, info).
void add_mesh_argument(CLI::App& cmd, std::string& mesh);

}  // namespace meshtour::cli
