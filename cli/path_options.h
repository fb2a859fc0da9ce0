#pragma once
// The path search's settings (registry rows with scene keys "patches.*" and "paper.*"; their
// flags, ranges and help are rows of options/option_registry.cpp) turned into the options of the
// toroidal-patch stage, which the feature orbit shares.
#include <CLI/CLI.hpp>

#include "options/option_registry.h"
#include "pathgen/paper_path.h"

namespace meshtour::cli {

/// `base` with every path-search value of `values` applied (checked text, see options::check_value).
PaperPathOptions paper_path_options(const options::Values& values, PaperPathOptions base = {});

/// Help text of --up for the paper path (axis, vector, longest-aabb or pca; I-18).
extern const char* const kPaperUpHelp;

/// CLI11 check for an up direction accepted by UpDirection::parse.
CLI::Validator up_direction_validator();

}  // namespace meshtour::cli
