#pragma once
// Image-based light: an equirectangular (latitude-longitude) environment that lights the model
// in place of the look's uniform sky. Its diffuse light is the environment's irradiance, held as
// nine spherical-harmonic coefficients (Ramamoorthi and Hanrahan 2001, "An efficient
// representation for irradiance environment maps"), times the occlusion the sky rays measure:
// exact on convex surfaces for any environment up to the second band (on average within about
// 1 % of the true irradiance; a small bright sun is spread over a wide lobe, so it casts no
// shadow of its own: the look's lights do).
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace meshtour {

/// An environment image: linear RGB, rows from the zenith (top) to the nadir; column u runs round
/// the up axis (u = 0.5 looks along the environment's -z, as Blender and three.js lay it out).
struct EnvironmentImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< width * height * 3
  std::string source;      ///< the file, or "neutral"
};

/// Reads an equirectangular image (Radiance HDR, OpenEXR, or any image OpenImageIO reads; 8-bit
/// images are sRGB-decoded). \throw IoError if it cannot be read, InputError if it is not about
/// twice as wide as high (an equirectangular image is 2:1), has no pixels or holds a value that
/// is negative or not finite.
EnvironmentImage read_environment(const std::filesystem::path& file);

/// The built-in neutral studio, made here (no file): a bright grey room, lit by a large softbox
/// above and in front, a strip light on each side and a darker floor, in the spirit of
/// model-viewer's "neutral". Scaled so that a white diffuse surface facing up receives an
/// irradiance of pi (it shows as 1.0 before the look's lights).
EnvironmentImage neutral_environment();

/// "neutral" or a file: what --environment names.
std::shared_ptr<const EnvironmentImage> environment_named(const std::string& name_or_file);

/// Nine coefficients per channel of the irradiance E(n) / pi for world normals n, in the world
/// frame: E(n) / pi = sum_k coefficient[k] * basis_k(n), with basis (1, y, z, x, xy, yz,
/// 3z^2 - 1, xz, x^2 - y^2) of the world's own axes.
struct IrradianceSH {
  std::array<Eigen::Vector3f, 9> coefficient{};
  /// E(n) / pi for a unit normal, clamped at 0 (the second band can dip below near a bright spot).
  Eigen::Vector3f operator()(const Eigen::Vector3f& n) const;
};

/// The environment's irradiance with its +y on the world's `up` and turned `rotation_deg` about
/// it (right-handed, seen from above), times `intensity`.
IrradianceSH irradiance_sh(const EnvironmentImage& env, const Eigen::Vector3f& up, float rotation_deg, float intensity);

/// The environment's radiance in world directions, for the rays of glossy reflections: the image
/// as placed in the world, times its intensity.
struct EnvironmentRadiance {
  std::shared_ptr<const EnvironmentImage> image;
  Eigen::Matrix3f environment_from_world = Eigen::Matrix3f::Identity();
  float intensity = 1.0f;
  /// The radiance arriving from unit world direction `d`: bilinear between the four nearest
  /// pixels' centres (wrapping round the up axis, clamped at the poles).
  Eigen::Vector3f operator()(const Eigen::Vector3f& d) const;
};
EnvironmentRadiance environment_radiance(std::shared_ptr<const EnvironmentImage> env, const Eigen::Vector3f& up, float rotation_deg,
                                         float intensity);

/// The world direction of the environment's direction `d` (its own frame: +y up), under the same
/// placement as irradiance_sh().
Eigen::Vector3f environment_to_world(const Eigen::Vector3f& d, const Eigen::Vector3f& up, float rotation_deg);

}  // namespace meshtour
