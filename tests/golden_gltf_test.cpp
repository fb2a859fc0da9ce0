// A textured GLB and a PLY with texture coordinates render like the same model as a textured
// OBJ (mean pixel difference at most 3/255); the GLB also like its own golden image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "gltf_writer.h"
#include "golden.h"
#include "helpers.h"
#include "scenes/scene.h"
#include "textured_cube.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

// The textured cube of tests/textured_cube.h as a GLB: one vertex per triangle corner, the
// checker PNG embedded in the binary chunk.
std::filesystem::path write_cube_glb(const std::filesystem::path& dir, const TriangleMesh& cube) {
  test::GltfBuilder b;
  std::vector<float> positions, uvs;
  std::vector<std::uint32_t> indices;
  for (std::size_t t = 0; t < cube.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = cube.positions[cube.triangles[t][c]];
      positions.insert(positions.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
      const Eigen::Vector2f& uv = cube.corner_uvs[3 * t + c];
      uvs.insert(uvs.end(), {uv.x(), 1.0f - uv.y()});  // glTF's v runs down the image
      indices.push_back(static_cast<std::uint32_t>(indices.size()));
    }
  const int pos = b.floats(positions, 3), uv = b.floats(uvs, 2), idx = b.indices(indices);
  const int image = b.embedded_image(test::read_bytes(dir / "checker.png"), "image/png");
  b.doc["textures"] = {{{"source", image}}};
  // Two-sided as the OBJ is (glTF's default is single-sided; the cube is wound inwards).
  b.doc["materials"] = {{{"name", "checker"}, {"doubleSided", true}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", idx}, {"material", 0}}}}}};
  b.doc["nodes"] = {{{"mesh", 0}}};
  b.doc["scenes"] = {{{"nodes", {0}}}};
  b.write_glb(dir / "cube.glb");
  return dir / "cube.glb";
}

// The textured cube's frame: small, studio look, every face of the cube in view.
RenderOptions cube_options() {
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.samples_per_pixel = 4;
  o.shading = look_preset("studio");
  // The same shading for every format (the look's), so that the images compare the texture
  // lookups alone: the GLB's material, having no metallicFactor, is a rough metal by glTF's rule.
  o.shading.material.use_file_material = false;
  return o;
}
const Camera kCubeCamera{{3.2, 2.6, 4.4}, {0, -0.3, 0}, {0, 1, 0}, 40.0};

TEST(GoldenGltf, TexturedGlbRendersLikeTheObj) {
  const auto dir = test::scratch_dir();
  const TriangleMesh obj = load_mesh(test::write_textured_cube(dir));
  const TriangleMesh glb = load_mesh(write_cube_glb(dir, obj));
  ASSERT_TRUE(glb.has_texture());
  const Image a = Renderer(obj, cube_options()).render(kCubeCamera), b = Renderer(glb, cube_options()).render(kCubeCamera);
  const double mean = test::mean_pixel_difference(a, b);
  std::printf("mean pixel difference textured OBJ vs GLB: %.3f/255\n", mean);
  EXPECT_LE(mean, 3.0);
  test::compare_with_golden(b, "studio_textured_glb", 0.01);
}

// The same cube as an ASCII PLY with a face 'texcoord' list and 'comment TextureFile'.
TEST(GoldenGltf, PlyWithCornerTexcoordsRendersLikeTheObj) {
  const auto dir = test::scratch_dir();
  const TriangleMesh obj = load_mesh(test::write_textured_cube(dir));
  {
    std::ofstream ply(dir / "cube.ply");
    ply << "ply\nformat ascii 1.0\ncomment TextureFile checker.png\nelement vertex " << obj.positions.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << obj.triangles.size()
        << "\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n";
    for (const auto& p : obj.positions) ply << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (std::size_t t = 0; t < obj.triangles.size(); ++t) {
      ply << "3 " << obj.triangles[t][0] << " " << obj.triangles[t][1] << " " << obj.triangles[t][2] << " 6";
      for (int c = 0; c < 3; ++c) ply << " " << obj.corner_uvs[3 * t + c].x() << " " << obj.corner_uvs[3 * t + c].y();
      ply << "\n";
    }
  }
  const TriangleMesh ply = load_mesh(dir / "cube.ply");
  ASSERT_TRUE(ply.has_texture());
  const double mean = test::mean_pixel_difference(Renderer(obj, cube_options()).render(kCubeCamera),
                                                  Renderer(ply, cube_options()).render(kCubeCamera));
  std::printf("mean pixel difference textured OBJ vs PLY: %.3f/255\n", mean);
  EXPECT_LE(mean, 3.0);
}

}  // namespace
}  // namespace meshtour
