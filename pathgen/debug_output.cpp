#include "pathgen/debug_output.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/error.h"
#include "pathgen/path_file.h"

namespace meshtour {
namespace {

template <typename T>
void put(std::ostream& out, T value) {
  // PLY binary_little_endian: the hosts we build for are little-endian, so the bytes go as is.
  static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

void check_stream(const std::ofstream& out, const std::filesystem::path& file) {
  if (!out) throw IoError("cannot write " + file.string() + ": " + std::strerror(errno));
}

std::vector<Eigen::Vector3d> model_positions(const PaperPathResult& r) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(r.surface.positions.size());
  for (const auto& p : r.surface.positions) out.push_back(r.surface.scale * p + r.surface.offset);
  return out;
}

}  // namespace

FaceColor heat_color(double value, double lo, double hi) {
  double x = hi > lo ? (value - lo) / (hi - lo) : 0.0;
  x = std::clamp(x, 0.0, 1.0);
  // Green → yellow over the first half, yellow → red over the second.
  const double red = std::min(1.0, 2.0 * x);
  const double green = std::min(1.0, 2.0 * (1.0 - x));
  return {static_cast<std::uint8_t>(std::lround(255 * red)), static_cast<std::uint8_t>(std::lround(255 * green)), 0};
}

FaceColor patch_color(int patch_id) {
  if (patch_id < 0) return {0, 0, 0};
  // A 32-bit integer hash (splitmix-style finalizer): neighbouring ids get unrelated colours.
  std::uint32_t h = static_cast<std::uint32_t>(patch_id) * 0x9E3779B9u + 0x7F4A7C15u;
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  h *= 0xC2B2AE35u;
  h ^= h >> 16;
  // Keep every channel above 40 so no patch looks like an orphan (black).
  auto channel = [&](int shift) { return static_cast<std::uint8_t>(40 + ((h >> shift) & 0xFF) * 215 / 255); };
  return {channel(0), channel(8), channel(16)};
}

void write_face_colored_ply(const std::filesystem::path& file, const std::vector<Eigen::Vector3d>& positions,
                            const std::vector<std::array<std::uint32_t, 3>>& triangles,
                            const std::vector<FaceColor>& face_colors) {
  if (face_colors.size() != triangles.size())
    throw IoError("internal: " + std::to_string(face_colors.size()) + " face colours for " +
                  std::to_string(triangles.size()) + " faces in " + file.string());
  write_file_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    check_stream(out, file);
    out << "ply\nformat binary_little_endian 1.0\ncomment meshtour path debug output\n"
        << "element vertex " << positions.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face " << triangles.size() << "\nproperty list uchar int vertex_indices\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    for (const auto& p : positions)
      for (int k = 0; k < 3; ++k) put(out, static_cast<float>(p[k]));
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      put(out, std::uint8_t{3});
      for (std::uint32_t v : triangles[f]) put(out, static_cast<std::int32_t>(v));
      for (std::uint8_t c : face_colors[f]) put(out, c);
    }
    out.flush();
    check_stream(out, file);
  });
}

std::vector<FaceColor> patch_colors(const PaperPathResult& r) {
  std::vector<FaceColor> colors(r.surface.triangles.size(), FaceColor{0, 0, 0});
  for (std::size_t f = 0; f < r.surface.face_patch.size() && f < colors.size(); ++f)
    colors[f] = patch_color(r.surface.face_patch[f]);
  return colors;
}

std::vector<FaceColor> face_weight_colors(const PaperPathResult& r) {
  const auto& w = r.surface.face_weight;
  const auto [lo, hi] = std::minmax_element(w.begin(), w.end());
  std::vector<FaceColor> colors;
  colors.reserve(w.size());
  for (double x : w) colors.push_back(heat_color(x, *lo, *hi));
  return colors;
}

std::vector<FaceColor> cell_weight_colors(const PaperPathResult& r) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t c = 0; c < r.grid.weight.size(); ++c)
    if (r.grid.face_count[c] > 0) {
      lo = std::min(lo, r.grid.weight[c]);
      hi = std::max(hi, r.grid.weight[c]);
    }
  std::vector<FaceColor> colors;
  colors.reserve(r.grid.face_cell.size());
  for (int cell : r.grid.face_cell) colors.push_back(heat_color(r.grid.weight[cell], lo, hi));
  return colors;
}

std::vector<std::filesystem::path> write_debug_outputs(const PaperPathResult& r, const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw IoError("cannot create the debug folder " + dir.string() + ": " + (ec ? ec.message() : "not a folder"));
  std::vector<std::filesystem::path> written;
  try {
    const auto positions = model_positions(r);
    const auto& triangles = r.surface.triangles;
    auto colored = [&](const char* name, const std::vector<FaceColor>& colors) {
      write_face_colored_ply(dir / name, positions, triangles, colors);
      written.push_back(dir / name);  // only files completed by this call are listed (and undone)
    };
    colored("patches.ply", patch_colors(r));
    colored("face_weights.ply", face_weight_colors(r));
    colored("cell_weights.ply", cell_weight_colors(r));

    const std::filesystem::path csv_file = dir / "samples.csv";
    const PaperCameraPath path = r.camera_path();
    const PaperPathGeometry& g = path.geometry();
    std::ostringstream csv;
    csv << std::setprecision(17);
    csv << "k,t,U,U_g,U_p,V,eye_x,eye_y,eye_z,target_x,target_y,target_z\n";
    const int K = r.options.samples;
    for (int k = 0; k < K; ++k) {
      const double frame_t = static_cast<double>(k) / K;
      double t = g.start_parameter + frame_t;
      t -= std::floor(t);
      const CameraPose pose = path.pose(frame_t);
      csv << k << ',' << t << ',' << g.base_height(t) << ',' << g.gaze_height(t) << ',' << g.position_height(t)
          << ',' << g.angle(t) << ',' << pose.eye.x() << ',' << pose.eye.y() << ',' << pose.eye.z() << ','
          << pose.target.x() << ',' << pose.target.y() << ',' << pose.target.z() << '\n';
    }
    const std::string text = csv.str();
    write_file_atomically(csv_file, [&](const std::filesystem::path& temporary) {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      check_stream(out, csv_file);
      out << text;
      out.flush();
      check_stream(out, csv_file);
    });
    written.push_back(csv_file);
  } catch (...) {
    // No partial debug set: remove what this call already wrote.
    for (const auto& f : written) std::filesystem::remove(f, ec);
    throw;
  }
  return written;
}

}  // namespace meshtour
