#include "cli/common_options.h"

#include "core/error.h"

namespace meshtour::cli {

void add_resource_options(CLI::App& cmd, ResourceArgs& args) {
  const std::string group = "Resources";
  cmd.add_option("--max-memory", args.max_memory,
                 "Memory the job may use, e.g. 512M or 8G (default: 75% of this machine's memory). A job whose "
                 "estimated peak is larger is refused before it allocates anything")
      ->type_name("SIZE")
      ->check([](const std::string& text) -> std::string {
        try {
          parse_memory_size(text);
        } catch (const InputError& e) {
          return e.what();
        }
        return {};
      })
      ->group(group);
  cmd.add_flag("--verbose", args.verbose, "Report the time and memory (resident, peak) of every stage on stderr")
      ->group(group);
}

void add_progress_option(CLI::App& cmd, std::string& mode) {
  cmd.add_option("--progress", mode,
                 "Progress on stderr: bar (frames done, frames/s, time left), json (one JSON line per finished frame\n"
                 "and a summary line, for farm logs), none, or auto (default): bar on a terminal, json otherwise")
      ->check(CLI::IsMember({"auto", "bar", "json", "none"}));
}

}  // namespace meshtour::cli
