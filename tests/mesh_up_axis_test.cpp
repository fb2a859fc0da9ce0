// --up auto (mesh/up_axis.h): the rule on the shared meshes, on the same meshes turned so that
// their up is another axis (the rule must turn with them), and on procedural shapes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>

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
  std::printf("%-10s", name.c_str());
  for (const UpRest& r : c.rests)
    std::printf(" %s: %.3f (a %.2f m %+.2f h %.2f)", r.up.name().c_str(), r.score, r.support_area, r.margin, r.centroid_height);
  std::printf("  -> %s%s\n", c.up.name().c_str(), c.confident ? "" : " (not confident)");
}

struct Documented {
  const char* file;
  const char* up;       // meshes.tsv's up axis
  bool rule_finds_it;   // whether the hull-rest rule finds it (see below)
};
// The rule finds the documented up of the animals that stand on their feet. The bear (upright on
// its hind legs: no side rests stably) and the Venus bust (no flat base: every side's support is
// under 5% of the footprint) rest nowhere firmly, so the rule keeps +y: right for the bear by
// convention, wrong for Venus (+z), hence --up auto is not the default. The rocker arm has no
// natural up (+y is a convention). All are checked for following a rotation.
constexpr Documented kShared[] = {{"horse.ply", "+y", true},     {"kitten.ply", "+y", true}, {"bunny.ply", "+y", true},
                                  {"armadillo.ply", "+y", true}, {"bear.ply", "+y", false},  {"venus.ply", "+z", false},
                                  {"rocker.ply", "+y", false}};

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
    } else if (std::string(d.file) != "rocker.ply") {
      EXPECT_FALSE(choice.confident) << d.file << ": " << choice.reason;
      EXPECT_EQ(choice.up.name(), "+y");
    }
    // Turned so that its up is another axis, every side's rest turns with it: the same scores on
    // the turned sides, so the same choice whenever there is a stable rest.
    for (const Axis to : {Axis{0, false}, Axis{2, true}, Axis{1, true}}) {
      const Eigen::Matrix3d r = axis_rotation(up, to);
      const UpChoice turned = choose_up_axis(rotated(mesh, r));
      for (const UpRest& rest : choice.rests) {
        const Eigen::Vector3d v = r * rest.up.vector();
        const int index = v.cwiseAbs().maxCoeff() == std::abs(v.x()) ? 0 : v.cwiseAbs().maxCoeff() == std::abs(v.y()) ? 1 : 2;
        const UpRest& same = turned.rests[static_cast<std::size_t>(2 * index + (v[index] < 0.0 ? 1 : 0))];
        EXPECT_NEAR(same.score, rest.score, 1e-9) << d.file << " turned to " << to.name() << ", side " << rest.up.name();
      }
      if (d.rule_finds_it) {
        EXPECT_EQ(turned.up.name(), to.name()) << d.file << " turned to " << to.name() << ": " << turned.reason;
      }
    }
  }
}

// A box on a wider plinth: it stands on the plinth, whichever axis is up.
TEST(UpAxis, BoxOnPlinth) {
  TriangleMesh mesh;
  const auto add_box = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (int i = 0; i < 8; ++i)
      mesh.positions.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
      mesh.triangles.push_back({base + q[0], base + q[1], base + q[2]});
      mesh.triangles.push_back({base + q[0], base + q[2], base + q[3]});
    }
  };
  add_box({-1.0, 0.0, -1.0}, {1.0, 0.3, 1.0});   // plinth
  add_box({-0.4, 0.3, -0.4}, {0.4, 2.0, 0.4});   // tall box on it
  const UpChoice choice = choose_up_axis(mesh);
  print_rests("plinth", choice);
  EXPECT_EQ(choice.up.name(), "+y") << choice.reason;
  for (const Axis to : {Axis{0, true}, Axis{2, false}, Axis{1, true}})
    EXPECT_EQ(choose_up_axis(rotated(mesh, axis_rotation(Axis{1, false}, to))).up.name(), to.name());
}

TEST(UpAxis, MeshWithoutAreaIsAnInputError) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}};
  EXPECT_THROW(choose_up_axis(mesh), InputError);
}

}  // namespace
}  // namespace meshtour
