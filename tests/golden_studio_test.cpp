// Golden-image tests of the looks: the studio preset on the bunny, a vertex-coloured model, the
// transparent background, the plain preset, and an EXR with its extra layers read back
// (metric, thresholds, diff images and the GOLDEN_UPDATE=1 switch: tests/golden.h).
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>

#include "core/error.h"
#include "golden.h"
#include "helpers.h"
#include "test_meshes.h"
#include "textured_cube.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

// Fraction of pixels allowed to fail (see tests/golden.h): 1 %, twice the default scene's, because at 4 spp
// every flipped secondary ray shows.
void studio_golden(const Image& image, const std::string& name) { test::compare_with_golden(image, name, 0.01); }


TriangleMesh sphere(bool colored) { return test_meshes::uv_sphere(1.0, 64, 32, colored); }

RenderOptions small_options(const std::string& preset) {
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.samples_per_pixel = 4;
  o.shading = look_preset(preset);
  return o;
}

const Camera kSphereCamera{{2.2, 1.6, 3.6}, {0, -0.2, 0}, {0, 1, 0}, 40.0};

TEST(GoldenStudio, Bunny) {
  MESHTOUR_SHARED_MESH(file, "bunny.ply");
  const TriangleMesh bunny = load_mesh(file);
  const Bounds b = bunny.bounds();
  const double distance = 0.55 * b.diagonal() / std::tan(35.0 * std::numbers::pi / 360.0);
  const double elevation = 18.0 * std::numbers::pi / 180.0;
  const Camera camera{b.center() + distance * Eigen::Vector3d(0, std::sin(elevation), std::cos(elevation)), b.center(),
                      {0, 1, 0}, 35.0};
  studio_golden(Renderer(bunny, small_options("studio")).render(camera), "studio_bunny");
}

TEST(GoldenStudio, VertexColours) {
  studio_golden(Renderer(sphere(true), small_options("studio")).render(kSphereCamera), "studio_vertex_colours");
}

TEST(GoldenStudio, TransparentBackground) {
  RenderOptions o = small_options("studio");
  o.shading.background = BackgroundKind::transparent;
  const Image img = Renderer(sphere(false), o).render(kSphereCamera);
  ASSERT_TRUE(img.transparent);
  studio_golden(img, "studio_transparent");  // RGBA PNG: alpha is compared too
}

TEST(GoldenStudio, PlainPreset) {
  studio_golden(Renderer(sphere(true), small_options("plain")).render(kSphereCamera), "plain_vertex_colours");
}

using test::write_textured_cube;

TEST(GoldenStudio, TexturedObj) {
  const auto file = write_textured_cube(test::scratch_dir());
  const TriangleMesh cube = load_mesh(file);
  ASSERT_TRUE(cube.has_texture()) << "the loader kept no UVs or no map_Kd";
  ASSERT_EQ(cube.materials.size(), 1u);
  EXPECT_EQ(cube.materials[0].texture.file.filename(), "checker.png");
  EXPECT_EQ(cube.corner_uvs.size(), 3 * cube.triangles.size());
  studio_golden(Renderer(cube, small_options("studio")).render(Camera{{3.2, 2.6, 4.4}, {0, -0.3, 0}, {0, 1, 0}, 40.0}),
                      "studio_textured_obj");
}

TEST(GoldenStudio, MissingTextureIsAnIoError) {
  const auto dir = test::scratch_dir();
  const auto file = write_textured_cube(dir);
  std::filesystem::remove(dir / "checker.png");
  try {
    load_mesh(file);
    FAIL() << "a missing texture loaded";
  } catch (const IoError& e) {
    // The message names the texture and its material, and the way out.
    EXPECT_NE(std::string(e.what()).find("checker.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'checker'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--missing-textures grey"), std::string::npos) << e.what();
  }
  LoadReport report;
  const TriangleMesh cube = load_mesh(file, &report, LoadOptions{.missing_textures_grey = true});
  EXPECT_FALSE(cube.has_texture());
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.back().find("checker.png"), std::string::npos);
  EXPECT_NO_THROW(Renderer(cube, small_options("studio")));
}

TEST(GoldenStudio, ExrWithExtraLayers) {
  RenderOptions o = small_options("studio");
  o.layers = {true, true, true};
  const Image img = Renderer(sphere(true), o).render(kSphereCamera, 5);
  const auto file = test::scratch_dir() / "layers.exr";
  write_image(img, file);

  OIIO::ImageBuf exr(file.string());
  ASSERT_TRUE(exr.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << exr.geterror();
  const OIIO::ImageSpec& spec = exr.spec();
  // OpenEXR sorts channels by name within a file; look each one up by its name.
  ASSERT_EQ(spec.nchannels, 15);
  for (const char* name : {"R", "G", "B", "A", "denoised.R", "denoised.G", "denoised.B", "denoised.A", "albedo.R", "albedo.G",
                           "albedo.B", "N.X", "N.Y", "N.Z", "Z"})
    EXPECT_GE(spec.channelindex(name), 0) << name;
  const int z = spec.channelindex("Z");
  ASSERT_GE(z, 0);
  EXPECT_EQ(spec.channelformat(z), OIIO::TypeDesc::FLOAT);
  // Header metadata.
  EXPECT_EQ(spec.get_int_attribute("meshtour:samplesPerPixel"), 4);
  EXPECT_EQ(spec.get_int_attribute("meshtour:frame"), 5);
  EXPECT_NEAR(spec.get_float_attribute("meshtour:verticalFovDegrees"), 40.0f, 1e-4f);
  EXPECT_FALSE(spec.get_string_attribute("meshtour:version").empty());
  const OIIO::ParamValue* eye = spec.find_attribute("meshtour:cameraPosition");
  ASSERT_NE(eye, nullptr);
  const double* e = static_cast<const double*>(eye->data());
  EXPECT_DOUBLE_EQ(e[0], 2.2);
  EXPECT_DOUBLE_EQ(e[2], 3.6);
  // The render time (the header's one run-dependent attribute, which comparisons skip), and no
  // OpenImageIO timestamp.
  EXPECT_GE(spec.get_float_attribute("meshtour:renderSeconds", -1.0f), 0.0f);
  EXPECT_TRUE(spec.get_string_attribute("DateTime").empty());

  // Layers hold what the renderer computed (to half precision), and make sense: the centre
  // pixel sees the sphere about 3.7 units away, with a unit normal facing the camera.
  const int cx = 80, cy = 60;
  const std::size_t p = static_cast<std::size_t>(cy) * 160 + cx;
  EXPECT_NEAR(exr.getchannel(cx, cy, 0, spec.channelindex("A")), 1.0f, 1e-3f);
  // The main layer is the raw frame, the denoised one beside it (to half precision).
  EXPECT_NEAR(exr.getchannel(cx, cy, 0, spec.channelindex("R")), img.rgba[p * 4], 2e-3f);
  EXPECT_NEAR(exr.getchannel(cx, cy, 0, spec.channelindex("denoised.R")), img.denoised[p * 4], 2e-3f);
  RenderOptions raw_only = o;
  raw_only.denoise = false;
  const auto raw_file = test::scratch_dir() / "raw-only.exr";
  write_image(Renderer(sphere(true), raw_only).render(kSphereCamera, 5), raw_file);
  OIIO::ImageBuf without(raw_file.string());
  ASSERT_TRUE(without.init_spec(without.name(), 0, 0));
  EXPECT_EQ(without.spec().nchannels, 11);  // no denoised layer when denoising is off
  EXPECT_LT(without.spec().channelindex("denoised.R"), 0);
  EXPECT_NEAR(exr.getchannel(cx, cy, 0, spec.channelindex("albedo.G")), img.albedo[p * 3 + 1], 2e-3f);
  EXPECT_FLOAT_EQ(exr.getchannel(cx, cy, 0, z), img.depth[p]);
  EXPECT_GT(img.depth[p], 2.5f);
  EXPECT_LT(img.depth[p], 4.5f);
  const Eigen::Vector3f n(exr.getchannel(cx, cy, 0, spec.channelindex("N.X")), exr.getchannel(cx, cy, 0, spec.channelindex("N.Y")),
                          exr.getchannel(cx, cy, 0, spec.channelindex("N.Z")));
  EXPECT_NEAR(n.norm(), 1.0f, 0.01f);
  EXPECT_GT(n.dot(Eigen::Vector3f(2.2f, 1.8f, 3.6f).normalized()), 0.5f);
  EXPECT_TRUE(std::isinf(exr.getchannel(0, 0, 0, z)));  // the sky: nothing hit

  // The normal layer, seen as colours (n * 0.5 + 0.5), against its reference.
  Image normals;
  normals.width = img.width;
  normals.height = img.height;
  normals.rgba.resize(img.rgba.size());
  for (std::size_t i = 0; i < img.normal.size() / 3; ++i) {
    for (int c = 0; c < 3; ++c) normals.rgba[i * 4 + c] = img.normal[i * 3 + c] * 0.5f + 0.5f;
    normals.rgba[i * 4 + 3] = 1.0f;
  }
  studio_golden(normals, "exr_layer_normals");
}

TEST(SceneLook, PresetAndOverridesFromTheFile) {
  const Scene scene = parse_scene(R"({"model": {"procedural": "sculpture"},
      "look": {"preset": "plain", "base_color": [0.2, 0.4, 0.6], "roughness": 0.3, "exposure": 0.5,
               "background": "transparent", "lights": [{"from": [0, 1, 1], "intensity": 2, "size": 5}]},
      "output": {"exr_layers": ["albedo", "depth"]}})", "test.json", ".");
  const Shading& sh = scene.render.shading;
  EXPECT_EQ(sh.preset, "plain");
  EXPECT_FLOAT_EQ(sh.material.base_color.y(), 0.4f);
  EXPECT_FLOAT_EQ(sh.material.roughness, 0.3f);
  EXPECT_FLOAT_EQ(sh.exposure, 0.5f);
  EXPECT_EQ(sh.background, BackgroundKind::transparent);
  ASSERT_EQ(sh.lights.size(), 1u);
  EXPECT_FLOAT_EQ(sh.lights[0].intensity, 2.0f);
  EXPECT_FALSE(sh.shadows);  // from the plain preset
  EXPECT_TRUE(scene.render.layers.albedo && scene.render.layers.depth && !scene.render.layers.normal);

  // --preset studio on the command line: the studio preset under the file's own values.
  Scene changed = scene;
  set_look_preset(changed, "studio");
  EXPECT_EQ(changed.render.shading.preset, "studio");
  EXPECT_TRUE(changed.render.shading.shadows);
  EXPECT_FLOAT_EQ(changed.render.shading.material.base_color.y(), 0.4f);

  EXPECT_THROW(parse_scene(R"({"model": {"procedural": "sculpture"}, "look": {"preset": "moody"}})", "t.json", "."), InputError);
  EXPECT_THROW(parse_scene(R"({"model": {"procedural": "sculpture"}, "look": {"lights": [{"from": [0, 0, 0]}]}})", "t.json", "."),
               InputError);
  EXPECT_THROW(parse_scene(R"({"model": {"procedural": "sculpture"}, "output": {"exr_layers": ["motion"]}})", "t.json", "."),
               InputError);
}

}  // namespace
}  // namespace meshtour
