#pragma once
// Sub-commands of the meshtour executable. Each adds itself to the app; its callback throws
// meshtour::Error on failure and main() turns that into one line on stderr and an exit code.
#include <CLI/CLI.hpp>

#include <exception>

#include "core/interrupt.h"

namespace meshtour::cli {

void add_tour_command(CLI::App& app);  // mesh or scene in, video out
void add_path_command(CLI::App& app);  // the camera path of a mesh, as JSON (+ plot, debug PLYs)
void add_encode_command(CLI::App& app);  // a frames directory in, video out (H.264, ProRes, FFV1, VP9, GIF)
void add_render_command(CLI::App& app);  // frames (all or a chunk) into a frames directory, resumable
void add_batch_command(CLI::App& app);   // a manifest of meshes in, one video per item
void add_farm_command(CLI::App& app);
void add_options_command(CLI::App& app);  // every option of every command (docs/OPTIONS.md)    // sbatch scripts for a Slurm job array + dependent encode

void add_evaluate_command(CLI::App& app);
void add_info_command(CLI::App& app);  // what a mesh file holds, before anything is rendered  // what a tour shows: coverage and smoothness per path mode

}  // namespace meshtour::cli
