#pragma once
// The denoiser: a guide from an edge-avoiding a-trous wavelet filter (Dammertz et al. 2010) with
// the variance-guided luminance weights of SVGF's spatial filter (Schied et al. 2017), then a
// weighted least-squares fit of each pixel's neighbourhood by pixel offset and normal tilt (after
// NFOR, Bitterli et al. 2016), applied to the lighting, not the colours: the frame is divided by the light its samples would reflect
// unshadowed (albedo x lights and sky; tracer-computed, noise-free), filtered, and multiplied
// back, so textures, vertex colours and the shading of small bumps stay sharp and only the
// visibility of the lights and the sky, the noise, is filtered (the ratio estimator of Heitz et al.
// 2018, "Combining analytic direct illumination and stochastic shadows"). Frame-local.
//
// Same bits on every CPU: without FMA contraction (-ffp-contract=off for the whole project), with
// IEEE add/multiply/divide/sqrt only and its own rational weight function (no exp, pow or log,
// whose glibc versions differ by CPU). Its hot loops, the a-trous pass and the fit (denoiser_pass.cpp), are
// compiled once per x86-64 level like the tile kernel, and every copy runs each pixel through the
// same operations whatever the vector width (Renderer.SamePixelsWithEveryInstructionSet compares
// the denoised frames too); rows are filtered in parallel, each row's result a function of the
// previous pass only, so the thread count does not change a bit.
#include <array>
#include <vector>

#include "core/huge_page_allocator.h"
#include "tracer/instruction_set.h"

namespace meshtour {

/// What the tracer gathers for the denoiser, per pixel, from the pixel's own samples (a box, not
/// the reconstruction filter).
struct DenoiseGuides {
  int width = 0, height = 0;
  int samples_per_pixel = 1;
  /// The light the samples would reflect if no shadow or occlusion ray were blocked (albedo times
  /// the lights and the sky, with highlights; the background's colour at the pixel's centre row
  /// where the ground and the background are seen), through the reconstruction filter with the
  /// beauty's own sample weights: the frame is divided by it, filtered and multiplied back, so only the visibility is
  /// filtered, and the shading's detail, colour edges and silhouettes stay as the raw frame has them.
  std::vector<float> unshadowed;  ///< 3 per pixel
  std::vector<float> normal;  ///< 3 per pixel: sum of the hit samples' shading normals (0: none hit)
  std::vector<float> depth;   ///< 1 per pixel: nearest hit's distance along the camera axis, +inf if none
  /// Sum and sum of squares of the samples' visibility (luminance / unshadowed luminance, plus
  /// alpha in transparent frames): the variance estimate.
  std::vector<float> moments;  ///< 2 per pixel

  /// Sizes the guides for a frame and clears them (0; depth +inf).
  void reset(int width, int height, int samples_per_pixel);
  /// Sizes the guides for a frame without clearing them: the renderer clears each tile's pixels
  /// while they are in its cache and writes `unshadowed` whole.
  void resize(int width, int height, int samples_per_pixel);
};

struct DenoiseSettings {
  bool transparent = false;  ///< RGB premultiplied; the shadows on the ground are in alpha
  /// A-trous passes (steps 1, 2, 4, ...: 3x3 taps each) over the visibility's luminance, 1..5:
  /// the fit's guide.
  int passes = 2;
  /// The fit's window: the unfiltered visibility of the pixels within fit_radius (a disc:
  /// dx^2 + dy^2 <= r^2 + r, 97 pixels at 5), weighted by normal, depth and the guide, fitted by
  /// offset and normal tilt (denoiser_pass.cpp). 1..8.
  int fit_radius = 5;
  /// Which copy of the a-trous pass runs (the same bits; the renderer picks its tile kernel's).
  using InstructionSet = meshtour::InstructionSet;
  InstructionSet instruction_set = InstructionSet::baseline;
};

/// The denoiser's scratch memory (about 80 MB for 1280x720), kept between frames by the caller:
/// mapping and page-faulting it afresh for every frame cost more than the filter itself.
struct DenoiseWorkspace {
  using Buffer = std::vector<float, HugePageAllocator<float>>;  // first touched a 2 MiB page at a time
  Buffer guides, ping, pong, luma_ping, luma_pong;
};

/// The denoised frame (RGBA, premultiplied like `rgba`, width * height * 4) from the filtered
/// beauty `rgba` and the guides. Uses the calling thread's TBB arena; `workspace` (may be null)
/// is reused memory, its contents do not change the result.
std::vector<float> denoise(const std::vector<float>& rgba, const DenoiseGuides& guides, const DenoiseSettings& settings,
                           DenoiseWorkspace* workspace = nullptr);

}  // namespace meshtour
