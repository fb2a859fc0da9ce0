#include "cli/commands.h"
namespace meshtour::cli { void add_path_command(CLI::App&) {} }
