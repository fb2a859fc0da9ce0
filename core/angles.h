#pragma once
// Angle constants: degrees to radians, and the full turn.
#include <numbers>

namespace meshtour {

/// Radians in one degree. Multiplying by it rounds differently from `deg * pi / 180.0`: code
/// that converts one way keeps converting that way, or its paths and pixels change.
inline constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

/// One full turn, 2 pi radians.
inline constexpr double kFullTurn = 2.0 * std::numbers::pi;

}  // namespace meshtour
