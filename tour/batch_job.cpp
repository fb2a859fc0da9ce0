#include "tour/batch_job.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <stdexcept>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_lock.h"
#include "core/interrupt.h"
#include "tour/mesh_warnings.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "tour/contact_sheet.h"
#include "tour/progress.h"

namespace meshtour {
namespace {

struct ItemResult {
  const BatchEntry* item = nullptr;
  std::string status;  // "rendered", "skipped" (video already there) or "failed"
  double seconds = 0.0;
  std::string error;
  std::optional<ExitClass> exit_class;  // of a failed item: what `tour` would exit with
  double peak_resident_bytes = 0;       // this process's peak so far, after the item
  // Beside the video in --out-dir ("" = not made): the poster, and with --web the WebM and glTF camera.
  std::string poster, webm, gltf, caption;
  long long faces = -1;
  double duration = -1;
};

// Removes what a killed run (SIGKILL, a dead node) left of the item's outputs: the hidden
// temporaries `.<name>.partial-<pid>...` of core/atomic_file.h. Called with the item's lock held,
// so no live writer of this item can own one.
void remove_stale_temporaries(const std::filesystem::path& dir, const std::vector<std::string>& names) {
  std::vector<std::string> prefixes;
  for (const std::string& name : names) {
    if (name.empty()) continue;
    std::string prefix = ".";  // piece by piece: "." + name + ... trips a GCC 12 -Wrestrict false positive
    prefix += name;
    prefix += ".partial-";
    prefixes.push_back(std::move(prefix));
  }
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string file = entry.path().filename().string();
    for (const std::string& prefix : prefixes)
      if (file.starts_with(prefix)) {
        std::error_code ignored;
        std::filesystem::remove(entry.path(), ignored);
      }
  }
}

// Writes one of the job's shared files (a summary, the page) under its lock, after removing what a
// killed run left of it: two runs on one folder each write a whole file, one after the other.
template <class Write>
void write_locked(const std::filesystem::path& dir, const std::string& name, Write&& write) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return write();  // it fails there, with its own message
  FolderLock lock(dir, name);
  lock.lock();
  remove_stale_temporaries(dir, {name});
  write();
}

// Makes the item, whose lock the caller holds.
ItemResult run_item(const BatchJob& args, const BatchEntry& item) {
  ItemResult r;
  r.item = &item;
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path dir(args.out_dir);
  const std::filesystem::path video = dir / item.output;
  const std::string stem = std::filesystem::path(item.output).stem().string();
  r.poster = item.poster;
  r.caption = item.caption;
  if (args.web) r.webm = stem + ".webm", r.gltf = stem + ".gltf";
  // The glTF camera's buffer is the .gltf's name with .bin (pathgen/camera_export.h).
  const std::string gltf_buffer = r.gltf.empty() ? "" : std::filesystem::path(r.gltf).replace_extension(".bin").string();
  if (item.error.empty()) remove_stale_temporaries(dir, {item.output, r.poster, r.webm, r.gltf, gltf_buffer});
  std::error_code ec;
  const auto exists = [&](const std::string& name) { return name.empty() || std::filesystem::is_regular_file(dir / name, ec); };
  if (item.error.empty() && exists(item.output) && exists(r.poster) && exists(r.webm) && exists(r.gltf)) {
    r.status = "skipped";
    return r;
  }
  try {
    if (!item.error.empty()) throw InputError(item.error);
    if (!args.quiet) std::fprintf(stderr, "== item %d: %s -> %s\n", item.index, item.mesh.string().c_str(), video.string().c_str());
    if (item.settings_failure) std::rethrow_exception(item.settings_failure);
    if (!item.scene) throw std::logic_error("batch item " + std::to_string(item.index) + " was not resolved");
    TourVideoJob job;
    job.output = video;
    job.poster = item.poster_job;
    job.poster.file = dir / r.poster;
    job.caption = item.caption_args;
    if (args.web) job.webm = dir / r.webm, job.gltf = dir / r.gltf;
    job.threads = args.threads;
    job.resources = args.resources;
    job.progress = args.quiet ? ProgressMode::none : args.progress;
    job.quiet = args.quiet;
    const TourVideoResult made = render_tour_video(*item.scene, job);
    r.faces = static_cast<long long>(made.faces);
    r.duration = made.seconds();
    r.status = "rendered";
  } catch (const Interrupted&) {
    throw;  // Ctrl-C stops the whole batch
  } catch (const std::exception& e) {
    r.status = "failed";
    r.error = e.what();
    r.exit_class = exit_class_of(e);
    std::fprintf(stderr, "meshtour batch: item %d (%s, line %d) failed: %s\n", item.index, item.mesh.string().c_str(), item.line,
                 e.what());
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.peak_resident_bytes = resident_memory().peak;
  return r;
}

void write_summary(const BatchJob& args, const std::vector<ItemResult>& results, const std::filesystem::path& file) {
  nlohmann::ordered_json j;
  j["manifest"] = std::filesystem::absolute(args.manifest).string();
  j["out_dir"] = std::filesystem::absolute(args.out_dir).string();
  int counts[3] = {0, 0, 0};
  nlohmann::ordered_json items = nlohmann::json::array();
  for (const auto& r : results) {
    nlohmann::ordered_json i;
    i["index"] = r.item->index;
    i["line"] = r.item->line;
    i["mesh"] = r.item->mesh.string();
    i["output"] = r.item->output;
    i["status"] = r.status;
    i["seconds"] = r.seconds;
    if (!r.error.empty()) i["error"] = r.error;
    if (r.exit_class) {
      i["exit_class"] = r.exit_class->name;
      i["exit_code"] = r.exit_class->code;
    }
    if (!r.caption.empty()) i["caption"] = r.caption;
    if (r.status != "failed") {
      i["poster"] = r.poster;
      if (!r.webm.empty()) i["webm"] = r.webm;
      if (!r.gltf.empty()) i["gltf"] = r.gltf;
    }
    if (r.faces >= 0) i["faces"] = r.faces;
    if (r.duration >= 0) i["duration"] = r.duration;
    if (r.peak_resident_bytes > 0) i["peak_resident_bytes"] = static_cast<long long>(r.peak_resident_bytes);
    items.push_back(std::move(i));
    counts[r.status == "rendered" ? 0 : r.status == "skipped" ? 1 : 2]++;
  }
  j["rendered"] = counts[0];
  j["skipped"] = counts[1];
  j["failed"] = counts[2];
  j["items"] = std::move(items);
  const std::string text = j.dump(2) + "\n";
  write_text_file_atomically(file, text, "batch summary");
}

void print_table(const std::vector<ItemResult>& results) {
  std::printf("%-5s %-9s %8s  %-28s %s\n", "item", "status", "seconds", "output", "mesh / error");
  int failed = 0, rendered = 0, skipped = 0;
  for (const auto& r : results) {
    std::printf("%-5d %-9s %8.1f  %-28s %s\n", r.item->index, r.status == "failed" ? "FAILED" : r.status.c_str(), r.seconds,
                r.item->output.c_str(), r.error.empty() ? r.item->mesh.string().c_str() : r.error.c_str());
    failed += r.status == "failed";
    rendered += r.status == "rendered";
    skipped += r.status == "skipped";
  }
  std::printf("%zu items: %d rendered, %d skipped (video already there), %d failed\n", results.size(), rendered, skipped, failed);
  std::fflush(stdout);
}

}  // namespace

void run_batch(const BatchJob& args) {
  install_interrupt_handlers();
  if (args.page_only) {
    // The last job of a farm's batch: the page from the array tasks' summaries.
    report_stage(args.quiet ? ProgressMode::none : args.progress, "page");
    write_locked(args.out_dir, "index.html", [&] {
      const std::filesystem::path page = write_contact_sheet(args.out_dir);
      if (!args.quiet) std::fprintf(stderr, "wrote %s\n", page.string().c_str());
    });
    return;
  }
  const std::vector<BatchEntry>& items = args.items;
  if (args.item && (*args.item < 0 || *args.item >= static_cast<int>(items.size())))
    throw InputError("--item " + std::to_string(*args.item) + ": the manifest has items 0.." + std::to_string(items.size() - 1));
  std::error_code ec;
  std::filesystem::create_directories(args.out_dir, ec);
  if (ec) throw IoError(args.out_dir + ": cannot create the output directory: " + ec.message());

  // Each item is made under its lock in the output folder, so that two runs of the job on one
  // folder (two operators, a re-submitted farm array) never make an item twice: an item another run
  // is making is left for the end, then waited for, and found done.
  std::vector<ItemResult> results;
  std::vector<const BatchEntry*> busy;
  for (const auto& item : items) {
    if (args.item && item.index != *args.item) continue;
    if (!item.error.empty()) {
      results.push_back(run_item(args, item));
      continue;
    }
    FolderLock lock(args.out_dir, item.output);
    if (lock.try_lock())
      results.push_back(run_item(args, item));
    else
      busy.push_back(&item);
  }
  for (const BatchEntry* item : busy) {
    if (!args.quiet) std::fprintf(stderr, "== item %d: %s is being made by another run; waiting for it\n", item->index, item->output.c_str());
    FolderLock lock(args.out_dir, item->output);
    lock.lock();
    results.push_back(run_item(args, *item));
  }
  std::sort(results.begin(), results.end(), [](const ItemResult& a, const ItemResult& b) { return a.item->index < b.item->index; });
  print_table(results);
  // One summary per farm task (--item), so that concurrent tasks never write the same file.
  const std::string name = args.item ? "batch-summary-" + std::to_string(*args.item) + ".json" : "batch-summary.json";
  write_locked(args.out_dir, name, [&] { write_summary(args, results, std::filesystem::path(args.out_dir) / name); });
  // One farm task (--item) knows only its own item: the farm's last job writes the page.
  if (args.web && !args.item) {
    report_stage(args.quiet ? ProgressMode::none : args.progress, "page");
    write_locked(args.out_dir, "index.html", [&] {
      const std::filesystem::path page = write_contact_sheet(args.out_dir);
      if (!args.quiet) std::fprintf(stderr, "wrote %s\n", page.string().c_str());
    });
  }
  for (const auto& r : results)
    if (r.status == "failed") throw SomeItemsFailed();
}

}  // namespace meshtour
