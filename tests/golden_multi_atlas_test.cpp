// Many materials: a sphere whose texture is one atlas, and the same sphere with the atlas cut in
// two halves (one material each, faces that straddle the cut keep the whole atlas, as
// photogrammetry exports do) render alike; the two-atlas form is also a golden image.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>

#include "golden.h"
#include "helpers.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

constexpr int kSlices = 48, kStacks = 24;

// A 128x64 atlas: coloured bands across u, stripes across v, so a wrong atlas or offset shows.
OIIO::ImageBuf atlas() {
  OIIO::ImageBuf image(OIIO::ImageSpec(128, 64, 3, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) {
      const float band = static_cast<float>((x / 16) % 4) / 3.0f;
      const bool stripe = (y / 8) % 2 == 0;
      float c[3] = {0.15f + 0.8f * band, stripe ? 0.8f : 0.2f, 0.9f - 0.7f * band};
      image.setpixel(x, y, c);
    }
  return image;
}

// Writes the sphere as OBJ; `split`: left and right halves of the atlas as materials of their own.
std::filesystem::path write_sphere(const std::filesystem::path& dir, bool split) {
  const OIIO::ImageBuf full = atlas();
  if (!full.write((dir / "atlas full.png").string())) throw std::runtime_error(full.geterror());
  std::ofstream mtl(dir / "sphere.mtl");
  mtl << "newmtl full\nKd 1 1 1\nmap_Kd atlas full.png\n";
  if (split) {
    for (int half = 0; half < 2; ++half) {
      const OIIO::ImageBuf part = OIIO::ImageBufAlgo::cut(full, OIIO::ROI(64 * half, 64 * (half + 1), 0, 64));
      const std::string name = half == 0 ? "left.png" : "right.png";
      if (!part.write((dir / name).string())) throw std::runtime_error(part.geterror());
      mtl << "newmtl " << (half == 0 ? "left" : "right") << "\nmap_Kd -clamp off " << name << "\n";
    }
  }
  mtl.close();
  const auto file = dir / (split ? "two_atlases.obj" : "one_atlas.obj");
  std::ofstream obj(file);
  obj << "mtllib sphere.mtl\n";
  for (int j = 0; j <= kStacks; ++j)
    for (int i = 0; i <= kSlices; ++i) {
      const double theta = std::numbers::pi * j / kStacks, phi = 2 * std::numbers::pi * i / kSlices;
      obj << "v " << std::sin(theta) * std::cos(phi) << " " << std::cos(theta) << " " << -std::sin(theta) * std::sin(phi) << "\n";
    }
  // Texture coordinates: the whole atlas, then (split) each half's own [0,1] range.
  for (int form = 0; form < (split ? 3 : 1); ++form)
    for (int j = 0; j <= kStacks; ++j)
      for (int i = 0; i <= kSlices; ++i) {
        const double u = static_cast<double>(i) / kSlices, v = 1.0 - static_cast<double>(j) / kStacks;
        obj << "vt " << (form == 0 ? u : form == 1 ? 2 * u : 2 * u - 1) << " " << v << "\n";
      }
  const int per_form = (kStacks + 1) * (kSlices + 1);
  std::string current;
  for (int j = 0; j < kStacks; ++j)
    for (int i = 0; i < kSlices; ++i) {
      // Every face lies in one half (the cut is on a slice boundary); alternate rows of the
      // left half keep the full atlas, like faces straddling a cut.
      const bool left = i < kSlices / 2;
      const int form = !split ? 0 : (left && j % 2 == 0) ? 0 : left ? 1 : 2;
      const std::string material = form == 0 ? "full" : form == 1 ? "left" : "right";
      if (material != current) obj << "usemtl " << (current = material) << "\n";
      const int a = 1 + j * (kSlices + 1) + i, b = a + 1, c = a + kSlices + 1, d = c + 1;
      const int o = form * per_form;
      obj << "f " << a << "/" << a + o << " " << c << "/" << c + o << " " << d << "/" << d + o << "\n";
      obj << "f " << a << "/" << a + o << " " << d << "/" << d + o << " " << b << "/" << b + o << "\n";
    }
  return file;
}

RenderOptions small_options() {
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.samples_per_pixel = 4;
  o.shading = look_preset("plain");
  return o;
}

const Camera kCamera{{2.0, 1.2, 2.4}, {0, 0, 0}, {0, 1, 0}, 45.0};

TEST(GoldenMultiAtlas, TwoAtlasesRenderLikeOne) {
  const auto dir = test::scratch_dir();
  const TriangleMesh one = load_mesh(write_sphere(dir, false));
  const TriangleMesh two = load_mesh(write_sphere(dir, true));
  ASSERT_EQ(one.materials.size(), 1u);
  ASSERT_EQ(two.materials.size(), 3u);
  EXPECT_EQ(two.materials[0].texture.file.filename(), "atlas full.png");  // a name with a space
  ASSERT_EQ(two.triangle_materials.size(), two.triangles.size());
  std::size_t per_material[3] = {};
  for (const auto m : two.triangle_materials) ++per_material[m];
  EXPECT_EQ(per_material[0], static_cast<std::size_t>(kStacks / 2 * kSlices));
  EXPECT_EQ(per_material[1], per_material[0]);
  EXPECT_EQ(per_material[2], static_cast<std::size_t>(kStacks * kSlices));

  const Image a = Renderer(one, small_options()).render(kCamera);
  const Image b = Renderer(two, small_options()).render(kCamera);
  const double mean = test::mean_pixel_difference(a, b);
  std::printf("mean pixel difference one atlas vs two atlases: %.3f/255\n", mean);
  EXPECT_LE(mean, 3.0);
  test::compare_with_golden(b, "plain_two_atlas_obj", 0.01);
}

TEST(GoldenMultiAtlas, WrongAtlasWouldShow) {
  // The check above has teeth: the faces of the half atlases, drawn from the whole one, differ.
  const auto dir = test::scratch_dir();
  TriangleMesh two = load_mesh(write_sphere(dir, true));
  const Image right = Renderer(two, small_options()).render(kCamera);
  std::fill(two.triangle_materials.begin(), two.triangle_materials.end(), 0u);
  const Image wrong = Renderer(two, small_options()).render(kCamera);
  EXPECT_GT(test::mean_pixel_difference(right, wrong), 4.0);  // the tolerance above is 3
}

}  // namespace
}  // namespace meshtour
