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
#include "cli/video_settings.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "options/batch_manifest.h"

namespace meshtour::cli {
namespace {

struct BatchArgs {
  SceneArgs defaults;  // the tour's settings for every item; the manifest's columns override them
  BatchJob job;
};

std::string value_or(const options::Values& values, const std::string& id, const std::string& fallback) {
  const auto it = values.find(id);
  return it == values.end() ? fallback : it->second;
}

// The batch's command-line values with the item's columns on top; a column replaces the option
// it excludes too (an item's "seconds" wins over a --frames given for the whole batch).
SceneArgs item_scene_args(const SceneArgs& defaults, const BatchItem& item) {
  SceneArgs a = defaults;
  a.input = item.mesh.string();
  for (const auto& [id, text] : item.values) {
    const options::Option& o = options::option(id);
    std::erase_if(a.values, [&o](const auto& value) { return o.excludes_option(value.first); });
    a.values[id] = text;
  }
  return a;
}

// The manifest's items with their settings resolved, each parsed once here: the scene, the poster
// and the caption. An item whose settings are bad keeps why, and fails when it runs (the others
// do not stop); with --item only that item is resolved.
std::vector<BatchEntry> batch_entries(const std::vector<BatchItem>& items, const SceneArgs& defaults, std::optional<int> only) {
  std::vector<BatchEntry> entries;
  for (const BatchItem& item : items) {
    BatchEntry e;
    e.index = item.index;
    e.line = item.line;
    e.mesh = item.mesh;
    e.output = item.output;
    e.error = item.error;
    e.poster = value_or(item.values, "poster", std::filesystem::path(item.output).stem().string() + ".poster.png");
    e.caption = value_or(item.values, "caption", value_or(defaults.values, "caption", ""));
    if (item.error.empty() && (!only || *only == item.index)) {
      try {
        const SceneArgs scene_args = item_scene_args(defaults, item);
        e.scene = resolve_scene(scene_args);
        e.poster_job = poster_job(scene_args.values);
        // A batch-wide caption style applies to the items that have a caption and is no error for the others.
        options::Values caption_values = scene_args.values;
        if (!caption_values.contains("caption"))
          for (const char* id : {"caption-position", "caption-size", "font"}) caption_values.erase(id);
        e.caption_args = caption_args(caption_values, e.scene->title);
        if (e.caption.empty() && e.caption_args.caption) e.caption = e.caption_args.caption->text;
      } catch (const std::exception&) {
        e.scene.reset();
        e.settings_failure = std::current_exception();
      }
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

}  // namespace

void add_batch_command(CLI::App& app) {
  auto args = std::make_shared<BatchArgs>();
  BatchJob& job = args->job;
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
  cmd->add_option("manifest", job.manifest, "Manifest: .csv with a header row, or .json")->required()->check(CLI::ExistingFile);
  add_scene_options(*cmd, args->defaults, options::batch,
                    {{"threads", options::to(job.threads)},
                     {"max-memory", options::to(job.resources.max_memory)},
                     {"web", options::to(job.web)},
                     {"page-only", options::to(job.page_only)},
                     {"out-dir", options::to(job.out_dir)},
                     {"item", options::to(job.item)},
                     {"progress", options::to(job.progress, parse_progress_mode)},
                     {"quiet", options::to(job.quiet)}},
                    /*with_input=*/false);
  cmd->callback([args] {
    // The contact sheet alone needs no manifest: it is made from the summaries in --out-dir.
    if (!args->job.page_only)
      args->job.items = batch_entries(read_batch_manifest(args->job.manifest), args->defaults, args->job.item);
    run_batch(args->job);
  });
}

}  // namespace meshtour::cli
