// OBJ materials beyond the maps (mesh/obj_reader.cpp, docs/FORMATS.md "OBJ materials"): Kd, d and
// Tr, map_d, Ns/Ks and Pr/Pm, Ke, and map_Bump/bump read as a normal map only when its image is one.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "mesh/mesh.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

// A textured quad whose one material is `mtl` (the statements after "newmtl m").
TriangleMesh quad_with(const fs::path& dir, const std::string& mtl, LoadReport* report = nullptr, LoadOptions options = {}) {
  std::ofstream(dir / "m.mtl", std::ios::binary) << "newmtl m\n" << mtl;
  std::ofstream(dir / "quad.obj", std::ios::binary) << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";
  return load_mesh(dir / "quad.obj", report, options);
}

// A 32x32 RGB(A) PNG whose pixel (x, y) is colour(x, y).
template <class Colour>
void write_png(const fs::path& file, int channels, Colour colour) {
  const int n = 32;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(n) * n * channels);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::vector<std::uint8_t> c = colour(x, y);
      for (int k = 0; k < channels; ++k) pixels[(static_cast<std::size_t>(y) * n + x) * channels + k] = c[k];
    }
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out && out->open(file.string(), OIIO::ImageSpec(n, n, channels, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  out->close();
}

// A tangent-space normal map with some relief (bluish, R and G around 128), and a grey height map.
void write_normal_map(const fs::path& file) {
  write_png(file, 3, [](int x, int y) {
    return std::vector<std::uint8_t>{static_cast<std::uint8_t>(128 + (x % 8) * 6 - 21), static_cast<std::uint8_t>(128 + (y % 5) * 8 - 16), 240};
  });
}
void write_height_map(const fs::path& file) {
  write_png(file, 3, [](int x, int y) {
    const auto v = static_cast<std::uint8_t>(40 + ((x * 7 + y * 3) % 200));
    return std::vector<std::uint8_t>{v, v, v};
  });
}

bool has_warning(const LoadReport& report, const std::string& part) {
  for (const std::string& w : report.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

TEST(MeshMtl, KdIsTheColourWhenThereIsNoMap) {
  const auto dir = test::scratch_dir();
  TriangleMesh mesh = quad_with(dir, "Kd 0.8 0.5 0.2\n");
  ASSERT_EQ(mesh.materials.size(), 1u);
  ASSERT_TRUE(mesh.materials[0].base_color);
  EXPECT_EQ(*mesh.materials[0].base_color, Eigen::Vector3f(0.8f, 0.5f, 0.2f));
  // One number is grey; values beyond 0..1 are clamped.
  mesh = quad_with(dir, "Kd 0.25\n");
  EXPECT_EQ(*mesh.materials[0].base_color, Eigen::Vector3f(0.25f, 0.25f, 0.25f));
  mesh = quad_with(dir, "Kd 1.5 -1 0.5\n");
  EXPECT_EQ(*mesh.materials[0].base_color, Eigen::Vector3f(1.0f, 0.0f, 0.5f));
  // With a map, Kd is not the colour (whichever comes first), as Blender and three.js read it.
  write_png(dir / "albedo.png", 3, [](int, int) { return std::vector<std::uint8_t>{200, 100, 50}; });
  mesh = quad_with(dir, "map_Kd albedo.png\nKd 0.1 0.1 0.1\n");
  EXPECT_FALSE(mesh.materials[0].base_color);
  EXPECT_TRUE(mesh.materials[0].texture.present());
  // Vertex colours are the colour: Kd does not tint them.
  std::ofstream(dir / "coloured.obj", std::ios::binary) << "mtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nusemtl m\nf 1 2 3\n";
  std::ofstream(dir / "m.mtl", std::ios::binary) << "newmtl m\nKd 0.8 0.8 0.8\n";
  mesh = load_mesh(dir / "coloured.obj");
  ASSERT_EQ(mesh.materials.size(), 1u);
  EXPECT_FALSE(mesh.materials[0].base_color);
  EXPECT_TRUE(mesh.has_colors());
  // Without Kd, nothing: the look's colour, as before.
  mesh = quad_with(dir, "illum 2\n");
  EXPECT_FALSE(mesh.materials[0].base_color);
  EXPECT_FALSE(mesh.materials[0].metallic_roughness);
}

TEST(MeshMtl, OpacityFromDOrTr) {
  const auto dir = test::scratch_dir();
  TriangleMesh mesh = quad_with(dir, "d 0.4\n");
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::blend);
  EXPECT_FLOAT_EQ(mesh.materials[0].alpha, 0.4f);
  mesh = quad_with(dir, "Tr 0.25\n");
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::blend);
  EXPECT_FLOAT_EQ(mesh.materials[0].alpha, 0.75f);
  // d wins over Tr, in either order.
  mesh = quad_with(dir, "Tr 0.5\nd 1\n");
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::opaque);
  EXPECT_FLOAT_EQ(mesh.materials[0].alpha, 1.0f);
  // Agisoft Metashape writes "Tr 1" on opaque scans: opaque, not invisible.
  mesh = quad_with(dir, "Kd 1 1 1\nKs 0 0 0\nTr 1\nillum 1\nNs 0\n");
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::opaque);
  EXPECT_FLOAT_EQ(mesh.materials[0].alpha, 1.0f);
}

TEST(MeshMtl, MapDOnTheColourMapsAlphaBlends) {
  const auto dir = test::scratch_dir();
  write_png(dir / "leaf.png", 4, [](int x, int) { return std::vector<std::uint8_t>{40, 160, 40, static_cast<std::uint8_t>(x < 16 ? 255 : 0)}; });
  TriangleMesh mesh = quad_with(dir, "map_d leaf.png\nmap_Kd leaf.png\n");
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::blend);
  EXPECT_FLOAT_EQ(mesh.materials[0].alpha, 1.0f);
  // A separate opacity image is not read: said, and the surface stays opaque.
  write_png(dir / "mask.png", 3, [](int, int) { return std::vector<std::uint8_t>{255, 255, 255}; });
  LoadReport report;
  mesh = quad_with(dir, "map_Kd leaf.png\nmap_d mask.png\n", &report);
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::opaque);
  EXPECT_TRUE(has_warning(report, "map_d names mask.png")) << ::testing::PrintToString(report.warnings);
}

TEST(MeshMtl, SpecularStatementsGiveARoughness) {
  const auto dir = test::scratch_dir();
  // Blender's export of its default material: Ns 250, Ks 0.5 -> roughness 1 - sqrt(0.25) = 0.5.
  TriangleMesh mesh = quad_with(dir, "Ns 250.000000\nKa 1 1 1\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nillum 2\n");
  ASSERT_TRUE(mesh.materials[0].metallic_roughness);
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->roughness, 0.5f);
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->metallic, 0.0f);
  mesh = quad_with(dir, "Ns 1000\nKs 1 1 1\n");
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->roughness, 0.0f);
  // No highlight (Ks black, or illum 0/1): fully rough.
  mesh = quad_with(dir, "Ns 900\nKs 0 0 0\n");
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->roughness, 1.0f);
  mesh = quad_with(dir, "Ns 900\nKs 1 1 1\nillum 1\n");
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->roughness, 1.0f);
  // The PBR extension wins over Ns.
  mesh = quad_with(dir, "Ns 10\nPr 0.3\nPm 1\n");
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->roughness, 0.3f);
  EXPECT_FLOAT_EQ(mesh.materials[0].metallic_roughness->metallic, 1.0f);
}

TEST(MeshMtl, KeIsEmission) {
  const auto dir = test::scratch_dir();
  TriangleMesh mesh = quad_with(dir, "Ke 2 1 0\n");
  EXPECT_EQ(mesh.materials[0].emissive, Eigen::Vector3f(2.0f, 1.0f, 0.0f));
  EXPECT_FALSE(mesh.materials[0].emissive_texture.present());
  // map_Ke: the emission's image, as it is without Ke, times Ke with it.
  write_png(dir / "glow.png", 3, [](int x, int) { return std::vector<std::uint8_t>{static_cast<std::uint8_t>(x * 8), 0, 0}; });
  mesh = quad_with(dir, "map_Ke glow.png\n");
  EXPECT_EQ(mesh.materials[0].emissive_texture.file.filename(), "glow.png");
  EXPECT_EQ(mesh.materials[0].emissive, Eigen::Vector3f(1.0f, 1.0f, 1.0f));
  mesh = quad_with(dir, "map_Ke glow.png\nKe 0.5 0.5 0.5\n");
  EXPECT_EQ(mesh.materials[0].emissive, Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  // A missing map_Ke is an error naming it, as any map.
  EXPECT_THROW(quad_with(dir, "map_Ke gone.png\n"), IoError);
}

TEST(MeshMtl, UnreadableValuesAreSaidAndIgnored) {
  const auto dir = test::scratch_dir();
  LoadReport report;
  const TriangleMesh mesh = quad_with(dir, "Kd spectral wood.rfl\nd -halo\nNs nan\nKs 1 2 3 4\n", &report);
  EXPECT_FALSE(mesh.materials[0].base_color);
  EXPECT_EQ(mesh.materials[0].alpha_mode, MeshMaterial::AlphaMode::opaque);
  EXPECT_FALSE(mesh.materials[0].metallic_roughness);
  EXPECT_TRUE(has_warning(report, "Kd 'spectral wood.rfl' is not one to three numbers")) << ::testing::PrintToString(report.warnings);
  EXPECT_TRUE(has_warning(report, "d '-halo' is not a number"));
  EXPECT_TRUE(has_warning(report, "Ns 'nan' is not a number"));
  EXPECT_TRUE(has_warning(report, "Ks '1 2 3 4'"));
}

TEST(MeshMtl, BumpIsTheNormalMapOnlyWhenItIsOne) {
  const auto dir = test::scratch_dir();
  write_normal_map(dir / "normal.png");
  write_height_map(dir / "height.png");
  // Blender's exporter writes its normal maps as map_Bump with -bm.
  TriangleMesh mesh = quad_with(dir, "map_Bump -bm 0.7 normal.png\n");
  ASSERT_TRUE(mesh.materials[0].normal_texture.present());
  EXPECT_EQ(mesh.materials[0].normal_texture.file.filename(), "normal.png");
  EXPECT_FLOAT_EQ(mesh.materials[0].normal_scale, 0.7f);
  mesh = quad_with(dir, "bump normal.png\n");
  EXPECT_TRUE(mesh.materials[0].normal_texture.present());
  // A height map (the MTL specification's bump) is said and left out.
  LoadReport report;
  mesh = quad_with(dir, "map_Bump height.png\n", &report);
  EXPECT_FALSE(mesh.materials[0].normal_texture.present());
  EXPECT_TRUE(has_warning(report, "is a height map")) << ::testing::PrintToString(report.warnings);
  // norm says what it is: a bump beside it is not looked at.
  mesh = quad_with(dir, "norm -bm 2 normal.png\nmap_Bump height.png\n");
  EXPECT_EQ(mesh.materials[0].normal_texture.file.filename(), "normal.png");
  EXPECT_FLOAT_EQ(mesh.materials[0].normal_scale, 2.0f);
  // A missing bump map is an error naming it, or with --missing-textures grey a warning.
  EXPECT_THROW(
      try { quad_with(dir, "map_Bump gone.png\n"); } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("gone.png"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bump map"), std::string::npos) << e.what();
        throw;
      },
      IoError);
  LoadReport grey;
  mesh = quad_with(dir, "map_Bump gone.png\n", &grey, LoadOptions{.missing_textures_grey = true});
  EXPECT_FALSE(mesh.materials[0].normal_texture.present());
  EXPECT_TRUE(has_warning(grey, "gone.png"));
  // A command that does not render (path) does not open it.
  EXPECT_NO_THROW(quad_with(dir, "map_Bump gone.png\n", nullptr, LoadOptions{.check_textures = false}));
}

}  // namespace
}  // namespace meshtour
