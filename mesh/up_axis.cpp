// The up-axis rule (mesh/up_axis.h). A model standing upright rests on its base: gravity along
// -up puts it on the hull face under it, and of the six axis directions the natural one is the one
// where that rest is firm. Firm means three things together, each measured on the convex hull
// (a table, the floor and the renderer's ground plane only ever touch the hull):
//  * the support polygon (the hull facets facing down within kSupportAngle) is large compared with
//    the model's footprint: a bust's base or four feet, not the top of a head or a curved back;
//  * the centroid projects well inside it (else the model would tip over);
//  * the centroid sits low above it (a lower centre of mass is the firmer rest of two equal bases).
// The score multiplies these, so a rest that fails any of them loses.
#include "mesh/up_axis.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "mesh/convex_hull.h"

namespace meshtour {
namespace {

// Hull facets within this angle of straight down carry the model: a scan's flat base is rarely
// exactly perpendicular to the axis, and a hull facet spanning feet tilts by a few degrees.
constexpr double kSupportAngleDeg = 12.0;
// The winner decides when its score is at least kFirmScore and this factor ahead of the runner-up.
// Measured (tests/mesh_up_axis_test.cpp): the animals standing on their feet score 0.017-0.16 and
// beat the next side by far more; the Venus bust's best side scores 0.0003, a box on a plinth 0.65.
constexpr double kConfidentRatio = 1.5;
constexpr double kFirmScore = 0.005;
// Facets up to this far (share of the model's size) above the support plane still touch the floor.
constexpr double kPlaneShare = 0.02;

double polygon_area(const std::vector<Eigen::Vector2d>& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& q = p[i];
    const Eigen::Vector2d& r = p[(i + 1) % p.size()];
    a += q.x() * r.y() - q.y() * r.x();
  }
  return 0.5 * std::abs(a);
}

// Signed distance of `x` to the edges of the counter-clockwise convex polygon `p`: > 0 inside.
double inside_distance(const std::vector<Eigen::Vector2d>& p, const Eigen::Vector2d& x) {
  if (p.size() < 3) return -std::numeric_limits<double>::infinity();
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d e = p[(i + 1) % p.size()] - p[i];
    const Eigen::Vector2d inward(-e.y(), e.x());
    d = std::min(d, inward.dot(x - p[i]) / e.norm());
  }
  return d;
}

}  // namespace

UpChoice choose_up_axis(const TriangleMesh& mesh) {
  // The surface centroid (area-weighted): the centre of mass of a shell, and close to the solid's
  // for a scan; it needs no closed surface.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double w = 0.5 * (b - a).cross(c - a).norm();
    centroid += w * (a + b + c) / 3.0;
    area += w;
  }
  if (!(area > 0.0)) throw InputError("--up auto: the mesh has no area, so it has no side to rest on");
  centroid /= area;

  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(mesh);
  const std::vector<HullTriangle> facets = convex_hull_triangles(hull);
  const double cos_support = std::cos(kSupportAngleDeg * std::numbers::pi / 180.0);

  double model_size = 0.0;  // the hull's extent along its longest axis, for the plane tolerance
  {
    Eigen::Vector3d lo = hull.front(), hi = lo;
    for (const Eigen::Vector3d& p : hull) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    model_size = (hi - lo).maxCoeff();
  }
  // The rest with gravity along `down`: on the hull facets within kSupportAngle of facing `down`
  // that touch the support plane.
  const auto rest_on = [&](const Eigen::Vector3d& down, UpRest& rest) {
    const Eigen::Vector3d e1 = down.unitOrthogonal(), e2 = down.cross(e1);
    const auto flat = [&](const Eigen::Vector3d& p) { return Eigen::Vector2d(p.dot(e1), p.dot(e2)); };
    std::vector<Eigen::Vector2d> all, support;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Eigen::Vector3d& p : hull) {
      all.push_back(flat(p));
      lo = std::min(lo, -p.dot(down));
      hi = std::max(hi, -p.dot(down));
    }
    const double tolerance = kPlaneShare * model_size;
    for (const HullTriangle& t : facets)
      if (t.normal.dot(down) >= cos_support &&
          std::all_of(t.corner.begin(), t.corner.end(), [&](const Eigen::Vector3d& c) { return -c.dot(down) - lo <= tolerance; }))
        for (const Eigen::Vector3d& c : t.corner) support.push_back(flat(c));
    const std::vector<Eigen::Vector2d> footprint = convex_polygon(std::move(all));
    const std::vector<Eigen::Vector2d> base = convex_polygon(std::move(support));
    const double footprint_area = polygon_area(footprint);
    if (!(footprint_area > 0.0) || !(hi > lo) || base.size() < 3) return;
    rest.support_area = polygon_area(base) / footprint_area;
    rest.margin = inside_distance(base, flat(centroid)) / std::sqrt(footprint_area / std::numbers::pi);
    rest.centroid_height = (-centroid.dot(down) - lo) / (hi - lo);
    rest.score = rest.margin > 0.0 ? rest.support_area * rest.margin * (1.0 - rest.centroid_height) : 0.0;
  };

  UpChoice choice;
  for (int k = 0; k < 6; ++k) {
    UpRest& rest = choice.rests[static_cast<std::size_t>(k)];
    rest.up = Axis{k / 2, k % 2 == 1};
    rest_on(-rest.up.vector(), rest);
  }

  // Ties (a cube) go to the earlier rest of this order (+y first: the glTF and most scanners' up).
  std::array<std::size_t, 6> order{2, 4, 0, 3, 5, 1};
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return choice.rests[a].score > choice.rests[b].score;
  });
  const UpRest& best = choice.rests[order[0]];
  const UpRest& second = choice.rests[order[1]];
  // Only a firm rest that clearly beats the others overrides the file's convention (+y): a bust
  // without a flat base or a bear upright on its hind legs rests nowhere firmly, and a guess
  // would turn it on its side.
  choice.confident = best.score >= kFirmScore && best.score >= kConfidentRatio * second.score;
  choice.up = choice.confident ? best.up : Axis{1, false};
  const auto side = [](const Axis& up) { return Axis{up.index, !up.negative}.name(); };
  char text[320];
  if (choice.confident)
    std::snprintf(text, sizeof text,
                  "rests on its %s side: support %.0f%% of the footprint, centroid %.0f%% of the radius inside it, "
                  "%.0f%% of the height above it (score %.3g, next %s %.3g)",
                  side(best.up).c_str(), 100.0 * best.support_area, 100.0 * best.margin, 100.0 * best.centroid_height,
                  best.score, second.up.name().c_str(), second.score);
  else
    std::snprintf(text, sizeof text,
                  "no side rests clearly firmest (best %s %.3g, next %s %.3g; firm is %.3g and %.1fx the next); "
                  "keeping +y, the usual convention",
                  best.up.name().c_str(), best.score, second.up.name().c_str(), second.score, kFirmScore, kConfidentRatio);
  choice.reason = text;
  return choice;
}

bool is_auto_up(std::string_view text) {
  return text.size() == 4 && std::equal(text.begin(), text.end(), "auto", [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == b;
         });
}

}  // namespace meshtour
