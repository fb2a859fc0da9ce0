#include "pathgen/torus.h"

#include <algorithm>
#include <cmath>

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
