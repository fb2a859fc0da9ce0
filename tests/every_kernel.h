#pragma once
// The tile kernel is compiled once per x86-64 level (tracer/CMakeLists.txt) and the CPU's widest
// runs: a frame must not depend on which, or a farm of mixed machines would give mixed frames.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "tracer/tracer.h"

namespace meshtour::test {

/// Renders `render()` once with each kernel this CPU runs (MESHTOUR_TILE_KERNEL) and expects the
/// same bits from each: the raw and denoised frames and the albedo and normal layers (the depth
/// too when `depth`). Returns the frames (the baseline's first).
inline std::vector<Image> expect_same_bits_on_every_kernel(const std::function<Image()>& render, const std::string& what,
                                                           bool depth = true) {
  std::vector<Image> images;
  std::vector<std::string> names;
  for (const char* kernel : {"baseline", "x86-64-v3", "x86-64-v4"}) {
    ScopedEnv env("MESHTOUR_TILE_KERNEL", kernel);
    try {
      images.push_back(render());
      names.push_back(kernel);
    } catch (const InputError&) {
      // Not a level this CPU runs (or not an x86-64 build): nothing to compare.
    }
  }
  EXPECT_FALSE(images.empty());
  for (std::size_t i = 1; i < images.size(); ++i) {
    SCOPED_TRACE(names[i] + " vs " + names[0] + ", " + what);
    EXPECT_EQ(0, std::memcmp(images[i].rgba.data(), images[0].rgba.data(), images[0].rgba.size() * sizeof(float)));
    EXPECT_EQ(images[i].denoised.size(), images[0].rgba.size());
    if (images[i].denoised.size() == images[0].denoised.size()) {
      EXPECT_EQ(0, std::memcmp(images[i].denoised.data(), images[0].denoised.data(), images[0].denoised.size() * sizeof(float)));
    }
    EXPECT_EQ(images[i].albedo, images[0].albedo);
    EXPECT_EQ(images[i].normal, images[0].normal);
    if (depth) {
      // (A frame without a depth layer has none to compare; memcmp of null pointers is undefined.)
      EXPECT_EQ(images[i].depth.size(), images[0].depth.size());
      if (!images[0].depth.empty() && images[i].depth.size() == images[0].depth.size()) {
        EXPECT_EQ(0, std::memcmp(images[i].depth.data(), images[0].depth.data(), images[0].depth.size() * sizeof(float)));
      }
    }
  }
  return images;
}

}  // namespace meshtour::test
