// face_areas (mesh/mesh.h): the one per-face area list, for TriangleMesh and for meshes held as the
// same two arrays (pathgen's SurfaceMesh), computed in parallel chunks.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/triangle_geometry.h"
#include "mesh/mesh.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

TEST(MeshFaceAreas, EachFaceHasItsTriangleAreaWhateverTheThreadCount) {
  // 2 x 96 x 96 faces: several of the parallel loop's chunks of 1024.
  const TriangleMesh mesh = test_meshes::transformed(test_meshes::plane(96), 3.0, test_meshes::rotation({1, 2, 3}, 0.7), {1, -2, 5});
  const std::vector<double> areas = face_areas(mesh);
  ASSERT_EQ(areas.size(), mesh.triangles.size());
  double total = 0.0;
  for (std::size_t f = 0; f < areas.size(); ++f) {
    ASSERT_EQ(areas[f], triangle_area(mesh.positions, mesh.triangles[f])) << "face " << f;
    total += areas[f];
  }
  EXPECT_NEAR(total, 9.0, 1e-9);  // the unit square scaled by 3
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(face_areas(mesh.positions, mesh.triangles), areas);
  }
}

TEST(MeshFaceAreas, EmptyMeshHasNoAreas) { EXPECT_TRUE(face_areas(TriangleMesh{}).empty()); }

}  // namespace
}  // namespace meshtour
