// The format table (mesh/mesh_formats.h): every extension maps to exactly one row with a check and
// a reader, check_mesh_file and load_mesh choose from it alike, and help lists every row.
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <functional>
#include <set>
#include <string>

#include "helpers.h"
#include "mesh/mesh.h"
#include "mesh/mesh_formats.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(MeshFormats, EveryExtensionHasExactlyOneRowWithACheckAndAReader) {
  std::set<std::string> seen;
  for (const mesh_formats::MeshFormat& format : mesh_formats::all()) {
    const std::string ext(format.extension);
    EXPECT_TRUE(seen.insert(ext).second) << ext << " has two rows";
    ASSERT_GE(ext.size(), 2u);
    EXPECT_EQ(ext.front(), '.');
    for (const char c : ext) EXPECT_FALSE(std::isupper(static_cast<unsigned char>(c))) << ext;
    EXPECT_NE(format.check, nullptr) << ext;
    EXPECT_NE(format.read, nullptr) << ext;
    EXPECT_EQ(mesh_formats::find(ext), &format);
    // Any case finds the same row ("model.PLY").
    std::string upper = ext;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_EQ(mesh_formats::find(upper), &format);
    // Help lists it, as the row says.
    EXPECT_NE(supported_mesh_formats().find(std::string(format.help)), std::string::npos) << ext;
  }
  EXPECT_EQ(seen, (std::set<std::string>{".obj", ".ply", ".off", ".stl", ".gltf", ".glb"}));
  EXPECT_EQ(supported_mesh_formats(), "obj, ply (ascii or binary), off, stl, gltf, glb");
  EXPECT_EQ(mesh_formats::find(".3ds"), nullptr);
  EXPECT_EQ(mesh_formats::find(""), nullptr);
}

TEST(MeshFormats, CheckAndLoadReadTheSameRow) {
  // One small triangle pair per text format: the check's counts match the loaded model's.
  const fs::path dir = test::scratch_dir();
  const std::pair<const char*, const char*> files[] = {
      {"quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"},
      {"quad.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"},
      {"quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"},
  };
  for (const auto& [name, text] : files) {
    const fs::path file = dir / name;
    std::ofstream(file) << text;
    const MeshFileSummary summary = check_mesh_file(file);
    EXPECT_EQ(summary.vertices, 4u) << name;
    EXPECT_EQ(summary.faces, 1u) << name;
    EXPECT_EQ(summary.triangles(), 2u) << name;
    LoadReport report;
    const TriangleMesh mesh = load_mesh(file, &report);
    EXPECT_EQ(mesh.vertex_count(), 4u) << name;
    EXPECT_EQ(mesh.face_count(), 2u) << name;
    EXPECT_EQ(report.polygons_triangulated, 1u) << name;
  }
}

TEST(MeshFormats, CheckAndLoadRefuseAlike) {
  const fs::path dir = test::scratch_dir();
  const fs::path unknown = dir / "model.3ds", empty = dir / "empty.stl", missing = dir / "missing.obj";
  std::ofstream(unknown) << "not a mesh";
  std::ofstream{empty};
  for (const fs::path& file : {unknown, empty, missing, dir}) {
    const std::string checked = message_of([&] { check_mesh_file(file); });
    EXPECT_EQ(message_of([&] { load_mesh(file); }), checked);
    EXPECT_NE(checked.find(file.string()), std::string::npos) << checked;
  }
  EXPECT_NE(message_of([&] { check_mesh_file(unknown); }).find("unknown mesh format '.3ds' (supported: obj, ply"), std::string::npos);
  EXPECT_NE(message_of([&] { load_mesh(empty); }).find("file is empty"), std::string::npos);
}

}  // namespace
}  // namespace meshtour
