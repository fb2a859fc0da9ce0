#pragma once
// Command-line options of the resource limits and of progress reporting (tour/resources.h,
// tour/progress.h), shared by the commands that run long jobs.
#include <CLI/CLI.hpp>

#include <string>

#include "tour/progress.h"
#include "tour/resources.h"

namespace meshtour::cli {

/// Adds --max-memory SIZE and --verbose to `cmd`. `args` must outlive the parse.
void add_resource_options(CLI::App& cmd, ResourceArgs& args);

/// Adds --progress auto|bar|json|none to `cmd`, writing into `mode` (text kept for CLI11).
void add_progress_option(CLI::App& cmd, std::string& mode);

}  // namespace meshtour::cli
