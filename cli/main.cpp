// meshtour: mesh in, tour video out. main() only wires the sub-commands and turns errors into
// one line on stderr and an exit code; the work happens in the commands and the libraries.
#include <CLI/CLI.hpp>

#include <iostream>

#include "cli/commands.h"
#include "tour/batch_job.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/memory_policy.h"
#include "options/option_registry.h"

namespace {

constexpr const char* kFooter = R"(
Exit codes: 0 success, 1 unexpected failure, 2 bad input or options, 3 file could not be read or
written, 4 rendering or encoding failed, 5 some items of a batch failed (the others were done),
130 interrupted.

Examples:
  meshtour tour                                  # the built-in default scene -> meshtour-default.mp4
  meshtour tour bunny.ply --up y -o bunny.mp4    # a mesh file, 4 s at 30 fps
  meshtour render bunny.ply --out-dir frames --frames 0-59   # a chunk of frames, resumable
  meshtour batch catalogue.csv --out-dir videos  # one video per manifest item
  meshtour farm slurm bunny.ply --out-dir /shared/bunny --chunk-size 10 --submit
  meshtour tour scenes/default.json --frames 48 --width 640 --height 360
  meshtour path bunny.ply -o bunny.path.json --plot bunny.png
  meshtour evaluate bunny.ply --compare          # coverage and smoothness of turntable, paper, feature-orbit
  meshtour info scan.glb --json                  # what a file holds: counts, materials, textures, memory
Run 'meshtour <command> --help' for the options of a command.)";

// For flags the chosen command does not take but another one does (or takes under another
// name: tour's --frames is render's --frame-count): "; hint: ..." per flag, from the registry.
std::string misplaced_flag_hints(const CLI::App& app, int argc, char** argv) {
  const CLI::App* command = nullptr;
  std::string hints;
  for (int i = 1; i < argc; ++i) {
    const std::string token = argv[i];
    const CLI::App* parent = command ? command : &app;
    const CLI::App* sub = nullptr;
    for (const CLI::App* s : parent->get_subcommands([](const CLI::App*) { return true; }))
      if (s->get_name() == token) sub = s;
    if (sub) {  // the command, or a command's command (farm slurm)
      command = sub;
      continue;
    }
    if (!command) continue;
    if (token.rfind("--", 0) != 0 || token.size() < 3) continue;
    const std::string flag = token.substr(0, token.find('='));
    if (command->get_option_no_throw(flag)) continue;
    if (const std::string hint = meshtour::options::misplaced_flag_hint(command->get_name(), flag); !hint.empty())
      hints += "; " + hint;
  }
  return hints;
}

}  // namespace

int main(int argc, char** argv) {
  // From the first moment: Ctrl-C or SIGTERM at any point ends every command with 130.
  meshtour::install_interrupt_handlers();
  meshtour::keep_freed_frame_buffers();
  CLI::App app{"meshtour: renders a tour video of a 3D triangle mesh, along a camera path computed from its geometry."};
  app.set_version_flag("--version", std::string("meshtour ") + MESHTOUR_VERSION);
  app.footer(kFooter);
  app.require_subcommand(1);
  meshtour::cli::add_tour_command(app);
  meshtour::cli::add_path_command(app);
  meshtour::cli::add_encode_command(app);
  meshtour::cli::add_render_command(app);
  meshtour::cli::add_batch_command(app);
  meshtour::cli::add_farm_command(app);
  meshtour::cli::add_evaluate_command(app);
  meshtour::cli::add_options_command(app);
  meshtour::cli::add_info_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "meshtour: " << e.what() << " (see 'meshtour --help')" << misplaced_flag_hints(app, argc, argv) << "\n";
    return 2;
  } catch (const meshtour::Error& e) {
    std::cerr << "meshtour: error: " << e.what() << "\n";
    return meshtour::exit_class_of(e).code;
  } catch (const meshtour::SomeItemsFailed& e) {
    std::cerr << "meshtour: " << e.what() << " (see the summary above)\n";
    return meshtour::kSomeItemsFailedExitCode;
  } catch (const meshtour::Interrupted&) {
    std::cerr << "meshtour: interrupted; partial outputs removed\n";
    return 130;
  } catch (const std::exception& e) {
    std::cerr << "meshtour: unexpected error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
