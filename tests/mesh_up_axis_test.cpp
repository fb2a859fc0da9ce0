// --up auto (mesh/up_axis.h): the rule on the shared meshes, on the same meshes turned so that
// their up is another axis (the rule must turn with them), and on procedural shapes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <tbb/global_control.h>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "helpers.h"
#include "mesh/mesh.h"
#include "core/error.h"
#include "mesh/up_axis.h"

namespace meshtour {
namespace {

// A proper rotation that is a signed permutation (exact in floating point) taking `from` to `to`.
Eigen::Matrix3d axis_rotation(const Axis& from, const Axis& to) {
  Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(from.vector(), to.vector()).toRotationMatrix();
  if (from.index == to.index && from.negative != to.negative)  // half turn about another axis
    r = Eigen::AngleAxisd(EIGEN_PI, Eigen::Vector3d::Unit((from.index + 1) % 3)).toRotationMatrix();
  return r.array().round().matrix();
}

TriangleMesh rotated(const TriangleMesh& mesh, const Eigen::Matrix3d& r) {
  TriangleMesh out = mesh;
  for (Eigen::Vector3d& p : out.positions) p = r * p;
  return out;
}

void print_rests(const std::string& name, const UpChoice& c) {
  std::printf("%-14s", name.c_str());
  for (const UpRest& r : c.rests)
    std::printf(" %s: %.3f (rest %.3f a %.2f m %+.2f h %.2f flat %.2f/%.2f)", r.up.name().c_str(), r.score, r.rest, r.support_area,
                r.margin, r.centroid_height, r.flat_base, r.flat_top);
  std::printf("  mirror x %.2f y %.2f z %.2f -> %s%s (margin %.3g)\n", c.symmetry[0], c.symmetry[1], c.symmetry[2],
              c.up.name().c_str(), c.confident ? "" : " (not confident)", c.margin);
}

struct Documented {
  const char* file;
  const char* up;       // meshes.tsv's up axis
  bool rule_finds_it;   // whether the rule finds it (see below)
};
// The rule finds the documented up of the animals that stand on their feet (a firm rest, and the
// kitten's and bunny's flat bases), and of the Venus head by its sawn neck: a rough cut tilted
// 22 degrees from -z that no axis rests on and no thin slab sees as flat, found on the coarse
// proxy as a flat region bounded by a crease (mesh/up_axis.cpp, kCutProxyCells). The bear
// (upright on one hind leg: no side rests stably, no flat sole or cut, no clear plane of
// symmetry) gives no side a clear lead, so the rule keeps +y and says it is not confident: right
// by convention only. The rocker arm has no natural up (+y is a convention; the rule lays it on
// its widest flank, +x). Every mesh is turned so that its up is each of the six axes: the rule
// must turn with it, and where it does not find the up it must never be confident.
constexpr Documented kShared[] = {{"horse.ply", "+y", true},     {"kitten.ply", "+y", true}, {"bunny.ply", "+y", true},
                                  {"armadillo.ply", "+y", true}, {"bear.ply", "+y", false},  {"venus.ply", "+z", true},
                                  {"rocker.ply", "+y", false}};

// The side of `turned` that `side` of the original became under the signed permutation `r`.
const UpRest& turned_side(const UpChoice& turned, const Eigen::Matrix3d& r, const Axis& side) {
  const Eigen::Vector3d v = r * side.vector();
  const int index = v.cwiseAbs().maxCoeff() == std::abs(v.x()) ? 0 : v.cwiseAbs().maxCoeff() == std::abs(v.y()) ? 1 : 2;
  return turned.rests[static_cast<std::size_t>(2 * index + (v[index] < 0.0 ? 1 : 0))];
}

constexpr Axis kAllAxes[] = {Axis{0, false}, Axis{0, true}, Axis{1, false}, Axis{1, true}, Axis{2, false}, Axis{2, true}};

// The command that prints the table of the report: test_mesh --gtest_filter='UpAxis.*'.
TEST(UpAxis, SharedMeshesAndTheirRotations) {
  for (const Documented& d : kShared) {
    MESHTOUR_SHARED_MESH(path, d.file);
    const TriangleMesh mesh = load_mesh(path);
    const UpChoice choice = choose_up_axis(mesh);
    print_rests(d.file, choice);
    const Axis up = Axis::parse(d.up);
    if (d.rule_finds_it) {
      EXPECT_EQ(choice.up.name(), up.name()) << d.file << ": " << choice.reason;
      EXPECT_TRUE(choice.confident) << d.file << ": " << choice.reason;
    } else if (std::string(d.file) != "rocker.ply") {
      EXPECT_FALSE(choice.confident) << d.file << ": " << choice.reason;
      EXPECT_EQ(choice.up.name(), "+y");
    }
    // Turned so that its up is another axis, every side's score turns with it (the rests and flat
    // ends exactly; the mirror test on a grid over the turned box), so the same choice.
    for (const Axis to : kAllAxes) {
      const Eigen::Matrix3d r = axis_rotation(up, to);
      const UpChoice turned = choose_up_axis(rotated(mesh, r));
      std::printf("  %s turned to %s -> %s%s (margin %.3g)\n", d.file, to.name().c_str(), turned.up.name().c_str(),
                  turned.confident ? "" : " (not confident)", turned.margin);
      for (const UpRest& rest : choice.rests) {
        const UpRest& same = turned_side(turned, r, rest.up);
        EXPECT_NEAR(same.score, rest.score, 1e-9) << d.file << " turned to " << to.name() << ", side " << rest.up.name();
        // The air under it, on a grid of columns over the turned box (a scan's tiny triangles fall
        // in the column of their centre, which can move by one at a column's edge).
        EXPECT_NEAR(same.trapped_air, rest.trapped_air, 0.005) << d.file << " turned to " << to.name() << ", side " << rest.up.name();
        EXPECT_NEAR(same.clearance, rest.clearance, 0.01) << d.file << " turned to " << to.name() << ", side " << rest.up.name();
      }
      if (d.rule_finds_it) {
        EXPECT_EQ(turned.up.name(), to.name()) << d.file << " turned to " << to.name() << ": " << turned.reason;
      } else if (std::string(d.file) != "rocker.ply") {
        EXPECT_FALSE(turned.confident) << d.file << " turned to " << to.name() << ": " << turned.reason;
      }
    }
  }
}

// Procedural shapes: boxes, spheres and frustums with outward normals.
struct Builder {
  TriangleMesh mesh;
  std::uint32_t vertex(const Eigen::Vector3d& p) {
    mesh.positions.push_back(p);
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  }
  void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (int i = 0; i < 8; ++i) vertex({i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()});
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
      mesh.triangles.push_back({base + q[0], base + q[1], base + q[2]});
      mesh.triangles.push_back({base + q[0], base + q[2], base + q[3]});
    }
  }
  // A surface of revolution about +y through `centre`: radius(t) at height y(t), t in [0, 1] from
  // bottom to top, closed by flat caps where the radius is not 0 (left open unless `capped`).
  template <class Radius, class Height>
  void revolution(const Eigen::Vector3d& centre, Radius radius, Height height, int rings = 24, int segments = 48, bool capped = true) {
    std::vector<std::uint32_t> ring_start;
    for (int i = 0; i <= rings; ++i) {
      const double t = static_cast<double>(i) / rings;
      ring_start.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      for (int j = 0; j < segments; ++j) {
        const double a = 2.0 * EIGEN_PI * j / segments;
        vertex(centre + Eigen::Vector3d(radius(t) * std::cos(a), height(t), -radius(t) * std::sin(a)));
      }
    }
    const auto at = [&](int i, int j) { return ring_start[static_cast<std::size_t>(i)] + static_cast<std::uint32_t>(j % segments); };
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < segments; ++j) {
        mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
        mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      }
    for (const int i : {0, rings}) {
      const double t = i == 0 ? 0.0 : 1.0;
      if (radius(t) <= 0.0 || !capped) continue;
      const std::uint32_t c = vertex(centre + Eigen::Vector3d(0.0, height(t), 0.0));
      for (int j = 0; j < segments; ++j)
        if (i == 0) mesh.triangles.push_back({c, at(i, j + 1), at(i, j)});
        else mesh.triangles.push_back({c, at(i, j), at(i, j + 1)});
    }
  }
  // A closed lathe-turned solid about +y: the profile (radius, height) runs from the centre of
  // the bottom out, up the outside, over the rim and down the inside to the centre of the inner
  // bottom (both ends at radius 0), as a potter's wheel turns a vessel with walls.
  // With `capped` false, ends off the axis stay open (a scan's holes).
  void lathe(const std::vector<Eigen::Vector2d>& profile, int segments = 64, bool capped = true) {
    const int n = static_cast<int>(profile.size()) - 1;
    const auto at = [&](double t) { return profile[static_cast<std::size_t>(std::lround(t * n))]; };
    revolution({0.0, 0.0, 0.0}, [&](double t) { return at(t).x(); }, [&](double t) { return at(t).y(); }, n, segments, capped);
  }
  void sphere(const Eigen::Vector3d& centre, double r, int rings = 24, int segments = 48) {
    revolution(centre, [r](double t) { return r * std::sin(EIGEN_PI * t); }, [r](double t) { return -r * std::cos(EIGEN_PI * t); },
               rings, segments);
  }
  void frustum(const Eigen::Vector3d& base_centre, double r_bottom, double r_top, double h) {
    revolution(base_centre, [=](double t) { return r_bottom + (r_top - r_bottom) * t; }, [h](double t) { return h * t; }, 1);
  }
};

// A shape must give its up back in all six orientations, confidently.
void expect_found_in_every_orientation(const std::string& name, const TriangleMesh& mesh, const Axis& up) {
  for (const Axis to : kAllAxes) {
    const UpChoice c = choose_up_axis(rotated(mesh, axis_rotation(up, to)));
    if (to == up) print_rests(name, c);
    EXPECT_EQ(c.up.name(), to.name()) << name << " turned to " << to.name() << ": " << c.reason;
    EXPECT_TRUE(c.confident) << name << " turned to " << to.name() << ": " << c.reason;
  }
}

// A bust: a head (sphere) on a truncated cone cut flat at the chest. The cut is a flat base much
// smaller than the head's footprint; it stands on it.
TEST(UpAxis, BustOnItsCut) {
  Builder b;
  b.frustum({0.0, 0.0, 0.0}, 0.6, 0.35, 0.9);
  b.sphere({0.0, 1.55, 0.0}, 0.75);
  b.box({-0.08, 1.4, 0.7}, {0.08, 1.6, 0.9});  // a nose: the bust faces +z
  expect_found_in_every_orientation("bust", b.mesh, (Axis{1, false}));
}

// A head on a neck sawn off at a slant (a marble head broken from its statue, as the Venus and
// Igea heads): the cut is tilted 20 degrees towards the back, so no axis rests on it and no thin
// slab at an end sees it flat, and the head rests on no side. The flat cut, seen on the coarse
// proxy, decides: it faces down and back, nearest to -y.
TEST(UpAxis, HeadOnASlantedCut) {
  const auto head = [](bool neck) {
    Builder b;
    b.sphere({0.0, 0.0, 0.0}, 1.0, 48, 96);
    b.box({-0.08, 0.0, 0.9}, {0.08, 0.2, 1.1});  // a nose: the head faces +z
    if (neck) {
      const auto first = static_cast<std::uint32_t>(b.mesh.positions.size());
      b.frustum({0.0, -1.5, 0.0}, 0.45, 0.45, 0.9);
      const double slope = std::tan(20.0 * EIGEN_PI / 180.0);
      for (std::size_t v = first; v < b.mesh.positions.size(); ++v)  // the bottom ring and cap onto the slanted cut
        if (Eigen::Vector3d& p = b.mesh.positions[v]; p.y() < -1.0) p.y() = -1.5 - slope * p.z();
    }
    return b.mesh;
  };
  const TriangleMesh bust = head(true);
  const UpChoice c = choose_up_axis(bust);
  print_rests("head on a cut", c);
  EXPECT_GT(c.cut_share, 0.03) << c.reason;
  EXPECT_NE(c.reason.find("flat cut on its -y side"), std::string::npos) << c.reason;
  expect_found_in_every_orientation("head on a slanted cut", bust, (Axis{1, false}));
  // As glTF it keeps +y by the specification, and a z-up export is not turned by so weak a cue:
  // its cut says +z, but it scores far below a firm rest.
  const UpChoice z_up = choose_up_axis(rotated(bust, axis_rotation(Axis{1, false}, Axis{2, false})), "head.glb");
  EXPECT_EQ(z_up.up.name(), "+y") << z_up.reason;
  EXPECT_TRUE(z_up.warning.empty()) << z_up.warning;
  // The head without its neck: no side and no cut decides, so +y, not confident, in every orientation.
  const TriangleMesh ball = head(false);
  for (const Axis to : kAllAxes) {
    const UpChoice round = choose_up_axis(rotated(ball, axis_rotation(Axis{1, false}, to)));
    EXPECT_FALSE(round.confident) << round.reason;
    EXPECT_EQ(round.cut_share, 0.0);
  }
}

// A mask: a face a third as deep as it is tall, its back flattened on a plane tilted 20 degrees
// (a wearable mask's brow band, a relief's or a plaque's back, made to lie on a face or hang on a
// wall). The flat back looks like a head's sawn neck to the cut rule, but a bust stands on its cut
// at least half as tall as its size (kCutThickness) and a mask is thin there: its back tells its
// front, not its up. Before that bound, the rule stood this mask on its back in three of its six
// orientations (and the Lynx mask of dome-experiments in four).
TEST(UpAxis, MaskIsNotStoodOnItsFlatBack) {
  Builder b;
  b.sphere({0.0, 0.0, 0.0}, 1.0, 48, 96);
  const double slope = std::tan(20.0 * EIGEN_PI / 180.0);
  for (Eigen::Vector3d& p : b.mesh.positions) {
    p.x() *= 0.8;
    p.z() *= 0.45;
    p.z() = std::max(p.z(), -0.12 - slope * p.y());  // the back, down to a plane facing back and down
  }
  b.box({-0.08, -0.1, 0.4}, {0.08, 0.15, 0.55});  // a nose: the mask faces +z
  const UpChoice c = choose_up_axis(b.mesh);
  print_rests("mask", c);
  EXPECT_EQ(c.cut_share, 0.0) << c.reason;
  for (const Axis to : kAllAxes) {  // turned so that its up is `to`: never stood on its back
    const Eigen::Matrix3d r = axis_rotation(Axis{1, false}, to);
    const UpChoice turned = choose_up_axis(rotated(b.mesh, r));
    const Eigen::Vector3d front = r * Eigen::Vector3d::UnitZ();
    EXPECT_FALSE(turned.confident && turned.up.vector().isApprox(front)) << "up " << to.name() << ": " << turned.reason;
  }
}

// An open end is flat surface at the end it faces only where a flat triangle would be: facing
// within kFlatAngle of the axis. A ball open at its bottom (a scan's open neck or underside)
// stands on its opening in every orientation. Turned 25 degrees off the axis, the opening is no
// base of any axis, and the ball rests on no side: not confident. Before, the cap counted its
// shadow on every axis, and a lion's head scan open at its throat 27 degrees off its back stood on
// its throat, confidently, in all six orientations.
TEST(UpAxis, OpenEndIsABaseOnlyFacingAnAxis) {
  const auto open_ball = [](double tilt_deg) {
    Builder b;
    const double from = 1.0 / 6.0;  // the opening: 30 degrees around the bottom pole
    const auto angle = [from](double t) { return EIGEN_PI * (from + (1.0 - from) * t); };
    b.revolution({0.0, 0.0, 0.0}, [&](double t) { return std::sin(angle(t)); }, [&](double t) { return -std::cos(angle(t)); }, 24, 48, false);
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(tilt_deg * EIGEN_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return rotated(b.mesh, tilt);
  };
  expect_found_in_every_orientation("ball open at its foot", open_ball(0.0), (Axis{1, false}));
  const TriangleMesh tilted = open_ball(25.0);
  print_rests("tilted opening", choose_up_axis(tilted));
  for (const Axis to : kAllAxes) {
    const UpChoice c = choose_up_axis(rotated(tilted, axis_rotation(Axis{1, false}, to)));
    EXPECT_FALSE(c.confident) << "turned to " << to.name() << ": " << c.reason;
  }
}

// A column whose capital is the same disc as its base rests as firmly on either end, and
// nothing tells up from down: +y, not confident, in every orientation. The flat-cut rule may
// break a tie between two firm ends only where its cut's end is clearly the flatter
// (kConfidentRatio), as a vase's foot is against its mouth's rim; between ends alike it tossed a
// coin: it stood this column on one end, confidently, and a column scan (kTDS Column03, flat ends
// 0.83 and 0.76 of its footprint) on its capital in two of its six orientations.
TEST(UpAxis, ColumnWithEndsAlikeIsNotTurnedByACut) {
  Builder b;
  b.frustum({0.0, 0.0, 0.0}, 0.5, 0.5, 0.2);   // the base
  b.frustum({0.0, 0.2, 0.0}, 0.3, 0.3, 2.0);   // the shaft
  b.frustum({0.0, 2.2, 0.0}, 0.5, 0.5, 0.2);   // the capital
  for (const Axis to : kAllAxes) {
    const UpChoice c = choose_up_axis(rotated(b.mesh, axis_rotation(Axis{1, false}, to)));
    if (to.index == 1 && !to.negative) print_rests("column", c);
    EXPECT_FALSE(c.confident) << "turned to " << to.name() << ": " << c.reason;
    EXPECT_EQ(c.cut_share, 0.0) << "turned to " << to.name() << ": " << c.reason;
  }
}

// A standing figure: legs and feet, a body, arms held out, a head and a nose. No side rests firmly wider
// than its feet, but the soles are flat and the head is round; its plane of symmetry (x = 0) is
// found and x is never up.
TEST(UpAxis, StandingFigure) {
  Builder b;
  b.box({-0.35, 0.0, -0.15}, {-0.1, 0.9, 0.2});  // legs, soles at y = 0
  b.box({0.1, 0.0, -0.15}, {0.35, 0.9, 0.2});
  b.box({-0.35, 0.0, 0.2}, {-0.1, 0.12, 0.5});   // feet, pointing to +z
  b.box({0.1, 0.0, 0.2}, {0.35, 0.12, 0.5});
  b.box({-0.4, 0.9, -0.2}, {0.4, 1.8, 0.2});     // body
  b.box({-1.1, 1.6, -0.1}, {-0.4, 1.75, 0.1});   // arms
  b.box({0.4, 1.6, -0.1}, {1.1, 1.75, 0.1});
  b.sphere({0.0, 2.1, 0.0}, 0.3);                // head
  b.box({-0.05, 2.05, 0.25}, {0.05, 2.15, 0.4});  // nose: facing +z
  const UpChoice c = choose_up_axis(b.mesh);
  EXPECT_EQ(c.symmetry_normal, 0) << "mirror x " << c.symmetry[0] << " y " << c.symmetry[1] << " z " << c.symmetry[2];
  expect_found_in_every_orientation("figure", b.mesh, (Axis{1, false}));
}

// A box on a wider plinth: it stands on the plinth, whichever axis is up.
TEST(UpAxis, BoxOnPlinth) {
  Builder b;
  b.box({-1.0, 0.0, -1.0}, {1.0, 0.3, 1.0});  // plinth
  b.box({-0.4, 0.3, -0.4}, {0.4, 2.0, 0.4});  // tall box on it
  expect_found_in_every_orientation("plinth", b.mesh, (Axis{1, false}));
}

// glTF is +y up by its specification: the shape overrides that only when it clearly disagrees,
// and then says so.
TEST(UpAxis, GltfKeepsItsUpUnlessTheShapeClearlyDisagrees) {
  Builder b;
  b.box({-1.0, 0.0, -1.0}, {1.0, 0.3, 1.0});
  b.box({-0.4, 0.3, -0.4}, {0.4, 2.0, 0.4});
  EXPECT_EQ(format_up_axis("a/model.glb"), (Axis{1, false}));
  EXPECT_EQ(format_up_axis("model.GLTF"), (Axis{1, false}));
  EXPECT_FALSE(format_up_axis("model.ply").has_value());
  // Upright (+y) as the specification says: +y, no warning.
  const UpChoice upright = choose_up_axis(b.mesh, "plinth.glb");
  EXPECT_EQ(upright.up.name(), "+y");
  EXPECT_TRUE(upright.warning.empty()) << upright.warning;
  // Exported z-up: the plinth is a firm rest and a flat base (score 0.9, +y 0): +z, with a warning.
  const TriangleMesh z_up = rotated(b.mesh, axis_rotation(Axis{1, false}, Axis{2, false}));
  const UpChoice overridden = choose_up_axis(z_up, "plinth.gltf");
  print_rests("plinth z-up", overridden);
  EXPECT_EQ(overridden.up.name(), "+z") << overridden.reason;
  EXPECT_NE(overridden.warning.find("glTF"), std::string::npos) << overridden.warning;
  EXPECT_EQ(choose_up_axis(z_up, "plinth.ply").up.name(), "+z");
  EXPECT_TRUE(choose_up_axis(z_up, "plinth.ply").warning.empty());
  // A flat model (a cut-out character: two layered cards in the xy plane) rests firmly on its
  // back, -z; that says nothing about its picture's up, so a glTF keeps +y.
  Builder card;
  card.box({-1.0, -2.0, 0.0}, {1.0, 2.0, 0.04});
  card.box({-0.5, -1.0, 0.04}, {0.5, 1.0, 0.08});
  EXPECT_EQ(choose_up_axis(card.mesh).up.name(), "+z");
  const UpChoice sprite = choose_up_axis(card.mesh, "sprite.glb");
  EXPECT_EQ(sprite.up.name(), "+y") << sprite.reason;
  EXPECT_TRUE(sprite.warning.empty()) << sprite.warning;
  // A weak disagreement (a head with no base: the shape is not confident) keeps +y.
  Builder head;
  head.sphere({0.0, 0.0, 0.0}, 1.0);
  const UpChoice ball = choose_up_axis(head.mesh, "ball.glb");
  EXPECT_EQ(ball.up.name(), "+y") << ball.reason;
  EXPECT_TRUE(ball.warning.empty()) << ball.warning;
  EXPECT_NE(ball.reason.find("glTF is +y up"), std::string::npos) << ball.reason;
}

// Vessels turned on a wheel, with walls: a bowl, a cup, a plate, a goblet on a hollow foot and a
// bowl on a recessed foot ring. Each rests more firmly on its rim than on its foot (the rim spans
// the footprint), so the rests alone put them upside down; the air trapped under the rim stands
// them mouth up, in every orientation. The hollows under a foot (the goblet's, the foot ring's)
// trap far less.
TEST(UpAxis, VesselsStandMouthUp) {
  using P = Eigen::Vector2d;
  std::vector<std::pair<std::string, std::vector<P>>> vessels;
  // A round bowl standing on `foot` (its profile up to the foot's outer edge at (0.38, 0.06)):
  // the outside rises as a quarter circle to the rim, the inside comes back down 0.05 thinner.
  const auto bowl_on = [](std::vector<P> profile) {
    const std::size_t foot = profile.size();
    for (int k = 1; k <= 10; ++k) {
      const double a = EIGEN_PI / 2 * k / 10;
      profile.emplace_back(0.38 + 0.62 * std::sin(a), 0.06 + 0.9 * (1 - std::cos(a)));
    }
    for (std::size_t k = 10; k >= 1; --k) {
      const P outside = profile[foot - 1 + k];
      profile.emplace_back(0.93 * outside.x(), 0.1 + 0.95 * (outside.y() - 0.06));
    }
    profile.emplace_back(0, 0.1);
    return profile;
  };
  vessels.emplace_back("bowl", bowl_on({{0, 0}, {0.35, 0}, {0.38, 0.06}}));
  vessels.emplace_back("cup", std::vector<P>{{0, 0}, {0.4, 0}, {0.42, 0.05}, {0.45, 0.9}, {0.5, 1.0}, {0.46, 1.0}, {0.41, 0.9}, {0.38, 0.1}, {0, 0.1}});
  vessels.emplace_back("plate", std::vector<P>{{0, 0}, {0.5, 0}, {0.52, 0.03}, {0.6, 0.06}, {1.0, 0.15}, {1.0, 0.17}, {0.6, 0.09}, {0, 0.09}});
  vessels.emplace_back("goblet", std::vector<P>{{0, 0.15}, {0.3, 0.02}, {0.45, 0}, {0.45, 0.02}, {0.32, 0.05}, {0.06, 0.25}, {0.06, 0.45},
                                                {0.3, 0.55}, {0.45, 0.75}, {0.5, 1.0}, {0.47, 1.0}, {0.42, 0.76}, {0.28, 0.58}, {0, 0.52}});
  vessels.emplace_back("foot-ring bowl", bowl_on({{0, 0.04}, {0.3, 0.04}, {0.3, 0}, {0.36, 0}, {0.38, 0.06}}));
  // A straight beaker: its foot and its rim are the same disc, so the two rests nearly tie and
  // either may lead; the air under the rim decides both ways.
  vessels.emplace_back("beaker", std::vector<P>{{0, 0}, {0.5, 0}, {0.5, 1.0}, {0.45, 1.0}, {0.45, 0.08}, {0, 0.08}});
  for (const auto& [name, profile] : vessels) {
    Builder b;
    b.lathe(profile);
    const UpChoice c = choose_up_axis(b.mesh);
    const UpRest& on_rim = c.rests[3];  // -y: upside down
    const UpRest& on_foot = c.rests[2];
    if (name != "beaker") {
      EXPECT_GT(on_rim.score, on_foot.score) << name << ": the rim is the firmer rest, so the air decides";
    }
    EXPECT_GE(on_rim.trapped_air, 0.15) << name;
    EXPECT_LE(on_foot.trapped_air, 0.05) << name;
    EXPECT_GT(c.upside_down_air, 0.0) << name << ": " << c.reason;
    EXPECT_NE(c.reason.find("mouth up"), std::string::npos) << c.reason;
    expect_found_in_every_orientation(name, b.mesh, (Axis{1, false}));
  }
  // A solid dome on its flat face (a paperweight) traps no air either way: it stays on its face.
  Builder dome;
  dome.revolution({0.0, 0.0, 0.0}, [](double t) { return std::cos(EIGEN_PI / 2 * t); }, [](double t) { return std::sin(EIGEN_PI / 2 * t); });
  const UpChoice d = choose_up_axis(dome.mesh);
  EXPECT_EQ(d.upside_down_air, 0.0) << d.reason;
  expect_found_in_every_orientation("dome", dome.mesh, (Axis{1, false}));
}

// Vessels as photogrammetry scans them: the camera never sees the underside (on the table) nor
// deep inside, so the scan is open at the foot and its inside stops partway down. The hole at the
// foot is the model's open base; the hole inside reaches no end of the model and counts for
// nothing (counted, its cap, wider than the foot and facing up, stood such a jar on its mouth, as
// it did the GGG black vase). Closed where the scan stopped, the inside traps the air a vessel on
// its mouth does. A jar (foot as wide as its mouth) and a vase swelling above a narrow foot,
// scanned down to a half and to a third of their height inside, stand mouth up in every orientation.
TEST(UpAxis, OpenScansOfVesselsStandMouthUp) {
  using P = Eigen::Vector2d;
  const std::vector<std::pair<std::string, std::vector<P>>> vessels = {
      {"jar", {{0.4, 0}, {0.5, 0.3}, {0.5, 0.8}, {0.38, 0.95}, {0.4, 1.0}, {0.36, 1.0}, {0.34, 0.95}, {0.46, 0.8}, {0.46, 0.5}}},
      {"vase", {{0.25, 0}, {0.4, 0.3}, {0.5, 0.6}, {0.42, 0.9}, {0.45, 1.0}, {0.41, 1.0}, {0.38, 0.9}, {0.46, 0.6}, {0.37, 0.35}}}};
  for (const auto& [name, profile] : vessels) {
    Builder b;
    b.lathe(profile, 64, false);
    const UpChoice c = choose_up_axis(b.mesh);
    const UpRest& upright = c.rests[2];
    EXPECT_GT(upright.flat_base, 0.2) << name << ": the open foot is its base";
    EXPECT_LT(upright.flat_top, 0.15) << name << ": only the lip is flat on top; the hole inside is no top";
    EXPECT_GE(c.rests[3].trapped_air, 0.15) << name << ": on its mouth, its inside closed where the scan stopped traps air";
    expect_found_in_every_orientation(name, b.mesh, (Axis{1, false}));
  }
}

// A top-heavy vase on a narrow foot with a flared mouth, as a scan whose inside stopped short in
// the neck: it rests more firmly on its mouth (the wider rim, the body low) than on its foot, and
// its mouth traps less air than a vessel's whole inside (kPocketShare). It is round about its
// axis, as a thrown pot is, and then less air tells its mouth (kRoundPocketShare). Before, this
// vase stood on its mouth, confidently, and a GGG SfM black vase scan (mouth 0.161, foot 0.124,
// 0.107 of its box trapped under its mouth) kept +y, not confident, in all six orientations.
TEST(UpAxis, RoundVesselWithLittleAirUnderItsMouthStandsOnItsFoot) {
  Builder b;
  b.lathe({{0.0, 0.0}, {0.29, 0.0}, {0.45, 0.35}, {0.5, 0.65}, {0.35, 0.85}, {0.37, 1.0}, {0.33, 1.0}, {0.31, 0.85}, {0.3, 0.8}, {0.0, 0.8}});
  const UpChoice c = choose_up_axis(b.mesh);
  print_rests("tied vase", c);
  const UpRest &foot = c.rests[2], &mouth = c.rests[3];
  EXPECT_GT(mouth.score, foot.score) << "it rests more firmly on its mouth";
  EXPECT_LT(mouth.trapped_air, 0.15);
  EXPECT_GT(mouth.trapped_air, 0.05);
  expect_found_in_every_orientation("tied vase", b.mesh, (Axis{1, false}));
}

// Furniture rests more firmly on its top or seat than on its legs (flat, heavy, the whole
// footprint); standing on its legs, most of its box is open air under it. A table, a stool, a
// bench and a chair (whose back is a rest nearly as firm as its legs) stand on their legs in every
// orientation.
TEST(UpAxis, FurnitureStandsOnItsLegs) {
  const auto legs = [](Builder& b, double w, double d, double h, double t) {
    for (const double sx : {-1.0, 1.0})
      for (const double sz : {-1.0, 1.0})
        b.box({sx * w - (sx > 0 ? t : 0.0), 0.0, sz * d - (sz > 0 ? t : 0.0)}, {sx * w + (sx > 0 ? 0.0 : t), h, sz * d + (sz > 0 ? 0.0 : t)});
  };
  Builder table, stool, bench, chair;
  table.box({-1.0, 0.72, -0.6}, {1.0, 0.76, 0.6});
  legs(table, 0.95, 0.55, 0.72, 0.05);
  stool.box({-0.2, 0.45, -0.2}, {0.2, 0.5, 0.2});
  legs(stool, 0.18, 0.18, 0.45, 0.04);
  bench.box({-1.0, 0.42, -0.2}, {1.0, 0.46, 0.2});
  legs(bench, 0.95, 0.15, 0.42, 0.05);
  chair.box({-0.22, 0.45, -0.22}, {0.22, 0.5, 0.22});
  chair.box({-0.22, 0.5, -0.22}, {0.22, 0.95, -0.18});
  legs(chair, 0.2, 0.2, 0.45, 0.04);
  for (const auto& [name, b] : {std::pair<std::string, const Builder*>{"table", &table}, {"stool", &stool}, {"bench", &bench}, {"chair", &chair}}) {
    const UpChoice c = choose_up_axis(b->mesh);
    EXPECT_GE(c.rests[2].clearance, 0.4) << name;
    EXPECT_NE(c.reason.find("stands on its legs"), std::string::npos) << name << ": " << c.reason;
    expect_found_in_every_orientation(name, b->mesh, (Axis{1, false}));
  }
}

// A figure with its arms spread (a T-pose: as wide as it is tall, a fifth as thick) rests far more
// firmly on its back than on its feet; its mirror plane (x = 0) tells it from a thing that lies
// flat, and it stands on its feet in every orientation, also where its feet are the firmer rest
// but not clearly so. A lizard lying on its belly (as thick, but
// much longer than its legs are wide) keeps lying.
TEST(UpAxis, FigureWithSpreadArmsStandsOnItsFeet) {
  const auto figure = [](double depth, double sole = 0.0) {
    Builder b;
    const double d = depth / 2;
    // Front and back differ as a body's do (the mirror test must not find a front-back plane):
    // legs and seat to the back, chest, head and feet to the front.
    b.box({-0.2, 0.0, -d}, {-0.05, 0.9, 0.2 * d});        // legs
    b.box({0.05, 0.0, -d}, {0.2, 0.9, 0.2 * d});
    b.box({-0.2 - sole, 0.0, -d}, {-0.05, 0.08, 2.2 * d + sole});  // feet, pointing to +z
    b.box({0.05, 0.0, -d}, {0.2 + sole, 0.08, 2.2 * d + sole});
    b.box({-0.25, 0.9, -d}, {0.25, 1.5, 0.6 * d});        // body
    b.box({-0.22, 1.1, 0.6 * d}, {0.22, 1.45, 1.6 * d});  // chest
    b.box({-0.85, 1.38, -0.4 * d}, {-0.25, 1.48, 0.6 * d}); // arms, straight out
    b.box({0.25, 1.38, -0.4 * d}, {0.85, 1.48, 0.6 * d});
    b.sphere({0.0, 1.65, 0.5 * d}, 0.12);                 // head and nose
    b.box({-0.03, 1.62, 0.5 * d + 0.1}, {0.03, 1.68, 0.5 * d + 0.16});
    return b;
  };
  const Builder person = figure(0.24);
  const UpChoice c = choose_up_axis(person.mesh);
  EXPECT_EQ(c.symmetry_normal, 0) << c.reason;
  EXPECT_TRUE(c.lying_figure) << c.reason;
  EXPECT_GT(c.rests[4].score, c.rests[2].score) << "lying on its back is the firmer rest, so the figure rule decides";
  expect_found_in_every_orientation("T-pose", person.mesh, (Axis{1, false}));
  // Wide soles make the feet the firmest rest, but not clearly (less than 1.5x the back): the
  // same figure, so it stands on its feet in every orientation all the same.
  const Builder shod = figure(0.24, 0.1);
  const UpChoice f = choose_up_axis(shod.mesh);
  EXPECT_GT(f.rests[2].score, f.rests[4].score) << f.reason;
  EXPECT_LT(f.rests[2].score, 1.5 * f.rests[4].score) << f.reason;
  EXPECT_TRUE(f.lying_figure) << f.reason;
  expect_found_in_every_orientation("T-pose on wide soles", shod.mesh, (Axis{1, false}));

  Builder lizard;
  lizard.box({-0.15, 0.0, -1.0}, {0.15, 0.3, 1.0});  // body, head to tail along z
  for (const double sx : {-1.0, 1.0})
    for (const double z : {-0.6, 0.6}) lizard.box({sx > 0 ? 0.15 : -0.45, 0.0, z - 0.05}, {sx > 0 ? 0.45 : -0.15, 0.1, z + 0.05});
  const UpChoice l = choose_up_axis(lizard.mesh);
  EXPECT_FALSE(l.lying_figure) << l.reason;
  expect_found_in_every_orientation("lizard", lizard.mesh, (Axis{1, false}));

}

// The air under each side is gathered by threads over chunks of triangles and merged by lowest and
// highest point: the same choice and the same numbers on one thread as on all.
TEST(UpAxis, SameAnswerOnAnyThreadCount) {
  Builder b;
  for (int i = 0; i < 12; ++i) b.sphere({0.3 * i, 0.1 * (i % 3), 0.0}, 0.4, 96, 192);  // > 400k triangles: many chunks
  b.box({-0.5, -0.6, -0.5}, {3.8, -0.4, 0.5});
  const UpChoice all = choose_up_axis(b.mesh);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const UpChoice single = choose_up_axis(b.mesh);
  EXPECT_EQ(single.up, all.up);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(single.rests[k].trapped_air, all.rests[k].trapped_air) << k;
    EXPECT_EQ(single.rests[k].clearance, all.rests[k].clearance) << k;
    EXPECT_EQ(single.rests[k].score, all.rests[k].score) << k;
  }
}

TEST(UpAxis, MeshWithoutAreaIsAnInputError) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}};
  EXPECT_THROW(choose_up_axis(mesh), InputError);
}

}  // namespace
}  // namespace meshtour
