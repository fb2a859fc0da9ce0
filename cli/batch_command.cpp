// meshtour batch: a catalogue job. One video per manifest item, each made by the tour pipeline in
// this process; a bad item is reported and skipped without stopping the others, items whose video
// exists are skipped (so a re-run does only what is missing), and a summary table (stdout) and
// batch-summary.json say what succeeded and failed.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/commands.h"
#include "tour/batch_job.h"
#include "cli/scene_args.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "options/batch_manifest.h"

namespace meshtour::cli {

void add_batch_command(CLI::App& app) {
  auto args = std::make_shared<BatchJob>();
  CLI::App* cmd = app.add_subcommand("batch", "Render one video per item of a manifest (CSV or JSON); for catalogues.");
  cmd->description(
      "Render one tour video per item of MANIFEST into --out-dir, each by the tour pipeline.\n"
      "CSV: a header row naming the columns, then one item per line; JSON: an array of objects (or\n"
      "{\"items\": [...]}) with the same keys. Columns: mesh (required; relative to the manifest),\n"
      "output (default <mesh name>.mp4), and every option marked as a column in docs/OPTIONS.md (up, preset,\n"
      "path, frames, seconds, width, height, fps, spp, crf, ...; named as the option without '--').\n"
      "The options below apply to every item; the manifest's columns override them. A bad item is\n"
      "reported and skipped; items whose video exists are skipped, so a re-run does only what is\n"
      "missing. Prints a summary table and writes DIR/batch-summary.json.\n"
      "Exit code 5 when some items failed (the others are done), 0 when none did.\n"
      "Example CSV:\n  mesh,up,output,preset\n  bunny.ply,y,bunny.mp4,studio\n  dragon.stl,z,,plain");
  cmd->add_option("manifest", args->manifest, "Manifest: .csv with a header row, or .json")->required()->check(CLI::ExistingFile);
  add_scene_options(*cmd, args->defaults, options::batch,
                    {{"threads", options::to(args->threads)},
                     {"web", options::to(args->web)},
                     {"page-only", options::to(args->page_only)},
                     {"out-dir", options::to(args->out_dir)},
                     {"item", options::to(args->item)},
                     {"progress", options::to(args->progress, parse_progress_mode)},
                     {"quiet", options::to(args->quiet)}},
                    /*with_input=*/false);
  cmd->callback([args] { run_batch(*args); });
}

}  // namespace meshtour::cli
