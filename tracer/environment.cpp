#include "tracer/environment.h"

#include <Eigen/Geometry>
#include <OpenImageIO/imageio.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/portable_math.h"
#include "mesh/image_probe.h"
#include "tracer/color.h"

namespace meshtour {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// The environment's frame in the world: +y on `up`, -z on the horizontal direction nearest the
// world's -z (else +x), turned about up.
Eigen::Matrix3f world_from_environment(const Eigen::Vector3f& up_in, float rotation_deg) {
  const Eigen::Vector3f up = up_in.normalized();
  Eigen::Vector3f back = Eigen::Vector3f::UnitZ() - up * up.z();  // the environment's +z
  if (back.squaredNorm() < 1e-6f) back = Eigen::Vector3f::UnitX() - up * up.x();
  back.normalize();
  const Eigen::Vector3f right = up.cross(back);  // +x = y cross z
  const float a = rotation_deg * kPi / 180.0f, c = std::cos(a), s = std::sin(a);
  const Eigen::Vector3f x = c * right - s * back, z = s * right + c * back;
  Eigen::Matrix3f m;
  m.col(0) = x;
  m.col(1) = up;
  m.col(2) = z;
  return m;
}

// The direction (environment frame) through the centre of pixel (i, j), and its solid angle.
// IEEE-exact angles (portable_sincos_turns), so that what is built from it (the irradiance map)
// is the same on every node of a farm.
Eigen::Vector3f pixel_direction(const EnvironmentImage& env, int i, int j, float& solid_angle) {
  double sin_theta = 0.0, cos_theta = 0.0, sin_phi = 0.0, cos_phi = 0.0;
  portable_sincos_turns(0.5 * (j + 0.5) / env.height, sin_theta, cos_theta);  // from the zenith
  portable_sincos_turns((i + 0.5) / env.width - 0.5, sin_phi, cos_phi);
  solid_angle = static_cast<float>((2.0 * std::numbers::pi / env.width) * (std::numbers::pi / env.height) * sin_theta);
  // u = 0.5 (phi 0) looks along -z; phi grows towards +x.
  return Eigen::Vector3d(sin_theta * sin_phi, cos_theta, -sin_theta * cos_phi).cast<float>();
}

// An environment at most `kWidth` pixels wide: each smaller pixel averages the pixels it covers,
// weighted by their solid angle, so that the light's energy stays as it was.
EnvironmentImage downsampled(EnvironmentImage env, int kWidth) {
  if (env.width <= kWidth) return env;
  EnvironmentImage small;
  small.width = kWidth;
  small.height = std::max(1, static_cast<int>(std::lround(static_cast<double>(env.height) * kWidth / env.width)));
  small.source = env.source;
  std::vector<double> sum(static_cast<std::size_t>(small.width) * small.height * 3, 0.0), weight(static_cast<std::size_t>(small.width) * small.height, 0.0);
  for (int j = 0; j < env.height; ++j) {
    const double w = std::sin((j + 0.5) / env.height * std::numbers::pi);
    const int sj = std::min(small.height - 1, static_cast<int>(static_cast<long long>(j) * small.height / env.height));
    for (int i = 0; i < env.width; ++i) {
      const int si = std::min(small.width - 1, static_cast<int>(static_cast<long long>(i) * small.width / env.width));
      const std::size_t d = static_cast<std::size_t>(sj) * small.width + si;
      for (int c = 0; c < 3; ++c) sum[d * 3 + c] += w * env.rgb[(static_cast<std::size_t>(j) * env.width + i) * 3 + c];
      weight[d] += w;
    }
  }
  small.rgb.resize(sum.size());
  for (std::size_t d = 0; d < weight.size(); ++d)
    for (int c = 0; c < 3; ++c) small.rgb[d * 3 + c] = weight[d] > 0 ? static_cast<float>(sum[d * 3 + c] / weight[d]) : 0.0f;
  return small;
}

}  // namespace

Eigen::Vector3f IrradianceMap::at(float row, float column) const {
  const float r = std::clamp(row, 0.0f, static_cast<float>(height - 1));
  const int j0 = std::min(static_cast<int>(r), height - 2), j1 = j0 + 1;
  const float fr = std::clamp(r - static_cast<float>(j0), 0.0f, 1.0f);
  const float c = column - std::floor(column / static_cast<float>(width)) * static_cast<float>(width);  // in [0, width]
  const int i0 = std::min(static_cast<int>(c), width - 1), i1 = (i0 + 1) % width;
  const float fc = std::clamp(c - static_cast<float>(i0), 0.0f, 1.0f);
  const auto texel = [&](int i, int j) { return Eigen::Map<const Eigen::Vector3f>(&rgb[(static_cast<std::size_t>(j) * width + i) * 3]); };
  return (1.0f - fr) * ((1.0f - fc) * texel(i0, j0) + fc * texel(i1, j0)) + fr * ((1.0f - fc) * texel(i0, j1) + fc * texel(i1, j1));
}

Eigen::Vector3f IrradianceMap::operator()(const Eigen::Vector3f& n) const {
  const Eigen::Vector3f d = environment_from_world * n;
  const double theta = portable_atan2(std::sqrt(double(d.x()) * d.x() + double(d.z()) * d.z()), d.y());
  const double phi = portable_atan2(d.x(), -d.z());  // u = 0.5 (phi 0) looks along -z
  return at(static_cast<float>(theta / std::numbers::pi * (height - 1)), static_cast<float>((phi / (2.0 * std::numbers::pi) + 0.5) * width - 0.5));
}

Eigen::Vector3f environment_to_world(const Eigen::Vector3f& d, const Eigen::Vector3f& up, float rotation_deg) {
  return world_from_environment(up, rotation_deg) * d;
}

EnvironmentRadiance environment_radiance(std::shared_ptr<const EnvironmentImage> env, const Eigen::Vector3f& up, float rotation_deg,
                                         float intensity) {
  EnvironmentRadiance out;
  out.image = std::move(env);
  out.environment_from_world = world_from_environment(up, rotation_deg).transpose();  // a rotation
  out.intensity = intensity;
  return out;
}

Eigen::Vector3f EnvironmentRadiance::operator()(const Eigen::Vector3f& world) const {
  const EnvironmentImage& env = *image;
  const Eigen::Vector3f d = environment_from_world * world;
  // pixel_direction() inverted: theta from the zenith, phi from -z towards +x (portable: the
  // same bits on every CPU).
  const double sin_theta = std::sqrt(static_cast<double>(d.x()) * d.x() + static_cast<double>(d.z()) * d.z());
  const float theta = static_cast<float>(portable_atan2(sin_theta, d.y())), phi = static_cast<float>(portable_atan2(d.x(), -d.z()));
  return at((phi / (2.0f * kPi) + 0.5f) * static_cast<float>(env.width) - 0.5f, theta / kPi * static_cast<float>(env.height) - 0.5f);
}

Eigen::Vector3f EnvironmentRadiance::at(float x, float y_unclamped) const {
  const EnvironmentImage& env = *image;
  const float y = std::clamp(y_unclamped, 0.0f, static_cast<float>(env.height - 1));
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy), j1 = std::min(j0 + 1, env.height - 1);
  const auto texel = [&](int i, int j) {
    i = ((i % env.width) + env.width) % env.width;
    const float* p = &env.rgb[(static_cast<std::size_t>(j) * env.width + i) * 3];
    return Eigen::Vector3f(p[0], p[1], p[2]);
  };
  const Eigen::Vector3f top = (1.0f - ax) * texel(i0, j0) + ax * texel(i0 + 1, j0), bottom = (1.0f - ax) * texel(i0, j1) + ax * texel(i0 + 1, j1);
  return intensity * ((1.0f - ay) * top + ay * bottom);
}

namespace {
// The index k in [0, n) with cdf[k] <= u < cdf[k + 1] (cdf[0] = 0 <= u < 1 = cdf[n]): never an
// empty bin. `within` is where u falls in bin k, in [0, 1). `guide` (n + 1 values, from
// guide_table) narrows the search to the bins that u's n-th of [0, 1) spans; the answer is the
// one bin that holds u either way, so the guide changes the time, never the pick.
int invert_cdf(const float* cdf, const int* guide, int n, float u, float& within) {
  int lo = 0, hi = n;  // cdf[lo] <= u < cdf[hi] (cdf[n] = 1 > u)
  const int bucket = std::clamp(static_cast<int>(u * static_cast<float>(n)), 0, n - 1);
  const int guide_lo = guide[bucket], guide_hi = std::min(n, guide[bucket + 1] + 1);
  if (cdf[guide_lo] <= u && u < cdf[guide_hi]) lo = guide_lo, hi = guide_hi;  // else rounding put u outside: search all
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid;
  }
  const float width = cdf[lo + 1] - cdf[lo];
  within = width > 0.0f ? std::clamp((u - cdf[lo]) / width, 0.0f, 0x1.fffffep-1f) : 0.5f;
  return lo;
}

// guide[b] = the bin that holds b / n, for b = 0 ... n (the last is n - 1: u < 1).
void guide_table(const float* cdf, int n, int* guide) {
  int k = 0;
  for (int b = 0; b <= n; ++b) {
    const float u = std::min(static_cast<float>(b) / static_cast<float>(n), 0x1.fffffep-1f);
    while (k + 1 < n && cdf[k + 1] <= u) ++k;
    guide[b] = k;
  }
}
}  // namespace

EnvironmentDistribution environment_distribution(const EnvironmentImage& env, const Eigen::Vector3f& up, float rotation_deg) {
  EnvironmentDistribution out;
  out.world_from_environment = world_from_environment(up, rotation_deg);
  out.environment_from_world = out.world_from_environment.transpose();
  const int w = env.width, h = env.height;
  if (w <= 0 || h <= 0) return out;
  std::vector<double> luminance(static_cast<std::size_t>(w) * h), sin_row(static_cast<std::size_t>(h));
  for (int j = 0; j < h; ++j) {
    // sin of the row centre's polar angle (half a turn from the zenith to the nadir).
    double cos_theta = 0.0;
    portable_sincos_turns(0.5 * (j + 0.5) / h, sin_row[static_cast<std::size_t>(j)], cos_theta);
    for (int i = 0; i < w; ++i) {
      const float* p = &env.rgb[(static_cast<std::size_t>(j) * w + i) * 3];
      luminance[static_cast<std::size_t>(j) * w + i] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
  }
  // A pixel's weight: the largest luminance of it and its eight neighbours (wrapping round the up
  // axis, clamped at the poles) times the row's sin(theta) (its solid angle but for constant
  // factors), in double (the sums must not lose the dim rows under a bright sun). The radiance is
  // looked up bilinearly between pixel centres, so a sun's light reaches half a pixel beyond its
  // pixels: a density of the pixels' own luminance would be the dim sky's there, and the few
  // rays that land in that fringe would carry the sun's radiance over the sky's density (white
  // fireflies). The neighbours' largest bounds the bilinear value anywhere in the pixel.
  std::vector<double> weight(static_cast<std::size_t>(w) * h);
  std::vector<double> row_sum(static_cast<std::size_t>(h), 0.0);
  double total = 0.0, plain_total = 0.0, sin_sum = 0.0;
  for (int j = 0; j < h; ++j) {
    const double sin_theta = sin_row[static_cast<std::size_t>(j)];
    for (int i = 0; i < w; ++i) {
      double largest = 0.0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int jj = std::clamp(j + dj, 0, h - 1), ii = (i + di + w) % w;
          largest = std::max(largest, luminance[static_cast<std::size_t>(jj) * w + ii]);
        }
      const double value = largest * sin_theta;
      weight[static_cast<std::size_t>(j) * w + i] = value;
      row_sum[static_cast<std::size_t>(j)] += value;
      plain_total += luminance[static_cast<std::size_t>(j) * w + i] * sin_theta;
    }
    total += row_sum[static_cast<std::size_t>(j)];
    sin_sum += sin_theta * w;
  }
  if (!(total > 0.0) || !std::isfinite(total)) return out;
  // The peak: the share of the light (the pixels' own luminance) in pixels brighter than four
  // times the solid-angle mean.
  const double mean_luminance = plain_total / sin_sum;
  double peak = 0.0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double value = luminance[static_cast<std::size_t>(j) * w + i];
      if (value > 4.0 * mean_luminance) peak += value * sin_row[static_cast<std::size_t>(j)];
    }
  out.peak_share = static_cast<float>(peak / plain_total);
  out.width = w;
  out.height = h;
  out.row_cdf.resize(static_cast<std::size_t>(h) + 1);
  out.column_cdf.resize(static_cast<std::size_t>(h) * (w + 1));
  out.pixel_probability.resize(weight.size());
  double acc = 0.0;
  for (int j = 0; j < h; ++j) {
    out.row_cdf[static_cast<std::size_t>(j)] = static_cast<float>(acc / total);
    acc += row_sum[static_cast<std::size_t>(j)];
    float* cdf = &out.column_cdf[static_cast<std::size_t>(j) * (w + 1)];
    double in_row = 0.0;
    const double rs = row_sum[static_cast<std::size_t>(j)];
    for (int i = 0; i < w; ++i) {
      cdf[i] = rs > 0.0 ? static_cast<float>(in_row / rs) : static_cast<float>(i) / static_cast<float>(w);
      in_row += weight[static_cast<std::size_t>(j) * w + i];
      out.pixel_probability[static_cast<std::size_t>(j) * w + i] = static_cast<float>(weight[static_cast<std::size_t>(j) * w + i] / total);
    }
    cdf[w] = 1.0f;
  }
  out.row_cdf[static_cast<std::size_t>(h)] = 1.0f;
  out.row_guide.resize(out.row_cdf.size());
  guide_table(out.row_cdf.data(), h, out.row_guide.data());
  out.column_guide.resize(out.column_cdf.size());
  for (int j = 0; j < h; ++j) {
    const std::size_t row = static_cast<std::size_t>(j) * (w + 1);
    guide_table(&out.column_cdf[row], w, &out.column_guide[row]);
  }
  return out;
}

Eigen::Vector3f upward_irradiance(const EnvironmentImage& env, float intensity) {
  // Sum of L cos(theta) sin(theta) dtheta dphi / pi over the upper rows: (pi / h)(2 pi / w) / pi.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const int w = env.width, h = env.height;
  for (int j = 0; j < h / 2 + (h % 2); ++j) {
    double sin_theta = 0.0, cos_theta = 0.0;
    portable_sincos_turns(0.5 * (j + 0.5) / h, sin_theta, cos_theta);
    if (!(cos_theta > 0.0)) continue;
    for (int i = 0; i < w; ++i) {
      const float* p = &env.rgb[(static_cast<std::size_t>(j) * w + i) * 3];
      sum += Eigen::Vector3d(p[0], p[1], p[2]) * (cos_theta * sin_theta);
    }
  }
  return w > 0 && h > 0 ? Eigen::Vector3f((sum * (2.0 * std::numbers::pi / (static_cast<double>(w) * h)) * intensity).cast<float>())
                        : Eigen::Vector3f::Zero();
}

void EnvironmentDistribution::pick(float u, float v, int& i, int& j, float& fu, float& fv) const {
  j = invert_cdf(row_cdf.data(), row_guide.data(), height, u, fv);
  const std::size_t row = static_cast<std::size_t>(j) * (width + 1);
  i = invert_cdf(&column_cdf[row], &column_guide[row], width, v, fu);
}

float EnvironmentDistribution::density_times_sin(int i, int j) const {
  // p / (d_phi d_theta) with d_phi = 2 pi / width, d_theta = pi / height.
  return pixel_probability[static_cast<std::size_t>(j) * width + i] * static_cast<float>(width) * static_cast<float>(height) /
         (2.0f * kPi * kPi);
}

float EnvironmentDistribution::density(const Eigen::Vector3f& world) const {
  if (empty()) return 0.0f;
  const Eigen::Vector3f d = environment_from_world * world;
  const double sin_theta = std::sqrt(static_cast<double>(d.x()) * d.x() + static_cast<double>(d.z()) * d.z());
  const double theta = portable_atan2(sin_theta, d.y()), phi = portable_atan2(d.x(), -d.z());
  const int j = std::clamp(static_cast<int>(theta / std::numbers::pi * height), 0, height - 1);
  const int i = std::clamp(static_cast<int>((phi / (2.0 * std::numbers::pi) + 0.5) * width), 0, width - 1);
  return density_times_sin(i, j) / static_cast<float>(std::max(sin_theta, 1e-6));
}

IrradianceMap irradiance_map(const EnvironmentImage& full, const Eigen::Vector3f& up, float rotation_deg, float intensity) {
  // 256 x 128 pixels hold an environment's irradiance: it is the image blurred by a cosine lobe.
  const EnvironmentImage env = downsampled(full, 256);
  // The lit pixels, as columns (structure of arrays) for the texel loop below.
  std::vector<float> dx, dy, dz, lr, lg, lb;
  for (int j = 0; j < env.height; ++j)
    for (int i = 0; i < env.width; ++i) {
      float d_omega = 0.0f;
      const Eigen::Vector3f d = pixel_direction(env, i, j, d_omega);
      const float* p = &env.rgb[(static_cast<std::size_t>(j) * env.width + i) * 3];
      if (!(p[0] > 0.0f || p[1] > 0.0f || p[2] > 0.0f)) continue;
      dx.push_back(d.x()), dy.push_back(d.y()), dz.push_back(d.z());
      lr.push_back(p[0] * d_omega), lg.push_back(p[1] * d_omega), lb.push_back(p[2] * d_omega);
    }
  IrradianceMap map;
  map.width = IrradianceMap::kWidth;
  map.height = IrradianceMap::kHeight;
  map.environment_from_world = world_from_environment(up, rotation_deg).transpose();  // a rotation
  map.rgb.resize(static_cast<std::size_t>(map.width) * map.height * 3);
  // Rows in parallel; within a row, kGroup texels at once, each with its own sums over the pixels
  // in one fixed order (the inner loop runs across the texels, so the compiler makes it vector
  // code without reordering any texel's sum): the map does not depend on the threads, and it
  // takes a fraction of the time one texel at a time took (--environment neutral's whole set-up
  // fell from 0.60 to 0.26 s of CPU).
  constexpr int kGroup = 8;
  static_assert(IrradianceMap::kWidth % kGroup == 0);
  const std::size_t count = dx.size(), block = static_cast<std::size_t>(env.width);
  tbb::parallel_for(0, map.height, [&](int j) {
    double sin_theta = 0.0, cos_theta = 0.0;
    portable_sincos_turns(0.5 * j / (map.height - 1), sin_theta, cos_theta);  // rows from the zenith to the nadir
    for (int i0 = 0; i0 < map.width; i0 += kGroup) {
      float nx[kGroup], ny[kGroup], nz[kGroup];
      for (int t = 0; t < kGroup; ++t) {
        double sin_phi = 0.0, cos_phi = 0.0;
        portable_sincos_turns((i0 + t + 0.5) / map.width - 0.5, sin_phi, cos_phi);
        nx[t] = static_cast<float>(sin_theta * sin_phi), ny[t] = static_cast<float>(cos_theta), nz[t] = static_cast<float>(-sin_theta * cos_phi);
      }
      // Per texel in float over a block of env.width pixels, the blocks summed in double (a sum
      // of up to 32768 terms).
      double er[kGroup] = {}, eg[kGroup] = {}, eb[kGroup] = {};
      for (std::size_t start = 0; start < count; start += block) {
        float sr[kGroup] = {}, sg[kGroup] = {}, sb[kGroup] = {};
        const std::size_t end = std::min(count, start + block);
        for (std::size_t k = start; k < end; ++k) {
          const float x = dx[k], y = dy[k], z = dz[k], r = lr[k], g = lg[k], b = lb[k];
          for (int t = 0; t < kGroup; ++t) {
            const float cosine = std::max(0.0f, nx[t] * x + ny[t] * y + nz[t] * z);
            sr[t] += r * cosine, sg[t] += g * cosine, sb[t] += b * cosine;
          }
        }
        for (int t = 0; t < kGroup; ++t) er[t] += sr[t], eg[t] += sg[t], eb[t] += sb[t];
      }
      const double scale = static_cast<double>(intensity) / std::numbers::pi;
      for (int t = 0; t < kGroup; ++t) {
        float* texel = &map.rgb[(static_cast<std::size_t>(j) * map.width + i0 + t) * 3];
        texel[0] = static_cast<float>(er[t] * scale), texel[1] = static_cast<float>(eg[t] * scale), texel[2] = static_cast<float>(eb[t] * scale);
      }
    }
  });
  return map;
}

EnvironmentImage read_environment(const std::filesystem::path& file) {
  const std::string name = file.string();
  // The checks every texture gets before OpenImageIO reads it (mesh/textures.cpp: damaged PNG
  // chunks, OpenEXR header attributes larger than the file, headers claiming more pixels than it
  // can hold, at most 65536 a side): OpenEXR itself allocates what a header announces.
  probe_image(file, name + ": the environment image");
  auto in = OIIO::ImageInput::open(name);
  if (!in) throw IoError(name + ": cannot read the environment image (" + OIIO::geterror() + ")");
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0) throw InputError(name + ": the environment image has no pixels");
  const double aspect = static_cast<double>(spec.width) / spec.height;
  if (aspect < 1.9 || aspect > 2.1)
    throw InputError(name + ": the environment image is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                     "; an equirectangular (latitude-longitude) image is twice as wide as high");
  if (static_cast<double>(spec.width) * spec.height > 64.0 * 1024 * 1024)
    throw InputError(name + ": the environment image has more than 64 megapixels; scale it down (4k x 2k is plenty for light)");
  if (spec.nchannels < 1 || spec.nchannels > 4)
    throw InputError(name + ": the environment image has " + std::to_string(spec.nchannels) + " channels; save it as RGB");
  // A header may claim more pixels than its file can hold (a damaged file or a decompression
  // bomb): as for textures (mesh/textures.cpp), no codec packs more than 65,536 values into a byte.
  std::error_code ec;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(file, ec));
  if (!ec && static_cast<double>(spec.width) * spec.height * spec.nchannels > 65536.0 * std::max(1.0, file_bytes))
    throw InputError(name + ": the environment image claims " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                     " pixels but the file holds only " + std::to_string(static_cast<long long>(file_bytes)) + " bytes (damaged?)");
  EnvironmentImage env;
  env.width = spec.width;
  env.height = spec.height;
  env.source = name;
  const int channels = spec.nchannels;
  std::vector<float> all(static_cast<std::size_t>(env.width) * env.height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, all.data()))
    throw IoError(name + ": cannot read the environment image (" + in->geterror() + ")");
  const bool encoded = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
  env.rgb.resize(static_cast<std::size_t>(env.width) * env.height * 3);
  for (std::size_t p = 0, n = static_cast<std::size_t>(env.width) * env.height; p < n; ++p)
    for (int c = 0; c < 3; ++c) {
      float v = all[p * channels + static_cast<std::size_t>(std::min(c, channels - 1))];
      if (encoded) v = srgb_to_linear(v);
      if (!(v >= 0.0f) || !std::isfinite(v))
        throw InputError(name + ": the environment image holds a negative or non-finite value at pixel " + std::to_string(p % env.width) +
                         ", " + std::to_string(p / env.width));
      env.rgb[p * 3 + static_cast<std::size_t>(c)] = v;
    }
  return downsampled(std::move(env), 512);
}

EnvironmentImage neutral_environment() {
  EnvironmentImage env;
  env.width = 256;
  env.height = 128;
  env.source = "neutral";
  env.rgb.resize(static_cast<std::size_t>(env.width) * env.height * 3);
  // Soft-edged rectangles in (azimuth, elevation), degrees: a softbox above and in front, a strip
  // on each side, on a light grey room whose floor is darker.
  struct Panel {
    float azimuth, elevation, half_width, half_height, radiance;
  };
  const Panel panels[] = {{0.0f, 60.0f, 50.0f, 22.0f, 5.0f}, {-80.0f, 25.0f, 10.0f, 25.0f, 3.0f}, {95.0f, 20.0f, 10.0f, 20.0f, 2.0f}};
  const auto smooth_inside = [](float distance, float half, float edge) {
    return std::clamp((half - std::abs(distance)) / edge + 0.5f, 0.0f, 1.0f);
  };
  for (int j = 0; j < env.height; ++j)
    for (int i = 0; i < env.width; ++i) {
      const float elevation = 90.0f - (static_cast<float>(j) + 0.5f) / static_cast<float>(env.height) * 180.0f;
      const float azimuth = ((static_cast<float>(i) + 0.5f) / static_cast<float>(env.width) - 0.5f) * 360.0f;
      // The room: walls 0.6, the ceiling a little brighter, the floor 0.25, blended over 20 degrees.
      float v = elevation < 0.0f ? 0.25f + 0.35f * std::clamp(1.0f + elevation / 20.0f, 0.0f, 1.0f) : 0.6f + 0.2f * elevation / 90.0f;
      for (const Panel& p : panels) {
        float da = std::remainder(azimuth - p.azimuth, 360.0f);
        v += p.radiance * smooth_inside(da, p.half_width, 6.0f) * smooth_inside(elevation - p.elevation, p.half_height, 6.0f);
      }
      for (int c = 0; c < 3; ++c) env.rgb[(static_cast<std::size_t>(j) * env.width + i) * 3 + static_cast<std::size_t>(c)] = v;
    }
  // Scale: a surface facing up receives pi (E / pi = 1).
  const float up = upward_irradiance(env, 1.0f).x();
  for (float& v : env.rgb) v /= up;
  return env;
}

std::shared_ptr<const EnvironmentImage> environment_named(const std::string& name_or_file) {
  if (name_or_file == "neutral") {
    static const std::shared_ptr<const EnvironmentImage> neutral = std::make_shared<const EnvironmentImage>(neutral_environment());
    return neutral;
  }
  return std::make_shared<const EnvironmentImage>(read_environment(name_or_file));
}

}  // namespace meshtour
