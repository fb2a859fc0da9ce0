#include "jobs/frame_dir.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_reader.h"

namespace meshtour {

bool FrameDirInfo::same_tour(const FrameDirInfo& other) const {
  return frame_count == other.frame_count && fps == other.fps && width == other.width && height == other.height &&
         image_formats == other.image_formats && denoise == other.denoise;
}

std::filesystem::path frame_file(const std::filesystem::path& dir, int frame, std::string_view extension) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06d.", frame);
  std::string file = name;
  file += extension;
  return dir / file;
}

void write_frame_dir_info(const std::filesystem::path& dir, const FrameDirInfo& info) {
  nlohmann::ordered_json j;
  j["format"] = "meshtour-frames";
  j["version"] = kFrameDirFormatVersion;
  j["frame_count"] = info.frame_count;
  j["fps"] = info.fps;
  j["width"] = info.width;
  j["height"] = info.height;
  j["image_formats"] = info.image_formats;
  j["denoise"] = info.denoise;
  j["source"] = info.source;
  j["path_file"] = info.path_file;
  if (!info.view_scores.empty()) {
    j["view_scores"] = info.view_scores;
    j["best_view_frame"] = info.best_view_frame;
  }
  const std::string text = j.dump(2) + "\n";
  const std::filesystem::path file = dir / kFrameDirManifestName;
  write_text_file_atomically(file, text, "frames manifest");
}

bool has_frame_dir_info(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_regular_file(dir / kFrameDirManifestName, ec);
}

FrameDirInfo read_frame_dir_info(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / kFrameDirManifestName;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw InputError(dir.string() + ": no such frames directory");
  if (!std::filesystem::exists(file, ec))
    throw InputError(dir.string() + ": no " + std::string(kFrameDirManifestName) +
                     " (it is written by 'meshtour render --out-dir'); give the tour's frames with --frames instead");
  const std::string text = read_json_file_text(file, "frames manifest");
  const auto fail = [&](const std::string& why) -> InputError { return InputError(file.string() + ": " + why); };
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) throw fail("not a JSON object (the manifest is damaged; re-run 'meshtour render')");
  // Keys this version does not know are left alone: a newer meshtour may add some.
  JsonReader r(j, file.string(), "", " (the manifest is damaged; re-run 'meshtour render')");
  std::string format;
  r.read("format", format);
  if (format != "meshtour-frames") throw fail("not a meshtour frames manifest");
  const int version = r.integer("version", 1, 1'000'000);
  if (version > kFrameDirFormatVersion)
    throw fail("written by a newer meshtour (manifest version " + std::to_string(version) + ", this one reads " +
               std::to_string(kFrameDirFormatVersion) + "); encode with that version");
  FrameDirInfo info;
  info.frame_count = r.integer("frame_count", 1, 1'000'000'000);
  info.fps = r.integer("fps", 1, 1000);
  info.width = r.integer("width", 1, 1 << 16);
  info.height = r.integer("height", 1, 1 << 16);
  info.image_formats = r.strings("image_formats");
  if (info.image_formats.empty()) r.fail_key("image_formats", "is empty");
  for (const auto& f : info.image_formats)
    if (f != "png" && f != "exr") r.fail_key("image_formats", "may hold only \"png\" and \"exr\"");
  r.read("denoise", info.denoise);
  r.read("source", info.source);
  r.read("path_file", info.path_file);
  if (j.contains("view_scores")) {
    const nlohmann::json& scores = j["view_scores"];
    if (!scores.is_array() || static_cast<int>(scores.size()) != info.frame_count)
      r.fail_key("view_scores", "must be an array of one number per frame");
    for (const auto& v : scores) {
      if (!v.is_number()) r.fail_key("view_scores", "must hold numbers");
      info.view_scores.push_back(v.get<double>());
    }
    info.best_view_frame = r.integer("best_view_frame", 0, info.frame_count - 1);
  }
  return info;
}

namespace {
std::string describe(const FrameDirInfo& i) {
  std::string formats;
  for (const auto& f : i.image_formats) formats += (formats.empty() ? "" : "+") + f;
  return std::to_string(i.frame_count) + " frames of " + std::to_string(i.width) + "x" + std::to_string(i.height) + " at " +
         std::to_string(i.fps) + " fps as " + formats + (i.denoise ? ", denoised" : "");
}
}  // namespace

void prepare_frame_dir(const std::filesystem::path& dir, const FrameDirInfo& info) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw IoError(dir.string() + ": cannot create the frames directory: " + ec.message());
  if (has_frame_dir_info(dir)) {
    const FrameDirInfo existing = read_frame_dir_info(dir);
    if (!existing.same_tour(info))
      throw InputError(dir.string() + " holds another tour (" + describe(existing) + "; this one is " + describe(info) +
                       "); use another --out-dir, or delete the directory's frames and " + std::string(kFrameDirManifestName));
    return;
  }
  write_frame_dir_info(dir, info);
}

std::vector<int> missing_frames(const std::filesystem::path& dir, const std::vector<int>& frames,
                                std::string_view extension) {
  std::vector<int> missing;
  for (const int k : frames) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(frame_file(dir, k, extension), ec)) missing.push_back(k);
  }
  return missing;
}

}  // namespace meshtour
