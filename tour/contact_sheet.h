#pragma once
// The contact sheet of a batch (`batch --web`, and the last job of `farm slurm --manifest --web`):
// one index.html in the output folder, a grid of the items' posters with caption, face count,
// duration and status (done, or failed with its error line); each poster plays its video (H.264
// MP4 and VP9 WebM sources, muted, preload=none) on hover or click; links to the videos, posters,
// glTF cameras and the summary JSON. One file, inline CSS and a few lines of script, no network,
// relative links only: the folder can be copied anywhere. Made from the batch summaries, so the
// page of a farm's batch (one summary per array task) is the same as a single run's.
#include <filesystem>
#include <string>
#include <vector>

namespace meshtour {

/// One item of the sheet: file names are relative to the output folder ("" = none).
struct SheetItem {
  int index = 0;
  std::string name;  ///< the mesh's file name
  std::string caption, status, error;
  std::string exit_class;  ///< of a failed item: input, io, runtime or unexpected ("" = not given)
  std::string video, webm, poster, gltf;
  long long faces = -1;  ///< -1 = unknown (failed or skipped items)
  double seconds = -1;   ///< video length; -1 = unknown
};

/// The page's HTML (deterministic: the same items give the same bytes).
std::string contact_sheet_html(const std::string& title, const std::vector<SheetItem>& items,
                               const std::vector<std::string>& summary_files);

/// Reads every batch summary in `out_dir` (batch-summary.json, else batch-summary-<item>.json)
/// and writes `out_dir`/index.html atomically. \throw InputError when there is no summary.
/// Returns the page's path.
std::filesystem::path write_contact_sheet(const std::filesystem::path& out_dir);

}  // namespace meshtour
