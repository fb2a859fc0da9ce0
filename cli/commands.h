#pragma once
// Sub-commands of the meshtour executable. Each adds itself to the app; its callback throws
// meshtour::Error on failure and main() turns that into one line on stderr and an exit code.
#include <CLI/CLI.hpp>

#include <exception>

namespace meshtour::cli {

void add_tour_command(CLI::App& app);  // mesh or scene in, video out
void add_path_command(CLI::App& app);  // the camera path of a mesh, as JSON (+ plot, debug PLYs)
void add_encode_command(CLI::App& app);  // a frames directory in, video out (H.264, ProRes, FFV1, VP9, GIF)

/// Thrown by throw_if_interrupted() after SIGINT or SIGTERM, so that destructors remove partial
/// outputs on the way out; main() exits with 130.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};
/// Makes SIGINT/SIGTERM set a flag instead of killing the process (long commands call this).
void install_interrupt_handlers();
/// Throws Interrupted once a handled signal has arrived.
void throw_if_interrupted();

}  // namespace meshtour::cli
