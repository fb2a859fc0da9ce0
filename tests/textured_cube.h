#pragma once
// A cube with one texture over each face (OBJ + MTL + an 8x8 checkerboard PNG with a red
// corner, so that a flipped or rotated lookup shows), written into a folder: the textured model
// of the golden tests and of bench/denoise_quality. Header-only (no GoogleTest), so the bench can
// use it too.
#include <OpenImageIO/imagebuf.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace meshtour::test {

/// Writes checker.png, cube.mtl and cube.obj into `dir`; returns the OBJ's path.
/// \throw std::runtime_error if the texture cannot be written.
inline std::filesystem::path write_textured_cube(const std::filesystem::path& dir) {
  OIIO::ImageBuf tex(OIIO::ImageSpec(64, 64, 3, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool dark = ((x / 8) + (y / 8)) % 2 == 1;
      float c[3] = {dark ? 0.1f : 0.9f, dark ? 0.1f : 0.85f, dark ? 0.15f : 0.7f};
      if (x < 16 && y < 16) c[0] = 0.9f, c[1] = 0.1f, c[2] = 0.1f;  // top left of the image: v = 1
      tex.setpixel(x, y, c);
    }
  if (!tex.write((dir / "checker.png").string())) throw std::runtime_error("cannot write the checker texture: " + tex.geterror());
  std::ofstream(dir / "cube.mtl") << "newmtl checker\nKd 1 1 1\nmap_Kd checker.png\n";
  std::ofstream obj(dir / "cube.obj");
  obj << "mtllib cube.mtl\n";
  for (int i = 0; i < 8; ++i) obj << "v " << (i & 1 ? 1 : -1) << " " << (i & 2 ? 1 : -1) << " " << (i & 4 ? 1 : -1) << "\n";
  obj << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl checker\n";
  // Faces counter-clockwise seen from outside (vertex index = 1 + x + 2y + 4z bits).
  const int faces[6][4] = {{1, 2, 4, 3}, {5, 7, 8, 6}, {1, 5, 6, 2}, {3, 4, 8, 7}, {1, 3, 7, 5}, {2, 6, 8, 4}};
  // As two triangles each: the loader keeps the UVs of triangles (OpenMesh's triangulation of
  // polygons does not carry the corners' UVs over to the diagonal's halfedges).
  for (const auto& f : faces) {
    obj << "f " << f[0] << "/1 " << f[1] << "/2 " << f[2] << "/3\n";
    obj << "f " << f[0] << "/1 " << f[2] << "/3 " << f[3] << "/4\n";
  }
  return dir / "cube.obj";
}

}  // namespace meshtour::test
