#pragma once
// The command-line side of the option registry: a command's options, as CLI11 sees them, come
// from the rows that name the command.
#include <CLI/CLI.hpp>

#include "options/option_registry.h"

namespace meshtour::options {

/// Adds every registry row that `command` takes to `cmd`; what the user gives lands in `values`
/// (canonical text, checked by the row). `values` must outlive the parse. Rows that exclude each
/// other (--frames / --seconds) are declared so to CLI11.
void add_registered_options(CLI::App& cmd, Command command, Values& values);

/// Adds only the listed rows (for commands that take a few shared ones).
void add_registered_options(CLI::App& cmd, Command command, Values& values, std::initializer_list<std::string_view> ids);

}  // namespace meshtour::options
