#pragma once
// Command-line options of the toroidal-patch path (ALGORITHM.md §2), shared by `meshtour path`
// and `meshtour tour`.
#include <CLI/CLI.hpp>

#include "pathgen/paper_path.h"

namespace meshtour::cli {

/// Adds every option of `options` except the up direction (the caller owns --up, which means
/// the same for every path mode) and the thread count, in help groups by stage, with the
/// defaults currently held in `options` shown. Parsed values are written into `options`, which
/// must outlive the parse (hold it in the command's shared state).
void add_paper_path_options(CLI::App& cmd, PaperPathOptions& options);

/// Help text of --up for the paper path (axis, vector, longest-aabb or pca; I-18).
extern const char* const kPaperUpHelp;

/// CLI11 check for an up direction accepted by UpDirection::parse.
CLI::Validator up_direction_validator();

}  // namespace meshtour::cli
