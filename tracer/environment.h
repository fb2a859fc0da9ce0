#pragma once
// Image-based light: an equirectangular (latitude-longitude) environment that lights the model
// in place of the look's uniform sky. Where there are occlusion rays, a sample's light from it is
// the image's radiance along its ray (cosine-distributed, mixed with directions picked by the
// image's own light: EnvironmentDistribution), so a sun in an HDR casts its own sharp shadow. Its
// irradiance (IrradianceMap) is what a diffuse surface gets where its ray is unblocked (the ray
// then only takes away what the model blocks: no noise in the open), and stands in where a value
// must be noise-free: the denoiser's guides, the plain look without occlusion rays, and the
// surfaces interreflections meet.
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace meshtour {

/// An environment image: linear RGB, rows from the zenith (top) to the nadir; column u runs round
/// the up axis (u = 0.5 looks along the environment's -z; Blender, after its glTF import, puts
/// u = 0.5 along +x: docs/RENDERING.md).
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

/// The environment's irradiance over pi, E(n) / pi, at every unit normal: a 128 x 65 map over the
/// normal's angles in the environment's own layout (rows from its zenith to its nadir, both
/// poles included; columns from u = 0, texel centres), each texel the sum over the image's
/// pixels (averaged down to at most 256 x 128, their energy kept) of radiance x max(0, cos) x
/// solid angle / pi at the texel's normal, bilinear in between. No band limit: a small sun's
/// irradiance keeps its shape (tests/tracer_environment_test.cpp measures it against a fine
/// numerical integral).
struct IrradianceMap {
  static constexpr int kWidth = 128, kHeight = 65;
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< width * height * 3
  Eigen::Matrix3f environment_from_world = Eigen::Matrix3f::Identity();
  /// E / pi at fractional texel coordinates (whole numbers at texels; `row` 0 at the zenith,
  /// height - 1 at the nadir, `column` from u = 0): bilinear, wrapping round the up axis.
  Eigen::Vector3f at(float row, float column) const;
  /// E / pi for a unit world normal (angles in double, IEEE-exact: the same on every CPU).
  Eigen::Vector3f operator()(const Eigen::Vector3f& n) const;
};

/// The environment's irradiance map with its +y on the world's `up` and turned `rotation_deg`
/// about it (right-handed, seen from above), times `intensity`.
IrradianceMap irradiance_map(const EnvironmentImage& env, const Eigen::Vector3f& up, float rotation_deg, float intensity);

/// The environment's radiance in world directions, for the rays of glossy reflections: the image
/// as placed in the world, times its intensity.
struct EnvironmentRadiance {
  std::shared_ptr<const EnvironmentImage> image;
  Eigen::Matrix3f environment_from_world = Eigen::Matrix3f::Identity();
  float intensity = 1.0f;
  /// The radiance arriving from unit world direction `d`: bilinear between the four nearest
  /// pixels' centres (wrapping round the up axis, clamped at the poles).
  Eigen::Vector3f operator()(const Eigen::Vector3f& d) const;
  /// The same at image coordinates (x across from u = 0, y down from the zenith, pixel centres
  /// at whole numbers + 0 ... width - 1), for callers that compute the angles themselves.
  Eigen::Vector3f at(float x, float y) const;
};
EnvironmentRadiance environment_radiance(std::shared_ptr<const EnvironmentImage> env, const Eigen::Vector3f& up, float rotation_deg,
                                         float intensity);

/// Where an environment's light comes from, for importance sampling its light on diffuse surfaces
/// and in the glossy reflections of glTF materials: its pixels in proportion to their luminance times their solid angle (a
/// distribution over rows, and within each row over its columns), the image as placed in the
/// world (as EnvironmentRadiance).
struct EnvironmentDistribution {
  int width = 0, height = 0;
  std::vector<float> row_cdf;            ///< height + 1 values from 0 to 1
  std::vector<float> column_cdf;         ///< per row, width + 1 values from 0 to 1
  std::vector<float> pixel_probability;  ///< per pixel (row-major), its share of the whole
  /// Where to start looking in each cdf: entry b is the bin that holds b / n (n bins; row_guide
  /// height + 1 values, column_guide width + 1 per row), so a pick searches a few bins, not all.
  std::vector<int> row_guide, column_guide;
  Eigen::Matrix3f world_from_environment = Eigen::Matrix3f::Identity();
  Eigen::Matrix3f environment_from_world = Eigen::Matrix3f::Identity();
  /// The share of the light that comes from pixels brighter than four times the mean luminance
  /// (weighted by solid angle): 0 for an even sky, near 1 for a small sun. Cosine-distributed
  /// rays find such light rarely; it sets how often a diffuse surface's sky ray is picked here.
  float peak_share = 0.0f;

  /// Whether there is light to sample (an all-black environment has none).
  bool empty() const { return row_cdf.empty(); }
  /// The pixel (column i, row j from the zenith) that numbers u (rows) and v (columns) in [0, 1)
  /// pick, and where in it they fall (fu across, fv down, each in [0, 1)): u and v are stretched
  /// within the chosen row's and column's share, so a net of (u, v) stays a net over the pixel.
  void pick(float u, float v, int& i, int& j, float& fu, float& fv) const;
  /// The pick's density per unit solid angle at a world direction (unit), from IEEE-exact
  /// operations only; 0 where the environment has no light.
  float density(const Eigen::Vector3f& world) const;
  /// Pixel (i, j)'s probability over its solid angle but for the 1 / sin(theta) of its row:
  /// density = this / sin(theta) at the direction's polar angle theta.
  float density_times_sin(int i, int j) const;
};
EnvironmentDistribution environment_distribution(const EnvironmentImage& env, const Eigen::Vector3f& up, float rotation_deg);

/// E(up) / pi, the irradiance over pi of a surface facing the environment's up (+y, the world's
/// up), from the image's full pixels, times `intensity`: the mean of
/// what the ground's occlusion rays see where nothing blocks them.
Eigen::Vector3f upward_irradiance(const EnvironmentImage& env, float intensity);

/// The world direction of the environment's direction `d` (its own frame: +y up), under the same
/// placement as irradiance_map().
Eigen::Vector3f environment_to_world(const Eigen::Vector3f& d, const Eigen::Vector3f& up, float rotation_deg);

}  // namespace meshtour
