// The display tone curves' names and Khronos PBR Neutral (tracer.h), apart from the image writer:
// the scene-file parser and the option registry need them without OpenImageIO.
#include <Eigen/Core>

#include <string_view>
#include <utility>
#include <vector>

#include "tracer/tracer.h"

namespace meshtour {
namespace {

constexpr std::pair<ToneMapping, std::string_view> kToneMappingNames[] = {
    {ToneMapping::filmic, "filmic"}, {ToneMapping::clamp, "clamp"}, {ToneMapping::pbr_neutral, "pbr-neutral"}};

}  // namespace

std::string_view tone_mapping_name(ToneMapping t) {
  for (const auto& [curve, name] : kToneMappingNames)
    if (curve == t) return name;
  return "filmic";
}

std::optional<ToneMapping> tone_mapping_from_name(std::string_view name) {
  for (const auto& [curve, spelled] : kToneMappingNames)
    if (spelled == name) return curve;
  return std::nullopt;
}

std::vector<std::string_view> tone_mapping_names() {
  std::vector<std::string_view> names;
  for (const auto& entry : kToneMappingNames) names.push_back(entry.second);
  return names;
}

// Khronos PBR Neutral (github.com/KhronosGroup/ToneMapping, PBR_Neutral): a toe that takes at most
// 0.04 off (the offset a dielectric's Fresnel adds), values whose largest channel stays under
// 0.76 unchanged, and above that the peak compressed towards 1 and the colour desaturated by the
// share the peak lost.
Eigen::Vector3f pbr_neutral(Eigen::Vector3f c) {
  constexpr float kStartCompression = 0.8f - 0.04f, kDesaturation = 0.15f;
  const float x = c.minCoeff();
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  c.array() -= offset;
  const float peak = c.maxCoeff();
  if (peak < kStartCompression) return c;
  constexpr float d = 1.0f - kStartCompression;
  const float new_peak = 1.0f - d * d / (peak + d - kStartCompression);
  c *= new_peak / peak;
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  return (1.0f - g) * c + Eigen::Vector3f::Constant(g * new_peak);
}

}  // namespace meshtour
