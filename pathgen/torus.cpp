#include "pathgen/torus.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/triangle_geometry.h"

namespace meshtour {
namespace {

bool lexicographic_less(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

// (p0+p1+p2)/3 with the corners summed in a canonical order, so a cyclic rotation of the face's
// vertex list (or a renumbering) cannot change the rounding of the sample point.
Eigen::Vector3d centroid(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) {
  const Eigen::Vector3d* c[3] = {&p0, &p1, &p2};
  if (lexicographic_less(*c[1], *c[0])) std::swap(c[0], c[1]);
  if (lexicographic_less(*c[2], *c[1])) std::swap(c[1], c[2]);
  if (lexicographic_less(*c[1], *c[0])) std::swap(c[0], c[1]);
  return (*c[0] + *c[1] + *c[2]) / 3.0;
}

}  // namespace

Torus osculating_torus(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, double k1,
                       const Eigen::Vector3d& t1, double k2, const Eigen::Vector3d& t2, double kappa_min) {
  (void)t1;  // the torus is fixed by its axis t2; t1 is implied (the latitude circle's tangent)
  // sign(0) of κ2 is +1 and sign(0) of κ1 follows κ2, so a flat point becomes a sphere (§6.2).
  const double s2 = k2 < 0.0 ? -1.0 : 1.0;
  if (!(std::abs(k2) >= kappa_min)) k2 = s2 * kappa_min;
  const double s1 = k1 < 0.0 ? -1.0 : (k1 > 0.0 ? 1.0 : s2);
  if (!(std::abs(k1) >= kappa_min)) k1 = s1 * kappa_min;
  const double rho1 = 1.0 / std::abs(k1);
  const double rho2 = 1.0 / std::abs(k2);
  const double sigma = (k1 < 0.0) == (k2 < 0.0) ? 1.0 : -1.0;
  const Eigen::Vector3d m = (k1 < 0.0 ? -1.0 : 1.0) * normal;
  Torus t;
  t.center = p + rho1 * m;
  t.axis = t2;
  t.major_radius = rho1 - sigma * rho2;
  t.minor_radius = rho2;
  return t;
}

namespace {

// The I-32 samples beyond the seven: the quarter points of every edge.
template <typename Visit>
void quarter_points(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2, Visit&& visit) {
  for (const auto& [a, b] : {std::pair{&p0, &p1}, std::pair{&p1, &p2}, std::pair{&p2, &p0}}) {
    if (!visit((3.0 * *a + *b) / 4.0)) return;
    if (!visit((*a + 3.0 * *b) / 4.0)) return;
  }
}

// I-31: the face's normal against the torus normal at its centroid, sign ignored.
bool normal_within(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                   double max_angle_deg) {
  if (!(max_angle_deg > 0.0)) return true;
  const Eigen::Vector3d n = triangle_cross(p0, p1, p2);
  const Eigen::Vector3d c = centroid(p0, p1, p2);
  const Eigen::Vector3d w = c - torus.center;
  const Eigen::Vector3d radial = w - w.dot(torus.axis) * torus.axis;
  const double rho = radial.norm();
  const Eigen::Vector3d core = torus.center + (rho > 0.0 ? torus.major_radius / rho : 0.0) * radial;
  const Eigen::Vector3d m = c - core;
  if (!(n.norm() > 0.0) || !(m.norm() > 0.0)) return true;  // degenerate: the distance decides
  const double cosine = std::abs(n.dot(m)) / (n.norm() * m.norm());
  return cosine >= std::cos(max_angle_deg * 3.14159265358979323846 / 180.0);
}

}  // namespace

double point_torus_measure(const Torus& torus, const Eigen::Vector3d& q, PatchMeasure measure) {
  if (measure == PatchMeasure::geometric) return point_torus_distance(torus, q);
  const Eigen::Vector3d w = q - torus.center;
  const double z = w.dot(torus.axis);
  const double rho = (w - z * torus.axis).norm();
  const double dr = rho - torus.major_radius;
  const double d2 = dr * dr + z * z;
  const double f = std::abs(d2 - torus.minor_radius * torus.minor_radius);
  if (measure == PatchMeasure::algebraic) return f;
  const double d = std::sqrt(d2);
  return d > 0.0 ? f / (2.0 * d) : std::numeric_limits<double>::infinity();
}

double face_torus_distance(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                           const Eigen::Vector3d& p2, const PatchTest& test) {
  if (!normal_within(torus, p0, p1, p2, test.max_normal_angle_deg)) return std::numeric_limits<double>::infinity();
  const auto m = [&](const Eigen::Vector3d& q) { return point_torus_measure(torus, q, test.measure); };
  double d = std::max({m(p0), m(p1), m(p2)});
  if (test.samples == FaceSamples::vertices) return d;
  d = std::max({d, m((p0 + p1) / 2.0), m((p1 + p2) / 2.0), m((p2 + p0) / 2.0), m(centroid(p0, p1, p2))});
  if (test.samples == FaceSamples::edges4) quarter_points(p0, p1, p2, [&](const Eigen::Vector3d& q) {
    d = std::max(d, m(q));
    return true;
  });
  return d;
}

bool face_within(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                 const PatchTest& test, double tolerance) {
  if (test.measure == PatchMeasure::geometric && test.max_normal_angle_deg == 0.0 && test.samples != FaceSamples::edges4)
    return face_within(torus, p0, p1, p2, test.samples, tolerance);  // the specification's test, early exits
  return face_torus_distance(torus, p0, p1, p2, test) <= tolerance;
}

double face_torus_distance(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                           const Eigen::Vector3d& p2, FaceSamples samples) {
  double d = std::max({point_torus_distance(torus, p0), point_torus_distance(torus, p1),
                       point_torus_distance(torus, p2)});
  if (samples == FaceSamples::vertices) return d;
  d = std::max(d, point_torus_distance(torus, (p0 + p1) / 2.0));
  d = std::max(d, point_torus_distance(torus, (p1 + p2) / 2.0));
  d = std::max(d, point_torus_distance(torus, (p2 + p0) / 2.0));
  return std::max(d, point_torus_distance(torus, centroid(p0, p1, p2)));
}

bool face_within(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                 const Eigen::Vector3d& p2, FaceSamples samples, double tolerance) {
  // `!(d <= tol)` also rejects a NaN distance.
  if (!(point_torus_distance(torus, p0) <= tolerance)) return false;
  if (!(point_torus_distance(torus, p1) <= tolerance)) return false;
  if (!(point_torus_distance(torus, p2) <= tolerance)) return false;
  if (samples == FaceSamples::vertices) return true;
  if (!(point_torus_distance(torus, (p0 + p1) / 2.0) <= tolerance)) return false;
  if (!(point_torus_distance(torus, (p1 + p2) / 2.0) <= tolerance)) return false;
  if (!(point_torus_distance(torus, (p2 + p0) / 2.0) <= tolerance)) return false;
  return point_torus_distance(torus, centroid(p0, p1, p2)) <= tolerance;
}

}  // namespace meshtour
