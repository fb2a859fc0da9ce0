// meshtour options: prints the option registry (docs/OPTIONS.md is this command's output).
#include <cstdio>

#include "cli/commands.h"
#include "options/option_registry.h"

namespace meshtour::cli {

void add_options_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("options", "List every option of every command, with ranges, defaults, scene keys and columns.");
  cmd->description("Prints the option registry as Markdown (this is how docs/OPTIONS.md is made:\n"
                   "  meshtour options > docs/OPTIONS.md).");
  cmd->callback([] {
    const std::string text = options::options_markdown();
    std::fwrite(text.data(), 1, text.size(), stdout);
  });
}

}  // namespace meshtour::cli
