#pragma once
// The debug outputs of §14: the smoothed mesh with per-face colours (patch id, face weight w(f),
// cell weight W) as binary PLY, and the sampled curves as CSV. They make a wrong interpretation
// visible at a glance in any mesh viewer.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "pathgen/paper_path.h"

namespace meshtour {

using FaceColor = std::array<std::uint8_t, 3>;

/// Binary little-endian PLY with float vertex positions and uchar face colours (red, green,
/// blue), written atomically. \throw IoError if the file cannot be written.
void write_face_colored_ply(const std::filesystem::path& file, const std::vector<Eigen::Vector3d>& positions,
                            const std::vector<std::array<std::uint32_t, 3>>& triangles,
                            const std::vector<FaceColor>& face_colors);

/// Green (lo) → yellow → red (hi); values outside [lo, hi] are clamped.
FaceColor heat_color(double value, double lo, double hi);

/// A distinct pseudo-random colour for each patch id (stable across runs), black for orphans (-1).
FaceColor patch_color(int patch_id);

/// Per-face colourings of a result, §14: by patch, by w(f), by the W of the face's cell.
std::vector<FaceColor> patch_colors(const PaperPathResult& result);
std::vector<FaceColor> face_weight_colors(const PaperPathResult& result);
std::vector<FaceColor> cell_weight_colors(const PaperPathResult& result);

/// Writes patches.ply, face_weights.ply, cell_weights.ply (the smoothed mesh in model units)
/// and samples.csv (k, t, U, U_g, U_p, V, eye and target in model units, for K = samples
/// frames) into `dir`, creating it if needed. Returns the files written.
/// \throw IoError if a file cannot be written.
std::vector<std::filesystem::path> write_debug_outputs(const PaperPathResult& result, const std::filesystem::path& dir);

}  // namespace meshtour
