#pragma once
// The rendering options of the commands that render frames (tour; later render): look preset,
// samples per pixel, EXR layers, field of view. Kept apart from each command's own options so
// that every rendering command offers the same ones.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "scenes/scene.h"

namespace meshtour::cli {

struct RenderArgs {
  std::optional<std::string> preset;
  std::optional<int> spp;
  std::optional<std::string> background;
  std::optional<double> exposure;
  std::vector<std::string> exr_layers;
};

/// Adds --preset, --spp, --background, --exposure and --exr-layers to `cmd`.
void add_render_options(CLI::App& cmd, RenderArgs& args);

/// Applies the options given on the command line to `scene` (after the scene file was read and
/// the command's own overrides, such as --up, were applied).
void apply_render_options(const RenderArgs& args, Scene& scene);

}  // namespace meshtour::cli
