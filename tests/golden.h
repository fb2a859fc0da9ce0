#pragma once
// The golden-image comparison shared by tests/golden_*_test.cpp.
//
// Metric (OpenImageIO's ImageBufAlgo::compare, the same as idiff) on 8-bit sRGB PNGs:
//  - a pixel "fails" when any channel differs by more than 2/255: within one machine renders are
//    bit-identical, but another CPU may make Embree pick another ISA kernel or libm round
//    differently, which moves a silhouette pixel or flips a grazing shadow ray;
//  - the test fails when more than `fail_fraction` of the pixels fail (each test states its value
//    and why: a real change of lighting, framing or geometry moves far more), or when any pixel
//    differs by more than 0.25 (a missing or misplaced part, whatever its size).
// On failure the actual image and a x16 difference image are written to build-test/golden-results/.
//
// To regenerate the references on purpose (after a deliberate change to the look):
//   GOLDEN_UPDATE=1 ctest --test-dir build-test -L golden
// then look at the new images and commit them.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "helpers.h"
#include "tracer/tracer.h"

namespace meshtour::test {

inline bool golden_update_requested() {
  const char* v = std::getenv("GOLDEN_UPDATE");
  return v && std::string(v) == "1";
}

/// Compares the PNG `actual_file` with golden_images/<name>.png (or copies it there under
/// GOLDEN_UPDATE=1); on failure writes a x16 difference image beside `actual_file`.
inline void compare_png_with_golden(const std::filesystem::path& actual_file, const std::string& name, double fail_fraction) {
  constexpr float kPixelFail = 2.0f / 255.0f;
  constexpr float kHardFail = 0.25f;
  const auto golden = source_dir() / "golden_images" / (name + ".png");
  const auto out_dir = actual_file.parent_path();
  if (golden_update_requested()) {
    std::filesystem::create_directories(golden.parent_path());
    std::filesystem::copy_file(actual_file, golden, std::filesystem::copy_options::overwrite_existing);
    GTEST_SKIP() << "GOLDEN_UPDATE=1: rewrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing; create it with GOLDEN_UPDATE=1";
  OIIO::ImageBuf actual(actual_file.string()), reference(golden.string());
  ASSERT_TRUE(actual.read() && reference.read()) << actual.geterror() << reference.geterror();
  ASSERT_EQ(actual.spec().width, reference.spec().width);
  ASSERT_EQ(actual.spec().height, reference.spec().height);
  ASSERT_EQ(actual.spec().nchannels, reference.spec().nchannels);
  const auto result = OIIO::ImageBufAlgo::compare(actual, reference, kPixelFail, kPixelFail);
  const double pixels = static_cast<double>(actual.spec().width) * actual.spec().height;
  const double failing = static_cast<double>(result.nfail) / pixels;
  const bool ok = failing <= fail_fraction && result.maxerror <= kHardFail;
  if (!ok) {
    OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(actual, reference);
    diff = OIIO::ImageBufAlgo::mul(diff, 16.0f);
    diff.write((out_dir / (name + ".diff.png")).string());
  }
  EXPECT_TRUE(ok) << name << ": " << result.nfail << " pixels (" << 100 * failing << " %) differ by more than 2/255"
                  << ", max error " << result.maxerror << " at (" << result.maxx << ", " << result.maxy << ")"
                  << ", mean error " << result.meanerror << "; see " << out_dir / (name + ".diff.png")
                  << " and " << actual_file;
}

/// Compares `image` with golden_images/<name>.png (or rewrites it under GOLDEN_UPDATE=1).
/// Mean absolute difference of two renders' display values (sRGB 8-bit, all channels), in 0..255.
inline double mean_pixel_difference(const Image& a, const Image& b) {
  const auto pa = a.to_srgb8(), pb = b.to_srgb8();
  EXPECT_EQ(pa.size(), pb.size());
  const std::size_t n = std::min(pa.size(), pb.size());
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += std::abs(static_cast<int>(pa[i]) - static_cast<int>(pb[i]));
  return n ? sum / static_cast<double>(n) : 0.0;
}

inline void compare_with_golden(const Image& image, const std::string& name, double fail_fraction) {
  const auto out_dir = std::filesystem::path(MESHTOUR_BINARY_DIR) / "golden-results";
  std::filesystem::create_directories(out_dir);
  const auto actual_file = out_dir / (name + ".actual.png");
  write_image(image, actual_file);
  compare_png_with_golden(actual_file, name, fail_fraction);
}

}  // namespace meshtour::test
