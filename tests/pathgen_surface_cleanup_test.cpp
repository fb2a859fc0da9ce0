// §3 clean-up and normalization, §17.2 (exact items), option parsing and validation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "pathgen/surface.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

using namespace test_meshes;


Bounds bounds_of(const std::vector<Eigen::Vector3d>& points) {
  Bounds b{points.front(), points.front()};
  for (const auto& p : points) b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
  return b;
}

bool has_note_containing(const SurfaceAnalysis& s, const std::string& text) {
  for (const auto& n : s.cleanup_notes)
    if (n.find(text) != std::string::npos) return true;
  return false;
}

template <class F>
std::string input_error_message(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(PathgenSurfaceCleanup, DiagonalIsOneAndCentredAfterBothNormalizations) {
  const TriangleMesh m = transformed(bumpy_sphere(3), 7.3, rotation({1, 2, 3}, 0.7), {100, -5, 3});
  for (auto method : {SmoothingMethod::none, SmoothingMethod::implicit, SmoothingMethod::taubin, SmoothingMethod::pmp_default}) {
    SurfaceOptions o;
    o.smoothing = method;
    const SurfaceAnalysis s = analyze_surface(m, o);
    const Bounds b = bounds_of(s.positions);
    EXPECT_NEAR(b.diagonal(), 1.0, 1e-12) << to_string(method);
    EXPECT_LT(b.center().norm(), 1e-15) << to_string(method);
  }
}

TEST(PathgenSurfaceCleanup, NoneLeavesPositionsUntouchedAndScaleOffsetMapBack) {
  const TriangleMesh m = transformed(icosphere(3), 7.3, rotation({0, 1, 1}, 0.3), {100, -5, 3});
  const SurfaceAnalysis s = analyze_surface(m, no_smoothing());
  ASSERT_EQ(s.positions.size(), m.positions.size());
  const Bounds b = m.bounds();
  const Eigen::Vector3d c = (b.lo + b.hi) / 2.0;
  const double d = (b.hi - b.lo).norm();
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    // Exactly the §3 formula, bit for bit: `none` adds no second normalization.
    ASSERT_EQ(s.positions[v], ((m.positions[s.input_vertex[v]] - c) / d).eval());
    ASSERT_LT((s.scale * s.positions[v] + s.offset - m.positions[s.input_vertex[v]]).norm(), 1e-12 * d);
  }
  EXPECT_EQ(s.smoothing_dt, 0.0);
}

TEST(PathgenSurfaceCleanup, ScaleAndOffsetMapSmoothedPointsBackToModelUnits) {
  // Boundary vertices are held fixed by the implicit step, so mapping them back through both
  // normalizations must give their input coordinates.
  const TriangleMesh m = transformed(open_cylinder(0.2, 0.8, 32, 32), 3.0, rotation({1, 0, 0}, 0.2), {1, 2, 3});
  const SurfaceAnalysis s = analyze_surface(m, SurfaceOptions{});
  int boundary = 0;
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    const Eigen::Vector3d& input = m.positions[s.input_vertex[v]];
    const bool on_rim = std::abs(std::abs((rotation({1, 0, 0}, 0.2).transpose() * ((input - Eigen::Vector3d(1, 2, 3)) / 3.0)).y()) - 0.4) < 1e-9;
    if (!on_rim) continue;
    ++boundary;
    EXPECT_LT((s.scale * s.positions[v] + s.offset - input).norm(), 1e-12);
  }
  EXPECT_EQ(boundary, 64);
}

TEST(PathgenSurfaceCleanup, SmoothingKeepsBoundaryFixedAndPlaneFlat) {
  const TriangleMesh m = plane(16);
  const SurfaceAnalysis s = analyze_surface(m, SurfaceOptions{});
  EXPECT_GT(s.smoothing_dt, 0.0);
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    EXPECT_EQ(s.positions[v].z(), 0.0);
    const Eigen::Vector3d& input = m.positions[s.input_vertex[v]];
    if (std::abs(std::abs(input.x()) - 0.5) < 1e-12 || std::abs(std::abs(input.y()) - 0.5) < 1e-12) {
      EXPECT_LT((s.scale * s.positions[v] + s.offset - input).norm(), 1e-15);
    }
  }
  EXPECT_EQ(s.cleanup.boundary_edges, 64u);
  EXPECT_TRUE(s.cleanup_notes.empty());
}

TEST(PathgenSurfaceCleanup, TriangleSoupIsMergedIntoTheSameSurface) {
  const TriangleMesh welded = icosphere(3);
  const TriangleMesh stl = soup(welded);
  const SurfaceAnalysis a = analyze_surface(welded, SurfaceOptions{});
  const SurfaceAnalysis b = analyze_surface(stl, SurfaceOptions{});
  EXPECT_EQ(b.cleanup.merged_vertices, stl.positions.size() - welded.positions.size());
  EXPECT_TRUE(has_note_containing(b, "merged " + std::to_string(b.cleanup.merged_vertices) + " vertices"));
  EXPECT_EQ(b.positions.size(), welded.positions.size());
  EXPECT_EQ(b.cleanup.boundary_edges, 0u);
  EXPECT_EQ(b.patch_count, a.patch_count);
  EXPECT_EQ(b.orphans, a.orphans);
}

TEST(PathgenSurfaceCleanup, ScannerDefectsAreRepairedAndCounted) {
  TriangleMesh m = plane(4);  // 25 vertices, 32 faces
  const std::uint32_t n = static_cast<std::uint32_t>(m.positions.size());
  m.triangles.push_back({0, 0, 1});                  // repeated index: dropped
  m.triangles.push_back(m.triangles[5]);             // duplicate, same orientation: dropped
  m.triangles.push_back({m.triangles[7][0], m.triangles[7][2], m.triangles[7][1]});  // flipped duplicate: dropped
  m.positions.emplace_back(5.0, 5.0, 5.0);           // unreferenced: removed (not in the bounds)
  m.positions.emplace_back(0.25, 0.0, 0.3);          // a fin on interior edge (6,12): 3 faces on an edge
  m.triangles.push_back({6, 12, n + 1});             // non-manifold: split off
  m.positions.emplace_back(std::nan(""), 0.0, 0.0);  // NaN vertex
  m.triangles.push_back({0, 1, n + 2});              // dropped
  m.positions.emplace_back(0.5, -0.5, 0.0);          // duplicate of vertex 4 (a corner)
  m.positions.emplace_back(-0.5, -0.5, 0.0);         // duplicate of vertex 0
  m.positions.emplace_back(0.0, -0.5, 0.0);          // duplicate of vertex 2
  m.triangles.push_back({n + 3, n + 5, n + 4});      // collinear after merging: zero area, kept

  const SurfaceAnalysis s = analyze_surface(m, no_smoothing());
  EXPECT_EQ(s.cleanup.repeated_index_faces, 1u);
  EXPECT_EQ(s.cleanup.duplicate_faces, 2u);
  EXPECT_EQ(s.cleanup.non_finite_faces, 1u);
  EXPECT_EQ(s.cleanup.merged_vertices, 3u);
  EXPECT_EQ(s.cleanup.unreferenced_vertices, 2u);  // the far vertex and the NaN vertex
  EXPECT_EQ(s.cleanup.split_faces, 1u);
  EXPECT_EQ(s.cleanup.zero_area_faces, 1u);
  EXPECT_EQ(s.triangles.size(), 32u + 1u + 1u);
  EXPECT_EQ(s.positions.size(), 25u + 3u);  // 3 copies for the split face; its apex is used by nothing else
  EXPECT_EQ(s.cleanup.components, 2u);           // the split-off fin is a component of its own
  for (const char* text : {"dropped 1 degenerate face", "dropped 2 duplicate faces", "non-finite", "merged 3 vertices",
                           "removed 2 vertices", "split off 1 non-manifold face", "kept 1 face with zero area"})
    EXPECT_TRUE(has_note_containing(s, text)) << text;
  EXPECT_EQ(s.face_patch.size(), s.triangles.size());
  EXPECT_EQ(s.face_weight.size(), s.triangles.size());
  // input_face / input_vertex point back into the input arrays.
  for (std::size_t f = 0; f < s.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(m.positions[s.input_vertex[s.triangles[f][k]]], s.scale * s.positions[s.triangles[f][k]] + s.offset)
          << "face " << f;
}

TEST(PathgenSurfaceCleanup, FaceOrientedAgainstItsNeighboursIsSplitOff) {
  TriangleMesh m = plane(4);
  std::swap(m.triangles[10][1], m.triangles[10][2]);
  const SurfaceAnalysis s = analyze_surface(m, SurfaceOptions{});
  EXPECT_EQ(s.cleanup.split_faces, 1u);
  EXPECT_EQ(s.triangles.size(), m.triangles.size());
}

TEST(PathgenSurfaceCleanup, SeveralComponentsAreAnalysedTogether) {
  const TriangleMesh m = combined(icosphere(3), transformed(icosphere(3), 0.5, Eigen::Matrix3d::Identity(), {3, 0, 0}));
  SurfaceOptions o;
  o.tolerance = 1e9;  // every component is one patch
  const SurfaceAnalysis s = analyze_surface(m, o);
  EXPECT_EQ(s.cleanup.components, 2u);
  EXPECT_EQ(s.patch_count, 2);
  EXPECT_EQ(s.orphans, 0);
}

TEST(PathgenSurfaceCleanup, UnusableMeshesAreRejectedWithAClearMessage) {
  EXPECT_NE(input_error_message([] { analyze_surface(TriangleMesh{}, SurfaceOptions{}); }).find("no faces"), std::string::npos);
  TriangleMesh collinear;
  collinear.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  collinear.triangles = {{0, 1, 2}, {1, 3, 2}};
  EXPECT_NE(input_error_message([&] { analyze_surface(collinear, SurfaceOptions{}); }).find("no face with non-zero area"),
            std::string::npos);
  TriangleMesh point;
  point.positions = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  point.triangles = {{0, 1, 2}};
  EXPECT_NE(input_error_message([&] { analyze_surface(point, SurfaceOptions{}); }).find("no usable face"), std::string::npos);
  TriangleMesh broken = plane(2);
  broken.triangles.push_back({0, 1, 99});
  EXPECT_NE(input_error_message([&] { analyze_surface(broken, SurfaceOptions{}); }).find("refers to vertex 99"),
            std::string::npos);
}

TEST(PathgenSurfaceCleanup, OptionsAreValidatedAndParsed) {
  SurfaceOptions o;
  o.tolerance = 0.0;
  EXPECT_NE(input_error_message([&] { analyze_surface(plane(2), o); }).find("tolerance"), std::string::npos);
  o = {};
  o.smoothing_strength = -1.0;
  EXPECT_THROW(analyze_surface(plane(2), o), InputError);
  o = {};
  o.exact_normals.resize(3);
  EXPECT_THROW(analyze_surface(plane(2), o), InputError);
  o = {};
  o.tolerance = std::numeric_limits<double>::infinity();
  EXPECT_EQ(analyze_surface(plane(2), o).patch_count, 1);

  for (auto v : {SmoothingMethod::implicit, SmoothingMethod::none, SmoothingMethod::taubin, SmoothingMethod::pmp_default})
    EXPECT_EQ(parse_smoothing_method(to_string(v)), v);
  for (auto v : {WeightNeighbourhood::vertex_3_ring, WeightNeighbourhood::vertex_2_ring, WeightNeighbourhood::edge_2_ring})
    EXPECT_EQ(parse_weight_neighbourhood(to_string(v)), v);
  EXPECT_EQ(parse_leftover_mode("grow-leftovers"), LeftoverMode::grow);
  EXPECT_EQ(parse_seed_order("index"), SeedOrder::index);
  EXPECT_EQ(parse_face_samples("vertices"), FaceSamples::vertices);
  EXPECT_EQ(parse_curvature_fit("quadratic"), CurvatureFit::quadratic);
  EXPECT_NE(input_error_message([] { parse_smoothing_method("laplace"); }).find("implicit, none, taubin, pmp-default"),
            std::string::npos);
}

}  // namespace
}  // namespace meshtour
