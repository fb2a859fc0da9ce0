#pragma once
// §9 of docs/METHOD.md: the up direction (I-18) and the bounding cylinder the camera circles, with
// its angular frame; in normalized units (AABB diagonal of the smoothed model = 1).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/axis.h"

namespace meshtour {

/// How the cylinder axis direction û is chosen (I-18).
struct UpDirection {
  enum class Kind {
    axis,          ///< a signed coordinate axis (default +Y)
    vector,        ///< any direction given by the user
    longest_aabb,  ///< the longest side of the (normalized, smoothed) model's bounding box
    pca,           ///< principal axis of largest variance of the surface (area-weighted)
  };
  Kind kind = Kind::axis;
  Axis axis{1, false};
  Eigen::Vector3d vector = Eigen::Vector3d::UnitY();  ///< unit length; used when kind == vector

  /// Parses "y", "-z", "0,1,0.2" (any non-zero vector), "longest-aabb" or "pca".
  /// \throw InputError with the accepted forms otherwise.
  static UpDirection parse(std::string_view text);
  /// The form parse() accepts: "+y", "0.1,1,0", "longest-aabb", "pca".
  std::string name() const;
};

enum class AxisPointMode { surface_centroid, aabb_center };  ///< I-19
std::string to_string(AxisPointMode mode);

/// The bounding cylinder of §9 and its angular frame, in normalized units.
struct Cylinder {
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();   ///< û
  Eigen::Vector3d e_x = Eigen::Vector3d::UnitZ();  ///< angle 0
  Eigen::Vector3d e_y = Eigen::Vector3d::UnitX();  ///< angle π/2; (e_x, e_y, û) right-handed
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();  ///< c
  double base = 0.0;    ///< b = min η
  double height = 0.0;  ///< h
  double radius = 0.0;  ///< r

  /// O(η): the point of the axis at height η = p·û.
  Eigen::Vector3d axis_foot(double eta) const { return axis_point + (eta - axis_point.dot(up)) * up; }
  /// Q(u, θ, ρ): normalized height u, angle θ, distance ρ from the axis.
  Eigen::Vector3d point(double u, double theta, double rho) const;
  /// Distance of p from the axis line.
  double axis_distance(const Eigen::Vector3d& p) const;
};

/// §9.1: the angular frame (e_x, e_y) for the unit up vector (table for ±X/±Y/±Z).
std::pair<Eigen::Vector3d, Eigen::Vector3d> angular_frame(const Eigen::Vector3d& up);

/// The unit up vector for `up` on this (normalized) surface; longest-aabb and pca look at it.
Eigen::Vector3d resolve_up(const UpDirection& up, const std::vector<Eigen::Vector3d>& positions,
                           const std::vector<std::array<std::uint32_t, 3>>& triangles);

/// §9.2. \throw InputError if h or r is below 1e-9 (suggesting another up axis).
Cylinder fit_cylinder(const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<std::array<std::uint32_t, 3>>& triangles, const Eigen::Vector3d& up,
                      AxisPointMode axis_point = AxisPointMode::surface_centroid);

}  // namespace meshtour
