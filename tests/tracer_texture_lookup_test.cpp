// Texture lookups as each format says: OBJ maps repeat outside [0, 1] unless `-clamp on` (MTL's
// rule, and Blender's), glTF samplers' magFilter is honoured (LINEAR bilinear, NEAREST the texel
// under the point). Seen through the albedo layer of a square quad that fills the frame, its UVs
// running from -0.5 to 1.5 over an 8x8 texture: 16 texels across 128 pixels, 8 pixels a texel, so
// pixels can be chosen whose whole reconstruction filter (radius 1.5) lies inside one texel, at a
// known fraction of the way between two texel centres.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "gltf_writer.h"
#include "helpers.h"
#include "tracer/color.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;
constexpr int kTexels = 8, kPixels = 128;

// The texture's value at texel (i, j), column i from the left, row j from the top: red and green
// say which texel it is (a lookup of the wrong one shows), blue is a checkerboard (another filter
// than the format's, bicubic say, is a few hundredths off there).
Eigen::Vector3f texel_value(int i, int j) {
  return {0.05f + 0.1f * static_cast<float>(i), 0.05f + 0.1f * static_cast<float>(j), (i + j) % 2 ? 0.9f : 0.1f};
}

void write_texture(const fs::path& file, OIIO::TypeDesc type) {
  OIIO::ImageBuf tex(OIIO::ImageSpec(kTexels, kTexels, 3, type));
  for (int j = 0; j < kTexels; ++j)
    for (int i = 0; i < kTexels; ++i) {
      Eigen::Vector3f v = texel_value(i, j);
      if (type == OIIO::TypeDesc::UINT8) v = {linear_to_srgb(v.x()), linear_to_srgb(v.y()), linear_to_srgb(v.z())};
      tex.setpixel(i, j, v.data());
    }
  ASSERT_TRUE(tex.write(file.string())) << tex.geterror();
}

// The quad's corners, counter-clockwise seen from +z, and their UVs (OBJ's convention: v up).
const float kCorners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
const float kUvs[4][2] = {{-0.5f, -0.5f}, {1.5f, -0.5f}, {1.5f, 1.5f}, {-0.5f, 1.5f}};

fs::path write_obj(const fs::path& dir, const std::string& map_options) {
  write_texture(dir / "texels.exr", OIIO::TypeDesc::FLOAT);
  std::ofstream(dir / "quad.mtl") << "newmtl texels\nKd 1 1 1\nmap_Kd " << map_options << "texels.exr\n";
  std::ofstream obj(dir / "quad.obj");
  obj << "mtllib quad.mtl\nusemtl texels\n";
  for (const auto& c : kCorners) obj << "v " << c[0] << " " << c[1] << " 0\n";
  for (const auto& t : kUvs) obj << "vt " << t[0] << " " << t[1] << "\n";
  obj << "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  return dir / "quad.obj";
}

fs::path write_glb(const fs::path& dir, int mag_filter) {
  write_texture(dir / "texels.png", OIIO::TypeDesc::UINT8);
  test::GltfBuilder g;
  std::vector<float> positions, uvs;
  for (int k = 0; k < 4; ++k) {
    positions.insert(positions.end(), {kCorners[k][0], kCorners[k][1], 0.0f});
    uvs.insert(uvs.end(), {kUvs[k][0], 1.0f - kUvs[k][1]});  // glTF's v runs down the image
  }
  const int pos = g.floats(positions, 3), uv = g.floats(uvs, 2), idx = g.indices({0, 1, 2, 0, 2, 3});
  g.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", idx}, {"material", 0}}}}}};
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.doc["scenes"] = {{{"nodes", {0}}}};
  g.doc["scene"] = 0;
  g.embedded_image(test::read_bytes(dir / "texels.png"), "image/png");
  g.doc["samplers"] = {{{"magFilter", mag_filter}, {"minFilter", 9987}}};
  g.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
  g.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  g.write_glb(dir / "quad.glb");
  return dir / "quad.glb";
}

// The albedo layer of the quad seen square on, filling the frame exactly.
Image albedo_of(const fs::path& model) {
  RenderOptions options;
  options.width = options.height = kPixels;
  options.samples_per_pixel = 16;
  options.shading = look_preset("plain");
  options.layers.albedo = true;
  options.denoise = false;
  const double fov = 2.0 * std::atan(0.2) * 180.0 / std::numbers::pi;  // half height 1 at distance 5
  return Renderer(load_mesh(model), options).render(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, fov});
}

enum class Wrap { repeat, clamp };
enum class Filter { linear, nearest };

// What the format's lookup gives at texture coordinates (s, t) in texels (s right, t down).
Eigen::Vector3f expected_lookup(double s, double t, Wrap wrap, Filter filter, bool encoded) {
  const auto index = [&](int i) { return wrap == Wrap::repeat ? ((i % kTexels) + kTexels) % kTexels : std::clamp(i, 0, kTexels - 1); };
  // An 8-bit texture is filtered as stored (sRGB-encoded) and decoded after the lookup.
  const auto stored = [&](int i, int j) {
    const Eigen::Vector3f v = texel_value(index(i), index(j));
    return encoded ? Eigen::Vector3f(std::round(linear_to_srgb(v.x()) * 255) / 255, std::round(linear_to_srgb(v.y()) * 255) / 255,
                                     std::round(linear_to_srgb(v.z()) * 255) / 255)
                   : v;
  };
  Eigen::Vector3f value;
  if (filter == Filter::nearest) {
    value = stored(static_cast<int>(std::floor(s)), static_cast<int>(std::floor(t)));
  } else {
    const double fs = s - 0.5, ft = t - 0.5;
    const int i = static_cast<int>(std::floor(fs)), j = static_cast<int>(std::floor(ft));
    const float a = static_cast<float>(fs - i), b = static_cast<float>(ft - j);
    value = (1 - a) * (1 - b) * stored(i, j) + a * (1 - b) * stored(i + 1, j) + (1 - a) * b * stored(i, j + 1) + a * b * stored(i + 1, j + 1);
  }
  return encoded ? srgb_to_linear(value) : value;
}

// Compares the albedo with the lookup at pixels whose filter lies inside one texel and 0.1875 of
// the way from its centre to the next (both ways), over the whole quad, outside [0, 1] included.
void expect_lookups(const Image& img, Wrap wrap, Filter filter, bool encoded, float tolerance) {
  int checked = 0, outside = 0;
  double worst = 0;
  for (int py = 0; py < kPixels; ++py)
    for (int px = 0; px < kPixels; ++px) {
      // Film position -> quad point x, y in [-1, 1] -> UV in [-0.5, 1.5] -> texels (t down).
      const double x = (px + 0.5) / kPixels * 2 - 1, y = 1 - (py + 0.5) / kPixels * 2;
      const double s = (x + 0.5) * kTexels, t = (1 - (y + 0.5)) * kTexels;
      if (std::abs((s - std::floor(s)) - 0.6875) > 1e-9 || std::abs((t - std::floor(t)) - 0.6875) > 1e-9) continue;
      const Eigen::Vector3f want = expected_lookup(s, t, wrap, filter, encoded);
      const float* got = &img.albedo[(static_cast<std::size_t>(py) * kPixels + px) * 3];
      for (int c = 0; c < 3; ++c) worst = std::max(worst, static_cast<double>(std::abs(got[c] - want[c])));
      EXPECT_NEAR(got[0], want[0], tolerance) << "pixel " << px << "," << py << " (s " << s << ", t " << t << ")";
      EXPECT_NEAR(got[1], want[1], tolerance) << "pixel " << px << "," << py;
      EXPECT_NEAR(got[2], want[2], tolerance) << "pixel " << px << "," << py;
      ++checked;
      outside += s < 0 || t < 0 || s > kTexels || t > kTexels;
    }
  EXPECT_EQ(checked, 256);  // one pixel per texel of the 16 x 16 the quad shows
  EXPECT_EQ(outside, 256 - 64);
  std::cout << "[ worst ] " << worst << "\n";
}

TEST(TextureLookup, ObjMapsRepeatUnlessClampedAndAreBilinear) {
  const fs::path dir = test::scratch_dir();
  expect_lookups(albedo_of(write_obj(dir, "")), Wrap::repeat, Filter::linear, false, 3e-3f);
  expect_lookups(albedo_of(write_obj(dir, "-clamp on ")), Wrap::clamp, Filter::linear, false, 3e-3f);
}

TEST(TextureLookup, GltfSamplersMagFilterIsHonoured) {
  const fs::path dir = test::scratch_dir();
  expect_lookups(albedo_of(write_glb(dir, 9729)), Wrap::repeat, Filter::linear, true, 3e-3f);
  expect_lookups(albedo_of(write_glb(dir, 9728)), Wrap::repeat, Filter::nearest, true, 1e-4f);
}

}  // namespace
}  // namespace meshtour
