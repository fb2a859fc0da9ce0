// §7 toroidal-patch decomposition: the exact and expected items of §17.5 and hand-checked cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "pathgen/curvature.h"
#include "pathgen/patches.h"
#include "pathgen/surface.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

using namespace test_meshes;


// Faces sharing an edge, computed here independently of the library's halfedge structure.
std::vector<std::vector<std::size_t>> edge_neighbours(const SurfaceAnalysis& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> by_edge;
  for (std::size_t f = 0; f < s.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) by_edge[std::minmax(s.triangles[f][k], s.triangles[f][(k + 1) % 3])].push_back(f);
  std::vector<std::vector<std::size_t>> out(s.triangles.size());
  for (const auto& [edge, faces] : by_edge)
    for (std::size_t a : faces)
      for (std::size_t b : faces)
        if (a != b) out[a].push_back(b);
  return out;
}

// The exact properties of §17.5 for any decomposition.
void check_decomposition(const SurfaceAnalysis& s, const SurfaceOptions& o) {
  const std::size_t F = s.triangles.size();
  ASSERT_EQ(s.face_patch.size(), F);
  ASSERT_EQ(static_cast<int>(s.patches.size()), s.patch_count);
  EXPECT_EQ(s.patch_count, s.grown_patches + s.single_face_patches);
  std::vector<int> size(s.patches.size(), 0);
  int orphans = 0;
  for (std::size_t f = 0; f < F; ++f) {
    const int p = s.face_patch[f];
    ASSERT_GE(p, -1);
    ASSERT_LT(p, s.patch_count);
    if (p < 0) {
      ++orphans;
      continue;
    }
    ++size[p];
    const auto& t = s.triangles[f];
    const PatchRecord& patch = s.patches[p];
    // The accuracy of a patch is checked where the test ran on these positions (I-33 tests other
    // positions), against ε in the normalized frame (I-34's unit times --tolerance).
    if (patch.accurate && !o.patches_on_unsmoothed) {
      const PatchTest test{o.face_samples, o.patch_measure, o.patch_normal_angle_deg};
      const double eps = o.tolerance * surface_detail::tolerance_unit_length(s.positions, o.tolerance_unit);
      ASSERT_LE(face_torus_distance(patch.torus, s.positions[t[0]], s.positions[t[1]], s.positions[t[2]], test), eps)
          << "face " << f << " patch " << p;
    }
  }
  EXPECT_EQ(orphans, s.orphans);
  int total = 0, largest = 0;
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    EXPECT_EQ(size[p], s.patches[p].face_count) << "patch " << p;
    EXPECT_GE(size[p], 1);
    total += size[p];
    largest = std::max(largest, size[p]);
    // The patch torus is the osculating torus of its seed vertex.
    const Torus& t = s.vertex_torus[s.patches[p].seed_vertex];
    EXPECT_EQ(t.center, s.patches[p].torus.center);
    EXPECT_EQ(t.major_radius, s.patches[p].torus.major_radius);
    if (s.patches[p].kind == PatchRecord::Kind::single && o.leftovers == LeftoverMode::single) {
      EXPECT_EQ(size[p], 1);
    }
  }
  EXPECT_EQ(total + orphans, static_cast<int>(F));
  EXPECT_EQ(largest, s.largest_patch);
  EXPECT_EQ(static_cast<int>(std::count_if(s.patches.begin(), s.patches.end(),
                                           [](const PatchRecord& p) { return p.kind == PatchRecord::Kind::grown; })),
            s.grown_patches);

  // Every grown patch is connected over shared edges, or through its seed vertex: each edge-
  // connected piece holds a face incident to the seed.
  const auto adjacent = edge_neighbours(s);
  std::vector<int> piece(F, -1);
  for (std::size_t start = 0; start < F; ++start) {
    const int p = s.face_patch[start];
    if (p < 0 || piece[start] >= 0 || s.patches[p].kind != PatchRecord::Kind::grown) continue;
    std::vector<std::size_t> stack{start};
    piece[start] = static_cast<int>(start);
    bool touches_seed = false;
    while (!stack.empty()) {
      const std::size_t f = stack.back();
      stack.pop_back();
      for (std::uint32_t v : s.triangles[f]) touches_seed |= v == s.patches[p].seed_vertex;
      for (std::size_t g : adjacent[f])
        if (s.face_patch[g] == p && piece[g] < 0) {
          piece[g] = static_cast<int>(start);
          stack.push_back(g);
        }
    }
    EXPECT_TRUE(touches_seed) << "a piece of grown patch " << p << " is cut off from its seed";
  }
}

// Exact differential data of the unit sphere for icosphere(level), in normalized units.
std::vector<VertexDifferential> sphere_data(const TriangleMesh& m) {
  const double d = m.bounds().diagonal();
  std::vector<VertexDifferential> data;
  for (const auto& p : m.positions) {
    VertexDifferential v;
    v.normal = p.normalized();
    std::tie(v.t1, v.t2) = surface_detail::tangent_frame(v.normal);
    v.k1 = v.k2 = -d;  // radius 1/d after normalization, outward normal: negative
    data.push_back(v);
  }
  return data;
}

TEST(PathgenSurfacePatches, DecompositionInvariantsHoldForEveryOption) {
  const TriangleMesh m = bumpy_sphere(4, 0.002);
  std::vector<SurfaceOptions> variants(11);
  variants[1].face_samples = FaceSamples::vertices;
  variants[2].seed_order = SeedOrder::index;
  variants[3].leftovers = LeftoverMode::grow;
  variants[4].keep_inaccurate_patches = true;
  variants[4].tolerance = 1e-4;
  variants[5].smoothing = SmoothingMethod::none;
  variants[5].tolerance = 1e-4;
  // The patch-test hypotheses of docs/FIDELITY.md (I-30..I-34).
  variants[6].patch_measure = PatchMeasure::algebraic;
  variants[7].patch_measure = PatchMeasure::algebraic_normalized;
  variants[8].patch_normal_angle_deg = 10.0;
  variants[8].face_samples = FaceSamples::edges4;
  variants[9].patches_on_unsmoothed = true;
  variants[10].tolerance_unit = ToleranceUnit::diagonal;  // the specification's unit
  for (std::size_t i = 0; i < variants.size(); ++i) {
    SCOPED_TRACE("variant " + std::to_string(i));
    const SurfaceAnalysis s = analyze_surface(m, variants[i]);
    check_decomposition(s, variants[i]);
    if (i == 4) {
      EXPECT_EQ(s.orphans, 0);
    }
    if (i == 5) {
      EXPECT_GT(s.orphans, 0);
    }
  }
}

TEST(PathgenSurfacePatches, InfiniteToleranceMakesOnePatchPerComponent) {
  SurfaceOptions o;
  o.tolerance = 1e9;
  const SurfaceAnalysis s = analyze_surface(combined(plane(8), transformed(bumpy_sphere(2), 0.3, Eigen::Matrix3d::Identity(), {2, 0, 0})), o);
  EXPECT_EQ(s.patch_count, 2);
  EXPECT_EQ(s.grown_patches, 2);
  EXPECT_EQ(s.orphans, 0);
  check_decomposition(s, o);
}

TEST(PathgenSurfacePatches, AnalyticSphereDataCoversTheSphereFromAnySeed) {
  const TriangleMesh m = icosphere(4);
  SurfaceOptions o = no_smoothing();
  o.exact_differential = sphere_data(m);
  for (std::uint32_t seed : {0u, 17u, 1234u, 2561u}) {
    o.seed_vertices = {seed};
    const SurfaceAnalysis s = analyze_surface(m, o);
    EXPECT_EQ(s.patch_count, 1) << "seed " << seed;
    EXPECT_EQ(s.largest_patch, static_cast<int>(m.triangles.size()));
    EXPECT_EQ(s.input_vertex[s.patches.at(0).seed_vertex], seed);
  }
}

TEST(PathgenSurfacePatches, AnalyticTorusDataFromAnOuterEquatorSeedCoversTheTorus) {
  const double R = 0.3, r = 0.1;
  const int nu = 192, nv = 64;
  const TriangleMesh m = test_meshes::torus(R, r, nu, nv);
  const double d = m.bounds().diagonal();
  std::vector<VertexDifferential> data;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      VertexDifferential x;
      x.normal = Eigen::Vector3d(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      x.t1 = Eigen::Vector3d(-std::sin(u), std::cos(u), 0.0);                                      // along the latitude
      x.t2 = Eigen::Vector3d(-std::sin(v) * std::cos(u), -std::sin(v) * std::sin(u), std::cos(v));  // along the meridian
      x.k1 = -std::cos(v) / (R + r * std::cos(v)) * d;
      x.k2 = -1.0 / r * d;
      data.push_back(x);
    }
  SurfaceOptions o = no_smoothing();
  o.exact_differential = data;
  o.seed_vertices = {static_cast<std::uint32_t>(37 * nv)};  // (i, j) = (37, 0): outer equator
  const SurfaceAnalysis s = analyze_surface(m, o);
  EXPECT_EQ(s.patch_count, 1);
  EXPECT_EQ(s.largest_patch, nu * nv * 2);
  // The torus of an outer-equator vertex is the torus itself (hand-checked: C = 0, axis ±Z,
  // R_T = R, r_T = r in normalized units).
  const Torus& t = s.patches.at(0).torus;
  EXPECT_NEAR(t.major_radius, R / d, 1e-12);
  EXPECT_NEAR(t.minor_radius, r / d, 1e-12);
  EXPECT_NEAR(std::abs(t.axis.z()), 1.0, 1e-12);
  EXPECT_LT((s.scale * t.center + s.offset).norm(), 1e-12);
}

TEST(PathgenSurfacePatches, ExpectedCountsOnCleanSurfacesWithoutSmoothing) {
  EXPECT_EQ(analyze_surface(icosphere(5), no_smoothing()).patch_count, 1);
  EXPECT_EQ(analyze_surface(test_meshes::torus(), no_smoothing()).patch_count, 1);
  EXPECT_EQ(analyze_surface(open_cylinder(), no_smoothing()).patch_count, 1);
  EXPECT_EQ(analyze_surface(plane(64), no_smoothing()).patch_count, 1);
  const SurfaceAnalysis l4 = analyze_surface(icosphere(4), no_smoothing());
  // §17.5: "T ≈ 17 (a few large patches plus small ones)"; §17.8: faithful implementations agree
  // exactly on T, and this one gives 17.
  EXPECT_EQ(l4.patch_count, 17);
  EXPECT_GE(l4.largest_patch, 500);
  RecordProperty("icosphere4_T", l4.patch_count);
  check_decomposition(l4, no_smoothing());
}

TEST(PathgenSurfacePatches, CleanSurfacesStayOnePatchWithDefaultSmoothing) {
  EXPECT_EQ(analyze_surface(icosphere(5), specification_units()).patch_count, 1);
  EXPECT_EQ(analyze_surface(plane(64), specification_units()).patch_count, 1);
}

TEST(PathgenSurfacePatches, PatchesPlusOrphansDoNotIncreaseWithTheTolerance) {
  const TriangleMesh m = bumpy_sphere(5);
  int previous = std::numeric_limits<int>::max();
  for (double eps : {1e-4, 1e-3, 1e-2}) {
    SurfaceOptions o = no_smoothing();
    o.tolerance = eps;
    const SurfaceAnalysis s = analyze_surface(m, o);
    EXPECT_LE(s.patch_count + s.orphans, previous) << "eps " << eps;
    previous = s.patch_count + s.orphans;
  }
}

// I-34: a tolerance in another unit is the same test as the diagonal-unit tolerance scaled by that
// unit's length (normalization is a similarity, so the ratio can be taken on the input).
TEST(PathgenSurfacePatches, ToleranceUnitScalesEpsilonByTheBoxSide) {
  const TriangleMesh m = bumpy_sphere(4, 0.002);
  const Bounds b = m.bounds();
  const double side = (b.hi - b.lo).maxCoeff() / b.diagonal();
  SurfaceOptions half = no_smoothing(), extent = no_smoothing(), plain_half = no_smoothing(), plain_extent = no_smoothing();
  half.tolerance_unit = ToleranceUnit::box_half_extent;
  extent.tolerance_unit = ToleranceUnit::box_extent;
  plain_half.tolerance_unit = plain_extent.tolerance_unit = ToleranceUnit::diagonal;
  plain_half.tolerance = 1e-3 * side / 2.0;
  plain_extent.tolerance = 1e-3 * side;
  const SurfaceAnalysis h = analyze_surface(m, half), e = analyze_surface(m, extent);
  EXPECT_EQ(h.face_patch, analyze_surface(m, plain_half).face_patch);
  EXPECT_EQ(e.face_patch, analyze_surface(m, plain_extent).face_patch);
  // A smaller effective tolerance: more patches plus orphans (§7 is monotone in ε on this surface).
  EXPECT_GT(h.patch_count + h.orphans, e.patch_count + e.orphans);
}

// I-30: the three sample measures at a point δ outside the tube of a torus (minor radius r).
TEST(PathgenSurfacePatches, PatchMeasuresOfAPointOutsideTheTube) {
  Torus t;
  t.center = Eigen::Vector3d::Zero();
  t.axis = Eigen::Vector3d::UnitZ();
  t.major_radius = 2.0;
  t.minor_radius = 0.5;
  const double delta = 0.1;
  const Eigen::Vector3d q(2.0 + 0.5 + delta, 0.0, 0.0);
  EXPECT_NEAR(point_torus_measure(t, q, PatchMeasure::geometric), 0.1, 1e-12);
  EXPECT_NEAR(point_torus_measure(t, q, PatchMeasure::algebraic), 0.6 * 0.6 - 0.25, 1e-12);          // 0.11
  EXPECT_NEAR(point_torus_measure(t, q, PatchMeasure::algebraic_normalized), 0.11 / 1.2, 1e-12);  // ≈ 0.0917
}

TEST(PathgenSurfacePatches, BumpySphereHasAFewPercentPatchesAndNoOrphans) {
  const SurfaceAnalysis clean = analyze_surface(bumpy_sphere(5), specification_units());
  const double F = static_cast<double>(clean.triangles.size());
  EXPECT_GE(clean.patch_count / F, 0.005);
  EXPECT_LE(clean.patch_count / F, 0.05);
  EXPECT_GE(clean.single_face_patches, 50);
  EXPECT_LE(clean.single_face_patches, 999);
  EXPECT_EQ(clean.orphans, 0);
  const SurfaceAnalysis noisy = analyze_surface(bumpy_sphere(5, 0.002), specification_units());
  EXPECT_GT(noisy.patch_count, clean.patch_count);
  EXPECT_LE(noisy.patch_count / F, 0.08);
  RecordProperty("bumpy_T", clean.patch_count);
  RecordProperty("bumpy_noisy_T", noisy.patch_count);
}

TEST(PathgenSurfacePatches, HandCheckedToleranceBelowEverythingLeavesOnlyOrphans) {
  // Flat data on a plane: every vertex torus is the sphere of radius 1/κ_min tangent there.
  // Every face has a sample away from any one vertex, at a distance of ≥ s²/(2·10⁶) > 0 from that
  // sphere, so with ε = 1e-300 no face fits any torus: T = 0, every face an orphan; keeping the
  // inaccurate patches instead gives every face its own single patch.
  const TriangleMesh m = plane(6);
  SurfaceOptions o = no_smoothing();
  o.tolerance = 1e-300;
  const SurfaceAnalysis s = analyze_surface(m, o);
  EXPECT_EQ(s.patch_count, 0);
  EXPECT_EQ(s.orphans, 72);
  for (double w : s.face_weight) EXPECT_EQ(w, 0.0);
  o.keep_inaccurate_patches = true;
  const SurfaceAnalysis k = analyze_surface(m, o);
  EXPECT_EQ(k.patch_count, 72);
  EXPECT_EQ(k.single_face_patches, 72);
  EXPECT_EQ(k.orphans, 0);
  // Phase-B ids follow ascending face order.
  for (int f = 0; f < 72; ++f) EXPECT_EQ(k.face_patch[f], f);
  check_decomposition(k, o);
}

TEST(PathgenSurfacePatches, HandCheckedSeedRuleAndGrowthOnAStrip) {
  // A strip of 4 faces in the plane z = 0, vertices 0..4 along the bottom edge (y = 0) and
  // 5..9 along the top (y = 0.1). Data: flat (clamped to a sphere of radius 10⁶), except vertex 2
  // whose normal is tilted by 90° (its torus stands across the strip, so only faces through it fit).
  TriangleMesh m;
  for (int row = 0; row < 2; ++row)
    for (int i = 0; i < 5; ++i) m.positions.emplace_back(0.1 * i, 0.1 * row, 0.0);
  for (std::uint32_t i = 0; i < 4; ++i) {
    m.triangles.push_back({i, i + 1, i + 6});
    m.triangles.push_back({i, i + 6, i + 5});
  }
  SurfaceOptions o = no_smoothing();
  o.exact_differential.resize(10);
  o.exact_differential[2].normal = Eigen::Vector3d::UnitX();
  o.exact_differential[2].t1 = Eigen::Vector3d::UnitY();
  o.exact_differential[2].t2 = Eigen::Vector3d::UnitZ();
  // Seeding at the tilted vertex first: its torus is a sphere tangent to the plane x = 0.2, which
  // every face at vertex 2 leaves by ≥ 0.1 (model units) at its other corners, so it starts no
  // patch; the next seed, vertex 0, grows over the whole strip (flat faces sag ≤ 10⁻⁶ from its
  // sphere of radius 10⁶).
  o.seed_vertices = {2, 0};
  const SurfaceAnalysis s = analyze_surface(m, o);
  EXPECT_EQ(s.patch_count, 1);
  EXPECT_EQ(s.grown_patches, 1);
  EXPECT_EQ(s.largest_patch, 8);
  EXPECT_EQ(s.input_vertex[s.patches[0].seed_vertex], 0u);
  // A seed whose faces are already covered is skipped: seeds {0, 1} give one patch.
  o.seed_vertices = {0, 1};
  EXPECT_EQ(analyze_surface(m, o).patch_count, 1);
  // With only vertex 2 as a seed nothing grows, and Phase B gives every face the best torus of its
  // three vertices (a flat one, exact within ε): 8 single patches in face order.
  o.seed_vertices = {2};
  const SurfaceAnalysis b = analyze_surface(m, o);
  EXPECT_EQ(b.grown_patches, 0);
  EXPECT_EQ(b.single_face_patches, 8);
  for (int f = 0; f < 8; ++f) EXPECT_NE(b.input_vertex[b.patches[b.face_patch[f]].seed_vertex], 2u);
  // grow-leftovers: the first leftover face grows over everything.
  o.leftovers = LeftoverMode::grow;
  const SurfaceAnalysis g = analyze_surface(m, o);
  EXPECT_EQ(g.patch_count, 1);
  EXPECT_EQ(g.largest_patch, 8);
}

}  // namespace
}  // namespace meshtour
