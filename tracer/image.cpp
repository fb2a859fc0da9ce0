// Frames out: the display transform (exposure, tone curve, sRGB) and PNG/EXR writing.
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"
#include "tracer/color.h"
#include "tracer/image_writer.h"
#include "tracer/tracer.h"

#ifndef MESHTOUR_VERSION
#define MESHTOUR_VERSION "unknown"
#endif

namespace meshtour {
namespace {

// A filmic curve: Narkowicz's fit of the ACES reference rendering transform (2015), a rational
// function with a toe that deepens shadows and a shoulder that rolls highlights off to white
// instead of clipping them; 1.0 maps to 0.80 and 0.18 (mid grey) to 0.27.
float filmic(float x) {
  x = std::max(0.0f, x);
  return std::clamp(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

std::uint8_t to8(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

Eigen::Vector3f Image::display(const Eigen::Vector3f& linear) const {
  const Eigen::Vector3f exposed = linear.cwiseMax(0.0f) * std::exp2(exposure);
  Eigen::Vector3f mapped = exposed;  // clamp: the curve is the clamp below alone
  if (tone_mapping == ToneMapping::filmic) mapped = {filmic(exposed.x()), filmic(exposed.y()), filmic(exposed.z())};
  if (tone_mapping == ToneMapping::pbr_neutral) mapped = pbr_neutral(exposed);
  mapped = mapped.cwiseMax(0.0f).cwiseMin(1.0f);
  return {linear_to_srgb(mapped.x()), linear_to_srgb(mapped.y()), linear_to_srgb(mapped.z())};
}

std::vector<std::uint8_t> Image::to_srgb8() const {
  const std::vector<float>& rgba = display_rgba();
  std::vector<std::uint8_t> out(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t p = 0, n = static_cast<std::size_t>(width) * height; p < n; ++p)
  {
    const Eigen::Vector3f shown = display(Eigen::Vector3f(rgba[p * 4], rgba[p * 4 + 1], rgba[p * 4 + 2]));
    for (int k = 0; k < 3; ++k) out[p * 3 + k] = to8(shown[k]);
  }
  return out;
}

std::vector<std::uint8_t> Image::to_srgba8() const {
  const std::vector<float>& rgba = display_rgba();
  std::vector<std::uint8_t> out(static_cast<std::size_t>(width) * height * 4);
  for (std::size_t p = 0, n = static_cast<std::size_t>(width) * height; p < n; ++p) {
    const float a = std::clamp(rgba[p * 4 + 3], 0.0f, 1.0f);
    // PNG alpha is straight: undo the premultiplication before the (non-linear) display curve.
    const Eigen::Vector3f stored(rgba[p * 4], rgba[p * 4 + 1], rgba[p * 4 + 2]);
    const Eigen::Vector3f shown = display(!transparent ? stored : a > 0.0f ? Eigen::Vector3f(stored / a) : Eigen::Vector3f::Zero());
    for (int k = 0; k < 3; ++k) out[p * 4 + k] = to8(shown[k]);
    out[p * 4 + 3] = to8(a);
  }
  return out;
}

void write_image(const Image& image, const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool png = ext == ".png", exr = ext == ".exr";
  if (!png && !exr) throw InputError(file.string() + ": frames can be written as .png or .exr, not '" + ext + "'");
  const std::size_t npix = static_cast<std::size_t>(image.width) * image.height;
  if (image.rgba.size() != npix * 4 || (!image.denoised.empty() && image.denoised.size() != npix * 4) || (!image.albedo.empty() && image.albedo.size() != npix * 3) ||
      (!image.normal.empty() && image.normal.size() != npix * 3) || (!image.depth.empty() && image.depth.size() != npix))
    throw InputError(file.string() + ": the image's layers do not match its size " + std::to_string(image.width) + "x" +
                     std::to_string(image.height));

  if (png) {
    const auto pixels = image.transparent ? image.to_srgba8() : image.to_srgb8();
    write_8bit_image(file, pixels, image.width, image.height, image.transparent ? 4 : 3, SrgbTag::tagged, "image");
    return;
  }

  // One interleaved float buffer with every layer; OpenEXR stores RGBA and the extra layers
  // as half, depth as float (half's 11-bit mantissa would band the depth of large scenes).
  // The raw (unbiased) frame is the main layer; the denoised one, which the PNG and the video
  // show, a layer beside it, so compositors can choose.
  std::vector<std::string> names = {"R", "G", "B", "A"};
  if (!image.denoised.empty()) names.insert(names.end(), {"denoised.R", "denoised.G", "denoised.B", "denoised.A"});
  if (!image.albedo.empty()) names.insert(names.end(), {"albedo.R", "albedo.G", "albedo.B"});
  if (!image.normal.empty()) names.insert(names.end(), {"N.X", "N.Y", "N.Z"});
  if (!image.depth.empty()) names.push_back("Z");
  const int channels = static_cast<int>(names.size());
  OIIO::ImageSpec spec(image.width, image.height, channels, OIIO::TypeDesc::HALF);
  spec.channelnames = names;
  spec.alpha_channel = 3;
  if (!image.depth.empty()) {
    spec.z_channel = channels - 1;
    spec.channelformats.assign(channels, OIIO::TypeDesc::HALF);
    spec.channelformats.back() = OIIO::TypeDesc::FLOAT;
  }
  spec.attribute("oiio:ColorSpace", "linear");
  spec.attribute("compression", "zip");
  const FrameInfo& info = image.info;
  const OIIO::TypeDesc vec3d(OIIO::TypeDesc::DOUBLE, OIIO::TypeDesc::VEC3);
  spec.attribute("meshtour:version", MESHTOUR_VERSION);
  spec.attribute("meshtour:cameraPosition", vec3d, info.camera.eye.data());
  spec.attribute("meshtour:cameraTarget", vec3d, info.camera.target.data());
  spec.attribute("meshtour:cameraUp", vec3d, info.camera.up.data());
  spec.attribute("meshtour:verticalFovDegrees", static_cast<float>(info.camera.vertical_fov_deg));
  spec.attribute("meshtour:samplesPerPixel", info.samples_per_pixel);
  spec.attribute("meshtour:frame", static_cast<int>(info.frame_index));
  // The render time is the one run-dependent attribute (the issue asks for it in the header);
  // tools comparing frames across runs or farm chunks compare pixels and every other attribute.
  spec.attribute("meshtour:renderSeconds", static_cast<float>(info.render_seconds));
  // The display transform of the PNG frames and the video, so that 'meshtour encode' turns
  // these linear frames into the same 8-bit pixels.
  spec.attribute("meshtour:exposure", image.exposure);
  spec.attribute("meshtour:toneMapping", std::string(tone_mapping_name(image.tone_mapping)));
  // No OpenImageIO timestamp (capDate): an empty DateTime suppresses it.
  spec.attribute("DateTime", "");
  std::vector<float> pixels(npix * channels);
  for (std::size_t p = 0; p < npix; ++p) {
    float* dst = &pixels[p * channels];
    for (int k = 0; k < 4; ++k) *dst++ = image.rgba[p * 4 + k];
    if (!image.denoised.empty())
      for (int k = 0; k < 4; ++k) *dst++ = image.denoised[p * 4 + k];
    if (!image.albedo.empty())
      for (int k = 0; k < 3; ++k) *dst++ = image.albedo[p * 3 + k];
    if (!image.normal.empty())
      for (int k = 0; k < 3; ++k) *dst++ = image.normal[p * 3 + k];
    if (!image.depth.empty()) *dst++ = image.depth[p];
  }
  write_encoded_image(file, spec, OIIO::TypeDesc::FLOAT, pixels.data(), "frame");
}

}  // namespace meshtour
