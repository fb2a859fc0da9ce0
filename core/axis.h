#pragma once
// Signed coordinate axes, as users name them on the command line ("y", "-z", ...).
#include <Eigen/Core>
#include <string>
#include <string_view>

#include "core/error.h"

namespace meshtour {

/// One of the six signed coordinate axes.
struct Axis {
  int index = 1;     ///< 0 = x, 1 = y, 2 = z
  bool negative = false;

  /// Unit vector of the axis.
  Eigen::Vector3d vector() const {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    v[index] = negative ? -1.0 : 1.0;
    return v;
  }
  std::string name() const { return std::string(negative ? "-" : "+") + "xyz"[index]; }

  /// Parses "x", "+y", "-z" (case-insensitive). \throw InputError on anything else.
  static Axis parse(std::string_view text) {
    std::string_view t = text;
    bool neg = false;
    if (!t.empty() && (t.front() == '+' || t.front() == '-')) {
      neg = t.front() == '-';
      t.remove_prefix(1);
    }
    if (t.size() == 1) {
      const char c = static_cast<char>(t.front() | 0x20);  // lower case
      if (c >= 'x' && c <= 'z') return Axis{c - 'x', neg};
    }
    throw InputError("invalid axis '" + std::string(text) + "': use one of x, y, z, -x, -y, -z");
  }
  bool operator==(const Axis&) const = default;
};

/// The conventional front of a model standing on `up`, the direction a viewer looks at it from:
/// +Z for Y-up (OpenGL, most scanners) and X-up, -Y for Z-up (Blender and CAD). The turntable
/// starts there and the feature orbit breaks its ties towards it.
inline Eigen::Vector3d front_direction(const Axis& up) {
  return up.index == 2 ? Eigen::Vector3d(-Eigen::Vector3d::UnitY()) : Eigen::Vector3d(Eigen::Vector3d::UnitZ());
}

}  // namespace meshtour
