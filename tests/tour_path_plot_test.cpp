// The --plot image of `meshtour path` (tour/path_plot.h): the layout's size, the heat map's cells
// in their places with their weights' colours, the colour bar, the curves and the legend drawn,
// the same bytes every time, and the PNG written as drawn.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "pathgen/paper_path.h"
#include "tour/path_plot.h"

namespace {

using namespace meshtour;
using Rgb = std::array<std::uint8_t, 3>;

// A UV sphere, taller than wide, with uneven face weights: an analysed surface made up
// (pathgen's own stages are tested elsewhere), so that the plot has varied cells.
SurfaceAnalysis made_up_surface() {
  SurfaceAnalysis s;
  const int around = 48, along = 24;
  for (int i = 0; i <= along; ++i)
    for (int k = 0; k < around; ++k) {
      const double polar = std::numbers::pi * (i + 0.5) / (along + 1), a = 2 * std::numbers::pi * k / around;
      s.positions.emplace_back(0.3 * std::sin(polar) * std::sin(a), 0.4 * std::cos(polar), 0.3 * std::sin(polar) * std::cos(a));
    }
  for (int i = 0; i < along; ++i)
    for (int k = 0; k < around; ++k) {
      const auto v = [&](int ii, int kk) { return static_cast<std::uint32_t>(ii * around + (kk % around)); };
      s.triangles.push_back({v(i, k), v(i + 1, k + 1), v(i, k + 1)});
      s.triangles.push_back({v(i, k), v(i + 1, k), v(i + 1, k + 1)});
    }
  for (std::size_t f = 0; f < s.triangles.size(); ++f) {
    s.face_weight.push_back(1.0 + static_cast<double>((f * 7919) % 13));
    s.face_patch.push_back(static_cast<int>(f % 97));
  }
  s.patch_count = 97;
  return s;
}

const PaperPathResult& path() {
  static const PaperPathResult result = compute_paper_path(made_up_surface(), PaperPathOptions{});
  return result;
}

Rgb pixel(const PlotImage& image, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
  return {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
}

std::size_t count_colour(const PlotImage& image, const PlotRect& r, const Rgb& colour) {
  std::size_t n = 0;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) n += pixel(image, x, y) == colour;
  return n;
}

TEST(TourPathPlot, WeightColoursRunFromDarkBlueToYellowAndClamp) {
  EXPECT_EQ(weight_color(0.0), (Rgb{68, 1, 84}));
  EXPECT_EQ(weight_color(0.5), (Rgb{33, 145, 140}));
  EXPECT_EQ(weight_color(1.0), (Rgb{253, 231, 37}));
  EXPECT_EQ(weight_color(-3.0), weight_color(0.0));
  EXPECT_EQ(weight_color(7.0), weight_color(1.0));
  // Brighter (summed channels, green weighted as the eye does) with every step up the ramp.
  const auto luma = [](const Rgb& c) { return 0.3 * c[0] + 0.6 * c[1] + 0.1 * c[2]; };
  for (int k = 0; k < 100; ++k) EXPECT_LT(luma(weight_color(k / 100.0)), luma(weight_color((k + 1) / 100.0))) << k;
}

TEST(TourPathPlot, ImageHasTheLayoutsSizeAndIsTheSameEveryTime) {
  const PathPlotLayout layout = path_plot_layout();
  const PlotImage image = render_path_plot(path());
  ASSERT_EQ(image.width, layout.width);
  ASSERT_EQ(image.height, layout.height);
  ASSERT_EQ(image.rgb.size(), static_cast<std::size_t>(layout.width) * layout.height * 3);
  EXPECT_EQ(render_path_plot(path()).rgb, image.rgb);
  // The regions lie inside the image and do not overlap the heat map.
  for (const PlotRect& r : {layout.heat_map, layout.colour_bar, layout.legend}) {
    EXPECT_TRUE(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= layout.width && r.y1 <= layout.height && r.x0 < r.x1 && r.y0 < r.y1);
  }
  EXPECT_LE(layout.heat_map.x1, layout.colour_bar.x0);
  EXPECT_LE(layout.heat_map.y1, layout.legend.y0);
}

TEST(TourPathPlot, CellsShowTheirWeightsWhereTheyLie) {
  // Each cell's centre shows the colour of its weight (or the empty grey) unless a curve or a
  // marker is drawn over it: row 0 (the bottom of the cylinder) at the bottom, column 0 at the left.
  const PaperPathResult& r = path();
  const PlotImage image = render_path_plot(r);
  const PlotRect map = path_plot_layout().heat_map;
  const int rows = r.grid.rows, columns = r.grid.columns;
  ASSERT_GT(rows, 1);
  ASSERT_GT(columns, 1);
  namespace c = plot_colors;
  int matching = 0, covered = 0;
  bool varied = false;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) {
      const int x = map.x0 + static_cast<int>((j + 0.5) / columns * (map.x1 - map.x0));
      const int y = map.y0 + static_cast<int>((1.0 - (i + 0.5) / rows) * (map.y1 - map.y0));
      const Rgb expected = r.grid.empty(i, j) ? c::empty_cell : weight_color(r.grid.at(i, j) / r.metrics.weight_max);
      const Rgb shown = pixel(image, x, y);
      if (shown == expected) {
        ++matching;
        varied = varied || expected != weight_color(0.0);
      } else {
        ++covered;
        EXPECT_TRUE(shown == c::base || shown == c::gaze || shown == c::position || shown == c::control_ring ||
                    shown == c::start)
            << "cell (" << i << ", " << j << ") shows neither its colour nor a curve";
      }
    }
  EXPECT_GT(matching, rows * columns / 2) << covered << " cells covered by curves";
  EXPECT_TRUE(varied);
  // The curves, markers and start are drawn on the map.
  for (const Rgb& mark : {c::base, c::gaze, c::position, c::start}) EXPECT_GT(count_colour(image, map, mark), 50u);
}

TEST(TourPathPlot, ColourBarAndLegend) {
  const PathPlotLayout layout = path_plot_layout();
  const PlotImage image = render_path_plot(path());
  const PlotRect bar = layout.colour_bar;
  const int middle = (bar.x0 + bar.x1) / 2;
  EXPECT_EQ(pixel(image, middle, bar.y0), weight_color(1.0));      // Wmax at the top
  EXPECT_EQ(pixel(image, middle, bar.y1 - 1), weight_color(0.0));  // 0 at the bottom
  const PlotRect& legend = layout.legend;
  EXPECT_EQ(pixel(image, legend.x0 + 2, legend.y0 + 2), plot_colors::legend_box);
  EXPECT_GT(count_colour(image, legend, plot_colors::legend_text), 200u);  // its labels
  EXPECT_GT(count_colour(image, legend, plot_colors::empty_cell), 100u);   // the empty-cell sample
  // The image's corner is background.
  EXPECT_EQ(pixel(image, 0, 0), plot_colors::background);
}

TEST(TourPathPlot, WrittenAsDrawn) {
  const auto dir = test::scratch_dir();
  PlotImage image{7, 5, {}};
  for (int k = 0; k < 7 * 5 * 3; ++k) image.rgb.push_back(static_cast<std::uint8_t>(k * 7));
  write_plot_image(image, dir / "plot.png");
  OIIO::ImageBuf read((dir / "plot.png").string());
  ASSERT_TRUE(read.read(0, 0, true, OIIO::TypeDesc::UINT8)) << read.geterror();
  ASSERT_EQ(read.spec().width, 7);
  ASSERT_EQ(read.spec().height, 5);
  ASSERT_EQ(read.spec().nchannels, 3);
  std::vector<std::uint8_t> pixels(image.rgb.size());
  read.get_pixels(read.roi(), OIIO::TypeDesc::UINT8, pixels.data());
  EXPECT_EQ(pixels, image.rgb);
  // A type OpenImageIO cannot write is refused, and nothing is left behind.
  EXPECT_THROW(write_plot_image(image, dir / "plot.notanimage"), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "plot.notanimage"));
}

}  // namespace
