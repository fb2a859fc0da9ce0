// Loader tests: every supported format, colours, triangulation, and the errors users meet.
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "mesh/mesh.h"

namespace meshtour {
namespace {

std::filesystem::path write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

TEST(MeshLoader, ObjQuadIsTriangulated) {
  const auto dir = test::scratch_dir();
  const auto file = write_text(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  LoadReport report;
  const TriangleMesh mesh = load_mesh(file, &report);
  EXPECT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(mesh.face_count(), 2u);
  EXPECT_EQ(report.polygons_triangulated, 1u);
  const Bounds b = mesh.bounds();
  EXPECT_EQ(b.lo, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(b.hi, Eigen::Vector3d(1, 1, 0));
  EXPECT_DOUBLE_EQ(b.diagonal(), std::sqrt(2.0));
  EXPECT_FALSE(mesh.has_colors());
}

// The OBJ reader (mesh/obj_reader.h) keeps the file as it is: vertices in order with their
// colours (white where a line has none) and full double precision, a fin of three faces on one
// edge not split (OpenMesh gave the third face copies of its vertices), negative and '+' indices,
// v//vn corners, CRLF line ends, a last line without an end, comments, and a line longer than its
// 1 MB buffer (one polygon of 200,000 corners).
TEST(MeshLoader, ObjIsReadAsStored) {
  const auto dir = test::scratch_dir();
  const auto file = write_text(dir / "fin.obj",
                               "# a fin\r\nv 0 0 0 1 0 0\r\nv 1 0 0\r\n  v 0.5 1 0.1000000000000001 0 0.5 1\r\nv 0.5 -1 0\r\nv 0.5 0 1\r\n"
                               "vn 0 0 1\r\nf 1 2 3\r\nf -4//1 -5//1 -1//1\r\nf +1 +2 +4\r\nf 1 2 3 5");
  LoadReport report;
  const TriangleMesh mesh = load_mesh(file, &report);
  ASSERT_EQ(mesh.positions.size(), 5u);
  EXPECT_EQ(mesh.positions[2], Eigen::Vector3d(0.5, 1, 0.1000000000000001));  // not rounded to float
  const std::vector<std::array<std::uint32_t, 3>> expected = {{0, 1, 2}, {1, 0, 4}, {0, 1, 3}, {0, 1, 2}, {0, 2, 4}};
  EXPECT_EQ(mesh.triangles, expected);
  EXPECT_EQ(report.polygons_triangulated, 1u);
  ASSERT_TRUE(mesh.has_colors());
  EXPECT_EQ(mesh.colors[0], Eigen::Vector3f(1, 0, 0));
  EXPECT_EQ(mesh.colors[1], Eigen::Vector3f(1, 1, 1));
  EXPECT_EQ(mesh.colors[2], Eigen::Vector3f(0, 0.5f, 1));

  // Numbers as strtod reads them: "-1.5e0" and "+2" are numbers, "+-1" is not.
  const TriangleMesh signs = load_mesh(write_text(dir / "signs.obj", "v -1.5e0 +2 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_EQ(signs.positions[0], Eigen::Vector3d(-1.5, 2, 0));
  EXPECT_THROW(load_mesh(write_text(dir / "sign_sign.obj", "v +-1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")), InputError);

  // One polygon of 200,000 corners on a circle: a 1.4 MB line, fan-triangulated.
  const int n = 200000;
  std::ostringstream big;
  for (int i = 0; i < n; ++i) big << "v " << std::cos(i * 2 * EIGEN_PI / n) << " " << std::sin(i * 2 * EIGEN_PI / n) << " 0\n";
  big << "f";
  for (int i = 1; i <= n; ++i) big << " " << i;
  LoadReport disc_report;
  const TriangleMesh disc = load_mesh(write_text(dir / "disc.obj", big.str() + "\n"), &disc_report);
  ASSERT_EQ(disc.triangles.size(), static_cast<std::size_t>(n - 2));
  EXPECT_EQ(disc.triangles.back(), (std::array<std::uint32_t, 3>{0, n - 2, n - 1}));
  EXPECT_EQ(disc_report.polygons_triangulated, 1u);
}

// Every corner of every triangle of a fan-triangulated polygon keeps its own texture coordinate.
// The coordinates are chosen = (x, y) of the corner's vertex (scaled and shifted, and listed in
// another order than the vertices), so each corner's UV can be checked against its position.
TEST(MeshLoader, ObjPolygonsKeepEveryCornersUv) {
  const auto dir = test::scratch_dir();
  write_text(dir / "m.mtl", "newmtl m\nmap_Kd tex.png\n");
  std::string obj = "mtllib m.mtl\nusemtl m\n";
  const int sides = 7;
  std::string face = "f", vts;
  for (int k = 0; k < sides; ++k) {
    const double a = 2 * 3.14159265358979 * k / sides;
    obj += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0\n";
  }
  obj += "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n";  // a quad with negative (relative) indices
  // vt listed backwards: vt number k+1 belongs to vertex sides-k.
  for (int k = sides - 1; k >= 0; --k) {
    const double a = 2 * 3.14159265358979 * k / sides;
    obj += "vt " + std::to_string(0.5 + 0.25 * std::cos(a)) + " " + std::to_string(0.5 + 0.25 * std::sin(a)) + "\n";
  }
  for (int k = 0; k < sides; ++k) face.append(" ").append(std::to_string(k + 1)).append("/").append(std::to_string(sides - k));
  obj += "vt 0.5 0.5\nvt 0.75 0.5\nvt 0.5 0.75\nvt 0.75 0.75\n";
  obj += face + "\nf -4/-4 -3/-3 -1/-1 -2/-2\n";
  // tex.png is not written: the UVs are what this test checks.
  const TriangleMesh mesh = load_mesh(write_text(dir / "polygon.obj", obj), nullptr, LoadOptions{.check_textures = false});
  ASSERT_EQ(mesh.face_count(), static_cast<std::size_t>(sides - 2 + 2));
  ASSERT_TRUE(mesh.has_texture());
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = mesh.positions[mesh.triangles[f][c]];
      const Eigen::Vector2f expected(static_cast<float>(0.5 + 0.25 * p.x()), static_cast<float>(0.5 + 0.25 * p.y()));
      EXPECT_NEAR((mesh.corner_uvs[3 * f + c] - expected).norm(), 0.0f, 1e-5f) << "face " << f << " corner " << c;
    }
}

// The STL reader (mesh/stl_reader.h) merges the corners STL repeats per facet into vertices,
// numbered by first appearance: a cube's 12 facets give its 8 corners, as binary (whose header
// begins with "solid", as many writers' do: its exact size or its bytes say binary) and as ASCII with what
// writers vary (upper case, a facet on one line, CRLF, a 4-corner loop, two solids, -0, no final
// endsolid). Faults name the facet or the line.
TEST(MeshLoader, StlCornersAreMergedIntoVertices) {
  const auto dir = test::scratch_dir();
  const std::array<Eigen::Vector3f, 8> corner{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
  const std::array<std::array<int, 4>, 6> quads{{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}}};
  std::vector<std::array<int, 3>> facets;
  for (const auto& q : quads) facets.push_back({q[0], q[1], q[2]}), facets.push_back({q[0], q[2], q[3]});
  const auto binary_stl = [&](const std::vector<std::array<int, 3>>& tris, float poison = 0.0f) {
    std::string bytes = "solid cube (binary)";
    bytes.resize(80, ' ');
    const auto count = static_cast<std::uint32_t>(tris.size());
    bytes.append(reinterpret_cast<const char*>(&count), 4);
    for (std::size_t f = 0; f < tris.size(); ++f) {
      float record[12] = {};
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) record[3 + 3 * c + k] = corner[static_cast<std::size_t>(tris[f][c])][k];
      if (f == 3 && poison != 0.0f) record[7] = poison;
      bytes.append(reinterpret_cast<const char*>(record), sizeof record);
      bytes.append(2, '\0');
    }
    return bytes;
  };
  LoadReport report;
  const TriangleMesh binary = load_mesh(write_text(dir / "cube_binary.stl", binary_stl(facets)), &report);
  EXPECT_EQ(binary.vertex_count(), 8u);
  ASSERT_EQ(binary.face_count(), 12u);
  EXPECT_TRUE(report.warnings.empty());
  // First appearance numbers the vertices: corner 0, 3, 2, 1 of the first facets, then 4...
  EXPECT_EQ(binary.positions[1], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(binary.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  for (std::size_t f = 0; f < facets.size(); ++f)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(binary.positions[binary.triangles[f][c]], corner[static_cast<std::size_t>(facets[f][c])].cast<double>()) << f;

  // Bytes after the facets (some writers pad): binary all the same, though its header says solid.
  const TriangleMesh padded = load_mesh(write_text(dir / "cube_padded.stl", binary_stl(facets) + std::string(100, '\0')), &report);
  EXPECT_EQ(padded.triangles, binary.triangles);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("100 bytes after the 12 facets"), std::string::npos) << report.warnings[0];

  const auto vertex = [&](int v, bool negative_zero = false) {
    std::string line = "  vertex";
    for (int k = 0; k < 3; ++k) {
      const float c = corner[static_cast<std::size_t>(v)][k];
      line += ' ';
      line += c == 0.0f && negative_zero ? std::string("-0") : std::to_string(c);
    }
    return line + "\r\n";
  };
  std::string ascii = "solid cube\r\n";
  ascii += "FACET NORMAL 0 0 -1\r\n OUTER LOOP\r\n" + vertex(0) + vertex(3) + vertex(2) + vertex(1) + " ENDLOOP\r\nENDFACET\r\n";
  for (std::size_t f = 2; f < facets.size(); ++f) {
    if (f == 6) ascii += "endsolid cube\nsolid second part\n";
    ascii += f == 4 ? "facet normal 0 0 0 outer loop" : "facet normal 0 0 0\nouter loop\n";
    for (int c = 0; c < 3; ++c) ascii += vertex(facets[f][c], f == 9);
    ascii += "endloop\nendfacet\n";
  }
  const TriangleMesh text = load_mesh(write_text(dir / "cube_ascii.stl", ascii), &report);
  EXPECT_EQ(text.positions, binary.positions);
  EXPECT_EQ(text.triangles, binary.triangles);
  EXPECT_EQ(report.polygons_triangulated, 1u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("without 'endsolid' after 11 facets"), std::string::npos) << report.warnings[0];
  EXPECT_EQ(check_mesh_file(dir / "cube_ascii.stl").faces, 11u);

  const auto fails = [&](const std::string& file, const std::string& bytes, const std::string& message) {
    try {
      load_mesh(write_text(dir / file, bytes));
      ADD_FAILURE() << file << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  fails("nan.stl", binary_stl(facets, std::numeric_limits<float>::quiet_NaN()), "facet 3 has a NaN or infinite corner");
  const std::string head = "solid bad\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
  fails("short_corner.stl", head + "vertex 1 0\nendloop\n", "line 6: a corner of facet 0 is not a number: 'endloop'");
  fails("two_corners.stl", head + "vertex 1 0 0\nendloop\nendfacet\n", "line 6: facet 0 has 2 corners; a facet needs 3");
  fails("cut.stl", head + "vertex 1 0 0\n", "truncated: the file ends inside facet 0");
  fails("inner.stl", "solid bad\nfacet normal 0 0 1\ninner loop\n", "line 3: expected 'outer' in facet 0, found 'inner'");
  fails("binary_tail.stl", "solid name\n" + std::string("facet \x01\x02", 8), "binary data in an ASCII STL");
  fails("not_stl.stl", "ply\nformat ascii 1.0\n" + std::string(100, ' '), "corrupt binary STL: the header announces");
  fails("misnamed.stl", "s0lid x\nfacet normal 0 0 1\n", "shorter than a binary STL header");
  fails("other_statement.stl", "solid x\nvertex 0 0 0\n", "line 2: expected 'facet' or 'endsolid', found 'vertex'");
}

// An OBJ copied without its MTL file: an error naming the library, the OBJ and the way out, as
// for a missing texture; with --missing-textures grey the model loads untextured with a warning;
// commands that do not render (path) do not need it.
TEST(MeshLoader, ObjWithAMissingMaterialLibrary) {
  const auto dir = test::scratch_dir();
  const std::string body = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl skin\nf 1/1 2/2 3/3\n";
  const auto file = write_text(dir / "copied.obj", "mtllib gone.mtl\n" + body);
  try {
    load_mesh(file);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("copied.obj"), std::string::npos) << what;
    EXPECT_NE(what.find("gone.mtl"), std::string::npos) << what;
    EXPECT_NE(what.find("--missing-textures grey"), std::string::npos) << what;
  }
  LoadReport report;
  const TriangleMesh mesh = load_mesh(file, &report, LoadOptions{.missing_textures_grey = true});
  EXPECT_EQ(mesh.face_count(), 1u);
  EXPECT_FALSE(mesh.has_texture());
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("gone.mtl"), std::string::npos) << report.warnings.front();
  EXPECT_NO_THROW(load_mesh(file, nullptr, LoadOptions{.check_textures = false}));
  // Of two libraries on one line the present one still gives its texture; a directory of that
  // name is not a library.
  write_text(dir / "here.mtl", "newmtl skin\nmap_Kd skin.png\n");
  std::filesystem::create_directories(dir / "folder.mtl");
  const auto two = write_text(dir / "two.obj", "mtllib here.mtl folder.mtl\n" + body);
  EXPECT_THROW(load_mesh(two, nullptr), IoError);
  LoadReport two_report;
  const TriangleMesh textured = load_mesh(two, &two_report, LoadOptions{.missing_textures_grey = true, .check_textures = false});
  EXPECT_TRUE(textured.has_texture());
}

// MeshLab's per-vertex texture coordinates (texture_u/texture_v) and the image its header
// comment names, in a binary PLY with a quad (fan-triangulated: every triangle keeps its UVs).
TEST(MeshLoader, PlyVertexTexcoordsAndTextureFileComment) {
  const auto dir = test::scratch_dir();
  std::string ply = "ply\nformat binary_little_endian 1.0\ncomment TextureFile my texture.png\nelement vertex 4\n"
                    "property float x\nproperty float y\nproperty float z\nproperty float texture_u\nproperty float texture_v\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float vertices[4][5] = {{0, 0, 0, 0, 0}, {1, 0, 0, 1, 0}, {1, 1, 0, 1, 1}, {0, 1, 0, 0, 1}};
  ply.append(reinterpret_cast<const char*>(vertices), sizeof vertices);
  const unsigned char count = 4;
  const int indices[4] = {0, 1, 2, 3};
  ply.append(reinterpret_cast<const char*>(&count), 1);
  ply.append(reinterpret_cast<const char*>(indices), sizeof indices);
  const TriangleMesh mesh = load_mesh(write_text(dir / "quad.ply", ply), nullptr, LoadOptions{.check_textures = false});
  ASSERT_EQ(mesh.triangles.size(), 2u);
  ASSERT_EQ(mesh.materials.size(), 1u);
  EXPECT_EQ(mesh.materials[0].texture.file, dir / "my texture.png");
  ASSERT_TRUE(mesh.has_texture());
  for (std::size_t f = 0; f < 2; ++f)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = mesh.positions[mesh.triangles[f][c]];
      EXPECT_NEAR((mesh.corner_uvs[3 * f + c] - p.head<2>().cast<float>()).norm(), 0.0f, 1e-6f);
    }
  // Without the texture file the load fails naming it.
  try {
    load_mesh(dir / "quad.ply");
    FAIL() << "loaded without its texture";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("my texture.png"), std::string::npos) << e.what();
  }
}

// Cyberware and some Stanford scans store triangle strips (element 'tristrips', -1 between
// strips) instead of faces. A unit cube, each face one strip a b d c of its outward counter-
// clockwise quad a b c d, plus a strip with a repeated index (degenerate joins, dropped): 12
// triangles, all outward (signed volume +1), in ASCII and binary. A bad index names the strip.
TEST(MeshLoader, PlyTriangleStrips) {
  const auto dir = test::scratch_dir();
  const double corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  std::vector<int> strip;
  for (const auto& q : quads) {
    for (const int k : {q[0], q[1], q[3], q[2]}) strip.push_back(k);
    strip.push_back(-1);
  }
  for (const int k : {0, 0, 1, 1}) strip.push_back(k);  // only degenerate triangles
  const std::string header_end = "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  std::string ascii = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n" + header_end;
  for (const auto& c : corners) ascii += std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  ascii += std::to_string(strip.size());
  for (const int k : strip) ascii.append(" ").append(std::to_string(k));  // not " " + ...: GCC 12 warns falsely (-Wrestrict)
  ascii += "\n";
  std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n" + header_end;
  const auto put = [&](auto v) { binary.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (const auto& c : corners)
    for (const double x : c) put(static_cast<float>(x));
  put(static_cast<std::int32_t>(strip.size()));
  for (const int k : strip) put(static_cast<std::int32_t>(k));
  for (const auto& [file, text] : {std::pair{"strips_ascii.ply", ascii}, std::pair{"strips_binary.ply", binary}}) {
    SCOPED_TRACE(file);
    LoadReport report;
    const TriangleMesh mesh = load_mesh(write_text(dir / file, text), &report);
    ASSERT_EQ(mesh.face_count(), 12u);
    EXPECT_EQ(mesh.vertex_count(), 8u);
    double volume6 = 0.0;
    for (const auto& t : mesh.triangles) volume6 += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
    EXPECT_NEAR(volume6 / 6.0, 1.0, 1e-12);
    EXPECT_EQ(mesh.bounds().hi, Eigen::Vector3d(1, 1, 1));
  }
  std::string bad = ascii;
  bad.replace(bad.rfind(" 1\n"), 3, " 8\n");  // the last index: past the 8 vertices
  try {
    load_mesh(write_text(dir / "bad_strip.ply", bad));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle strip 0 refers to vertex 8"), std::string::npos) << e.what();
  }
}

TEST(MeshLoader, AsciiPlyKeepsVertexColours) {
  const auto dir = test::scratch_dir();
  const auto file = write_text(dir / "tri.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                               "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                               "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n");
  const TriangleMesh mesh = load_mesh(file);
  ASSERT_TRUE(mesh.has_colors());
  EXPECT_FLOAT_EQ(mesh.colors[0].x(), 1.0f);
  EXPECT_FLOAT_EQ(mesh.colors[1].y(), 1.0f);
  EXPECT_FLOAT_EQ(mesh.colors[2].z(), 1.0f);
  EXPECT_FLOAT_EQ(mesh.colors[0].y(), 0.0f);
}

// meshtour's OFF reader (mesh/off_reader.h): polygons fanned from their first corner, decimal
// colours taken as they are, the vertices as the file lists them (OpenMesh's reader gave a
// non-manifold vertex's faces copies of it: here two triangles meet at one vertex only).
TEST(MeshLoader, OffPolygonsColoursAndSharedVertices) {
  const auto dir = test::scratch_dir();
  write_text(dir / "bowtie.off",
             "COFF\n# two triangles touching at vertex 0, and a quad\n9 3\n0 0 0 0.5 0.25 1 1\n1 0 0 0 0 0 1\n1 1 0 0 0 0 1\n"
             "-1 0 0 0 0 0 1\n-1 -1 0 0 0 0 1\n3 0 0 1 0 0 1\n4 0 1 0 0 0 1\n4 1 1 0 0 0 1\n3 1 1 0 0 0 1\n"
             "3 0 1 2\n3 0 3 4 1 0 0\n4 5 6 7 8\n");
  const TriangleMesh mesh = load_mesh(dir / "bowtie.off");
  EXPECT_EQ(mesh.vertex_count(), 9u);
  const std::vector<std::array<std::uint32_t, 3>> expected = {{0, 1, 2}, {0, 3, 4}, {5, 6, 7}, {5, 7, 8}};
  EXPECT_EQ(mesh.triangles, expected);
  ASSERT_TRUE(mesh.has_colors());
  EXPECT_FLOAT_EQ(mesh.colors[0].x(), 0.5f);
  EXPECT_FLOAT_EQ(mesh.colors[0].y(), 0.25f);
  EXPECT_FLOAT_EQ(mesh.colors[0].z(), 1.0f);
  const MeshFileSummary summary = check_mesh_file(dir / "bowtie.off");
  EXPECT_EQ(summary.vertices, 9u);
  EXPECT_EQ(summary.faces, 3u);
  EXPECT_EQ(summary.triangles(), 4u);
}

TEST(MeshLoader, OffAndStlAndBinaryPlyAgree) {
  const auto dir = test::scratch_dir();
  // A tetrahedron in three formats.
  write_text(dir / "tet.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const TriangleMesh off = load_mesh(dir / "tet.off");
  EXPECT_EQ(off.vertex_count(), 4u);
  EXPECT_EQ(off.face_count(), 4u);

  std::string stl = "solid tet\n";
  for (const auto& t : off.triangles) {
    stl += " facet normal 0 0 0\n  outer loop\n";
    for (auto v : t) {
      const auto& p = off.positions[v];
      stl += "   vertex " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
    }
    stl += "  endloop\n endfacet\n";
  }
  stl += "endsolid tet\n";
  write_text(dir / "tet.stl", stl);
  const TriangleMesh from_stl = load_mesh(dir / "tet.stl");
  EXPECT_EQ(from_stl.face_count(), 4u);
  EXPECT_EQ(from_stl.bounds().hi, off.bounds().hi);

  save_mesh(off, dir / "tet_binary.ply");
  const TriangleMesh from_ply = load_mesh(dir / "tet_binary.ply");
  EXPECT_EQ(from_ply.vertex_count(), 4u);
  EXPECT_EQ(from_ply.face_count(), 4u);
  EXPECT_EQ(from_ply.positions, off.positions);
}

// The PLY reader (mesh/ply_reader.h) keeps the file as it is: its vertices in order (a fin of
// three triangles on one edge is not split, as OpenMesh split it), its faces in order with a quad
// fan-triangulated and counted, 16-bit colours scaled by 65535, and the same numbers from ASCII,
// little-endian and big-endian bodies, whatever the order of the face's lists. Lists longer than
// the buffer's refill boundary are read across it (a body of 2 MB).
TEST(MeshLoader, PlyIsReadAsStoredInEveryEncoding) {
  const auto dir = test::scratch_dir();
  const std::vector<std::array<double, 3>> points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}, {0.5, 0.5, -1}, {0.5, -1, 0.25}};
  const std::vector<std::vector<std::uint32_t>> faces = {{0, 1, 2, 3}, {0, 1, 4}, {1, 0, 5}, {0, 1, 6}};  // a quad, then a fin on edge 0-1
  const std::string header_vertices = "element vertex 7\nproperty float x\nproperty float y\nproperty float z\nproperty ushort red\n"
                                      "property ushort green\nproperty ushort blue\nproperty float confidence\n";
  const auto write = [&](const std::string& format) {
    const auto file = dir / ("mesh_" + format + ".ply");
    std::ofstream out(file, std::ios::binary);
    out << "ply\nformat " << format << " 1.0\ncomment written by the test\n" << header_vertices
        << "element face 4\nproperty uchar flags\nproperty list uchar int vertex_indices\nend_header\n";
    const bool big = format == "binary_big_endian";
    const auto put = [&](auto v) {
      char bytes[sizeof v];
      std::memcpy(bytes, &v, sizeof v);
      if (big) std::reverse(bytes, bytes + sizeof v);
      out.write(bytes, sizeof v);
    };
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto c = static_cast<std::uint16_t>(9000 * i);
      if (format == "ascii") {
        out << points[i][0] << " " << points[i][1] << " " << points[i][2] << " " << c << " 65535 0 0.5\n";
      } else {
        for (const double x : points[i]) put(static_cast<float>(x));
        put(c), put(std::uint16_t{65535}), put(std::uint16_t{0}), put(0.5f);
      }
    }
    for (const auto& f : faces) {
      if (format == "ascii") {
        out << "7 " << f.size();
        for (const auto v : f) out << " " << v;
        out << "\n";
      } else {
        put(std::uint8_t{7}), put(static_cast<std::uint8_t>(f.size()));
        for (const auto v : f) put(static_cast<std::int32_t>(v));
      }
    }
    return file;
  };
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    LoadReport report;
    const TriangleMesh mesh = load_mesh(write(format), &report);
    ASSERT_EQ(mesh.positions.size(), 7u) << format;
    for (std::size_t i = 0; i < points.size(); ++i)
      EXPECT_EQ(mesh.positions[i], Eigen::Vector3d(points[i][0], points[i][1], points[i][2])) << format << " vertex " << i;
    const std::vector<std::array<std::uint32_t, 3>> expected = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}, {1, 0, 5}, {0, 1, 6}};
    EXPECT_EQ(mesh.triangles, expected) << format;
    EXPECT_EQ(report.polygons_triangulated, 1u) << format;
    ASSERT_TRUE(mesh.has_colors()) << format;
    EXPECT_FLOAT_EQ(mesh.colors[2].x(), 18000.0f / 65535.0f) << format;
    EXPECT_FLOAT_EQ(mesh.colors[2].y(), 1.0f) << format;
    EXPECT_FLOAT_EQ(mesh.colors[2].z(), 0.0f) << format;
  }

  // A big body: a band of 2 x 60000 vertices as 119998 triangles, binary (4.3 MB, across the
  // reader's 1 MB buffer), every vertex and triangle where the file puts it.
  const int columns = 60000;
  const auto big = dir / "strip.ply";
  {
    std::ofstream out(big, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << 2 * columns
        << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << 2 * (columns - 1)
        << "\nproperty list uchar uint vertex_indices\nend_header\n";
    for (int i = 0; i < columns; ++i)
      for (const double y : {0.0, 1.0}) {
        const double p[3] = {i * 0.001, y, std::sin(i * 0.01)};
        out.write(reinterpret_cast<const char*>(p), sizeof p);
      }
    for (std::uint32_t i = 0; i + 1 < static_cast<std::uint32_t>(columns); ++i) {
      const std::uint32_t a = 2 * i, t[2][3] = {{a, a + 2, a + 1}, {a + 1, a + 2, a + 3}};
      for (const auto& tri : t) {
        out.put(3);
        out.write(reinterpret_cast<const char*>(tri), sizeof tri);
      }
    }
  }
  const TriangleMesh strip = load_mesh(big);
  ASSERT_EQ(strip.positions.size(), static_cast<std::size_t>(2 * columns));
  ASSERT_EQ(strip.triangles.size(), static_cast<std::size_t>(2 * (columns - 1)));
  EXPECT_EQ(strip.positions[2 * 43210 + 1], Eigen::Vector3d(43210 * 0.001, 1.0, std::sin(43210 * 0.01)));
  EXPECT_EQ(strip.triangles.back(), (std::array<std::uint32_t, 3>{2 * columns - 3, 2 * columns - 2, 2 * columns - 1}));
}

TEST(MeshLoader, MissingFileIsAnIoErrorNamingTheFile) {
  try {
    load_mesh("/nonexistent/dir/model.ply");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/model.ply"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos);
  }
}

TEST(MeshLoader, BadInputsAreInputErrors) {
  const auto dir = test::scratch_dir();
  EXPECT_THROW(load_mesh(write_text(dir / "empty.ply", "")), InputError);
  EXPECT_THROW(load_mesh(write_text(dir / "garbage.ply", "this is not a ply file\n\x01\x02\x03")), InputError);
  EXPECT_THROW(load_mesh(write_text(dir / "model.xyz", "0 0 0\n")), InputError);
  EXPECT_THROW(load_mesh(write_text(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n")), InputError);
  EXPECT_THROW(load_mesh(write_text(dir / "point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n")), InputError);
  EXPECT_THROW(load_mesh(dir), IoError);  // a directory
}

TEST(MeshLoader, StanfordBunnyCounts) {
  MESHTOUR_SHARED_MESH(file, "bunny.ply");
  const TriangleMesh mesh = load_mesh(file);
  EXPECT_EQ(mesh.vertex_count(), 34817u);
  EXPECT_EQ(mesh.face_count(), 69630u);
  const Bounds b = mesh.bounds();
  EXPECT_NEAR(b.lo.x(), -1.893798, 1e-5);
  EXPECT_NEAR(b.hi.y(), 2.74642, 1e-5);
}

TEST(ProceduralSculpture, IsClosedEnoughAndOriented) {
  const TriangleMesh mesh = make_sculpture(1.0);
  EXPECT_GT(mesh.face_count(), 30000u);
  EXPECT_LT(mesh.face_count(), 120000u);
  ASSERT_TRUE(mesh.has_colors());
  // Outward orientation: the signed volume of a closed, outward-oriented surface is positive.
  double volume = 0;
  for (const auto& t : mesh.triangles)
    volume += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]])) / 6.0;
  EXPECT_GT(volume, 0.5);  // pedestal alone: pi * 0.85^2 * 0.3 = 0.68
  const Bounds b = mesh.bounds();
  EXPECT_NEAR(b.lo.y(), 0.0, 1e-12);
  EXPECT_GT(b.hi.y(), 1.0);
  // Detail scales the triangle count.
  EXPECT_LT(make_sculpture(0.25).face_count(), mesh.face_count() / 2);
}

}  // namespace
}  // namespace meshtour
