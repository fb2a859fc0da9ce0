// The poster still (tour/poster.h): which frame it shows, the output checks before any work, the
// frame's own PNG byte for byte at the frames' size, and a centred crop resampled to another size,
// the same bytes every time.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "tour/poster.h"
#include "tour/tour.h"

namespace {

using namespace meshtour;
namespace fs = std::filesystem;

using Rgb = std::array<std::uint8_t, 3>;
constexpr Rgb kRed{220, 30, 30}, kBlue{30, 30, 220}, kGreen{30, 200, 30};

// A width x height RGB frame: the left quarter red, the right quarter blue, the middle green.
std::vector<std::uint8_t> three_bands(int width, int height) {
  std::vector<std::uint8_t> rgb;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Rgb& c = 4 * x < width ? kRed : 4 * x >= 3 * width ? kBlue : kGreen;
      rgb.insert(rgb.end(), c.begin(), c.end());
    }
  return rgb;
}

void write_png(const fs::path& file, const std::vector<std::uint8_t>& rgb, int width, int height) {
  OIIO::ImageBuf image(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8));
  image.set_pixels(image.roi(), OIIO::TypeDesc::UINT8, rgb.data());
  ASSERT_TRUE(image.write(file.string())) << image.geterror();
}

struct Png {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> pixels;
  Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * channels;
    return {pixels[i], pixels[i + 1], pixels[i + 2]};
  }
};

Png read_png(const fs::path& file) {
  OIIO::ImageBuf image(file.string());
  Png png;
  if (!image.read(0, 0, true, OIIO::TypeDesc::UINT8)) {
    ADD_FAILURE() << file << ": " << image.geterror();
    return png;
  }
  png.width = image.spec().width;
  png.height = image.spec().height;
  png.channels = image.spec().nchannels;
  png.pixels.resize(static_cast<std::size_t>(png.width) * png.height * png.channels);
  image.get_pixels(image.roi(), OIIO::TypeDesc::UINT8, png.pixels.data());
  return png;
}

bool near(const Rgb& a, const Rgb& b, int tolerance = 3) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(int{a[c]} - int{b[c]}) > tolerance) return false;
  return true;
}

TEST(TourPoster, IsTheFirstFrameAndTheManifestKeepsTheBestCoveringOne) {
  // best_view_frame (the manifest's, informative): the first of equal maxima, -1 without scores.
  EXPECT_EQ(best_view_frame({}), -1);
  EXPECT_EQ(best_view_frame({0.1, 0.7, 0.3}), 1);
  EXPECT_EQ(best_view_frame({0.2, 0.9, 0.5, 0.9}), 1);
  EXPECT_EQ(best_view_frame({5.0}), 0);
  // The poster is frame 0, the preferred view, whatever covers most.
  EXPECT_EQ(kPosterFrame, 0);
}

TEST(TourPoster, OutputIsCheckedBeforeAnyWork) {
  const fs::path dir = test::scratch_dir();
  EXPECT_NO_THROW(check_poster_output(PosterJob{}));  // no poster asked for
  EXPECT_NO_THROW(check_poster_output(PosterJob{dir / "poster.png", {}}));
  EXPECT_NO_THROW(check_poster_output(PosterJob{dir / "POSTER.PNG", {}}));
  try {
    check_poster_output(PosterJob{dir / "poster.jpg", {}});
    FAIL() << "a .jpg poster was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("name it *.png"), std::string::npos) << e.what();
  }
  try {
    check_poster_output(PosterJob{dir / "missing" / "poster.png", {}});
    FAIL() << "a poster in a missing folder was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

TEST(TourPoster, AtTheFramesSizeThePosterIsTheFramesOwnPng) {
  const fs::path dir = test::scratch_dir();
  const fs::path frame = dir / "frame_000004.png";
  write_png(frame, three_bands(32, 18), 32, 18);
  write_poster_from_png(frame, PosterJob{dir / "poster.png", {}});
  EXPECT_EQ(test::file_bytes(dir / "poster.png"), test::file_bytes(frame));
  // Asking for the frames' own size is the same.
  write_poster_from_png(frame, PosterJob{dir / "same.png", PosterSize{32, 18}});
  EXPECT_EQ(test::file_bytes(dir / "same.png"), test::file_bytes(frame));
  // No poster asked for: nothing is written.
  write_poster_from_png(frame, PosterJob{});
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
  // An unreadable frame is named.
  try {
    write_poster_from_png(dir / "frame_000009.png", PosterJob{dir / "other.png", {}});
    FAIL() << "a missing frame was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_000009.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "other.png"));
}

TEST(TourPoster, AnotherSizeIsACentredCropResampledTheSameEveryTime) {
  const fs::path dir = test::scratch_dir();
  const int width = 64, height = 16;
  const std::vector<std::uint8_t> frame = three_bands(width, height);
  // A square poster of a 4:1 frame keeps its middle half: the green band only.
  write_poster_pixels(frame, width, height, 3, PosterJob{dir / "square.png", PosterSize{8, 8}});
  const Png square = read_png(dir / "square.png");
  ASSERT_EQ(square.width, 8);
  ASSERT_EQ(square.height, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_TRUE(near(square.at(x, y), kGreen)) << x << "," << y;
  // A wider poster keeps the whole width (and crops rows): red at the left, blue at the right.
  write_poster_pixels(frame, width, height, 3, PosterJob{dir / "wide.png", PosterSize{32, 4}});
  const Png wide = read_png(dir / "wide.png");
  ASSERT_EQ(wide.width, 32);
  ASSERT_EQ(wide.height, 4);
  EXPECT_TRUE(near(wide.at(1, 2), kRed));
  EXPECT_TRUE(near(wide.at(16, 2), kGreen));
  EXPECT_TRUE(near(wide.at(30, 2), kBlue));
  // The same pixels give the same file.
  write_poster_pixels(frame, width, height, 3, PosterJob{dir / "square-again.png", PosterSize{8, 8}});
  EXPECT_EQ(test::file_bytes(dir / "square-again.png"), test::file_bytes(dir / "square.png"));
  // From a frame's PNG file, resampled the same way.
  write_png(dir / "frame.png", frame, width, height);
  write_poster_from_png(dir / "frame.png", PosterJob{dir / "from-file.png", PosterSize{8, 8}});
  EXPECT_EQ(read_png(dir / "from-file.png").pixels, square.pixels);
}

}  // namespace
