#pragma once
// `meshtour path`'s --up, which takes more than a coordinate axis (a vector, pca, longest-aabb).
// (The path search's other settings are rows of the option registry, applied by tour/tour.h.)
#include <CLI/CLI.hpp>

#include "options/option_registry.h"
#include "pathgen/paper_path.h"

namespace meshtour::cli {

/// Help text of --up for the paper path (axis, vector, longest-aabb or pca; I-18).
extern const char* const kPaperUpHelp;

/// CLI11 check for an up direction accepted by UpDirection::parse.
CLI::Validator up_direction_validator();

}  // namespace meshtour::cli
