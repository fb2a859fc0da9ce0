#pragma once
// §6: the osculating torus of a surface point and the exact point–torus and face–torus distances.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace meshtour {

/// ((√(x²+y²) − R)² + z² = r_T²) in a frame with origin `center` and third axis `axis`.
struct Torus {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit length
  double major_radius = 0.0;                        ///< R ≥ 0
  double minor_radius = 1.0;                        ///< r_T > 0
};

/// The equatorial osculating torus of §6.2 at p: normal N, curvature k1 (smaller |·|) along t1
/// and k2 along t2. |κ| below `kappa_min` is clamped to kappa_min (I-9).
Torus osculating_torus(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, double k1,
                       const Eigen::Vector3d& t1, double k2, const Eigen::Vector3d& t2,
                       double kappa_min = 1e-6);

/// Exact Euclidean distance from q to the full torus surface (§6.3), evaluated as written.
inline double point_torus_distance(const Torus& torus, const Eigen::Vector3d& q) {
  const Eigen::Vector3d w = q - torus.center;
  const double z = w.dot(torus.axis);
  const double rho = (w - z * torus.axis).norm();
  const double dr = rho - torus.major_radius;
  return std::abs(std::sqrt(dr * dr + z * z) - torus.minor_radius);
}

/// §6.4: points of a triangle whose largest torus distance is the face–torus distance (I-11).
enum class FaceSamples {
  seven,     ///< vertices, edge midpoints and centroid (default)
  vertices,  ///< the three vertices only
  edges4,    ///< vertices, the 1/4, 1/2 and 3/4 points of every edge, and the centroid (I-32)
};

/// What a sample's "distance" to the torus is (I-30). With d the distance from the torus's core
/// circle and r_T the minor radius: geometric |d − r_T| (§6.3, default); algebraic
/// |d² − r_T²| = |(√(x²+y²) − R)² + z² − r_T²|, the implicit equation's value; algebraic-normalized
/// |d² − r_T²| / |∇| = |d² − r_T²| / (2d), its first-order distance estimate.
enum class PatchMeasure { geometric, algebraic, algebraic_normalized };

/// The whole test of a face against a torus (§7.2 and the I-30..I-32 alternatives).
struct PatchTest {
  FaceSamples samples = FaceSamples::seven;
  PatchMeasure measure = PatchMeasure::geometric;
  /// I-31: also require the face's normal within this angle (degrees) of the torus normal at the
  /// face's centroid; 0 = distance only (the specification).
  double max_normal_angle_deg = 0.0;
};

/// The sample measure of `measure` (geometric = point_torus_distance).
double point_torus_measure(const Torus& torus, const Eigen::Vector3d& q, PatchMeasure measure);

/// D(f, T) under `test`: the largest sample measure, or +infinity when the normal test fails.
double face_torus_distance(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                           const Eigen::Vector3d& p2, const PatchTest& test);
/// D(f, T) ≤ tolerance under `test`.
bool face_within(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                 const Eigen::Vector3d& p2, const PatchTest& test, double tolerance);

/// D(f, T) = max over the sample set of d(q, T). The centroid is summed in lexicographic order
/// of the corners so that it does not depend on where the face's vertex list starts.
double face_torus_distance(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                           const Eigen::Vector3d& p2, FaceSamples samples);

/// D(f, T) ≤ tolerance, stopping at the first sample that is too far (same answer, less work).
bool face_within(const Torus& torus, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                 const Eigen::Vector3d& p2, FaceSamples samples, double tolerance);

}  // namespace meshtour
