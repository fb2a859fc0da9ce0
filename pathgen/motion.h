#pragma once
// Angular motion of a closed sequence of directions (camera position around a centre, or view
// direction): how smooth a camera path is, measured the same way by the evaluation and by the
// path modes that plan under smoothness limits.
#include <Eigen/Core>
#include <utility>
#include <vector>

namespace meshtour {

/// Largest angular speed and angular acceleration of the closed sequence of unit `directions`
/// (step k goes from k to k+1, the last step back to the first), per step and per step².
/// Speed: the angle between consecutive directions. Acceleration: the change of the angular
/// velocity of the frame that follows the direction with `ups[k]` as its up hint (the camera's
/// frame, roll included), |ω_{k+1} − ω_k|. A level or elevated orbit at constant rate therefore has
/// none; a sudden change of speed, of height or of turning direction has.
std::pair<double, double> angular_motion(const std::vector<Eigen::Vector3d>& directions, const std::vector<Eigen::Vector3d>& ups);

}  // namespace meshtour
