#pragma once
// The frames directory: what `meshtour render` writes and `meshtour encode` reads. Frames are
// named frame_000123.<ext>; a manifest beside them (meshtour-frames.json) records the tour they
// belong to, so that the encoder knows the whole frame range and every process that renders a
// chunk into the directory can check it renders the same tour.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace meshtour {

/// The manifest's file name inside a frames directory.
inline constexpr std::string_view kFrameDirManifestName = "meshtour-frames.json";
/// Version of the manifest's layout; read_frame_dir_info() rejects newer ones.
inline constexpr int kFrameDirFormatVersion = 1;

/// What a frames directory holds: one tour's frames.
struct FrameDirInfo {
  int frame_count = 0;                     ///< frames in the whole tour (0 .. frame_count-1)
  int fps = 30;                            ///< the tour's frame rate
  int width = 0, height = 0;               ///< pixels
  std::vector<std::string> image_formats;  ///< extensions written for every frame: "png", "exr"
  std::string source;                      ///< the mesh or scene the tour was made from (informative)
  std::string path_file;                   ///< absolute path of the camera path file rendered, if any
  /// Whether the frames are denoised (--denoise): PNGs show the denoised frame, EXRs carry it as
  /// the `denoised` layer beside the raw one. Manifests of meshtour before the denoiser: false.
  bool denoise = false;
  /// The score of each frame's view alone (pathgen/coverage.h's objective), when the path search
  /// measured them (the feature orbit does), and the frame with the highest: the thumbnail or
  /// poster frame. Informative; empty and -1 when not measured.
  std::vector<double> view_scores;
  int best_view_frame = -1;

  /// Same tour (frame count, rate, size, formats, denoising)? Source and path file are informative only.
  bool same_tour(const FrameDirInfo& other) const;
};

/// `dir`/frame_000123.<extension> (six digits at least; more for tours over a million frames).
std::filesystem::path frame_file(const std::filesystem::path& dir, int frame, std::string_view extension);

/// Writes the manifest into `dir` atomically (concurrent writers of the same content are safe).
/// \throw IoError if it cannot be written.
void write_frame_dir_info(const std::filesystem::path& dir, const FrameDirInfo& info);

/// Whether `dir` has a manifest.
bool has_frame_dir_info(const std::filesystem::path& dir);

/// Reads the manifest of `dir`.
/// \throw InputError if it is missing (naming the directory and what writes it), malformed, or
///        from a newer meshtour; IoError if it cannot be read.
FrameDirInfo read_frame_dir_info(const std::filesystem::path& dir);

/// Makes `dir` ready to receive frames of the tour `info`: creates it, writes the manifest when
/// there is none, and refuses a directory whose manifest describes another tour (so that two
/// tours never mix their frames in one directory).
/// \throw InputError if the manifest describes another tour (or is damaged), IoError if the
///        directory or the manifest cannot be written.
void prepare_frame_dir(const std::filesystem::path& dir, const FrameDirInfo& info);

/// The frames of `frames` whose file `frame_file(dir, k, extension)` does not exist.
std::vector<int> missing_frames(const std::filesystem::path& dir, const std::vector<int>& frames,
                                std::string_view extension);

}  // namespace meshtour
