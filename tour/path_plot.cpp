#include "tour/path_plot.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "pathgen/path_file.h"

namespace meshtour {
namespace {

using Rgb = std::array<std::uint8_t, 3>;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Small raster with just what the plot needs: filled rectangles, discs and thick polylines.
class Canvas {
public:
  Canvas(int width, int height, Rgb background) : image_{width, height, {}} {
    image_.rgb.resize(static_cast<std::size_t>(width) * height * 3);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) set(x, y, background);
  }
  void set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
    std::copy(c.begin(), c.end(), image_.rgb.begin() + (static_cast<std::ptrdiff_t>(y) * image_.width + x) * 3);
  }
  void rect(int x0, int y0, int x1, int y1, Rgb c) {  // [x0, x1) × [y0, y1)
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) set(x, y, c);
  }
  void disc(double cx, double cy, double radius, Rgb c) {
    for (int y = static_cast<int>(std::floor(cy - radius)); y <= static_cast<int>(std::ceil(cy + radius)); ++y)
      for (int x = static_cast<int>(std::floor(cx - radius)); x <= static_cast<int>(std::ceil(cx + radius)); ++x)
        if ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) <= radius * radius) set(x, y, c);
  }
  // A thick segment: discs stamped every half pixel along it.
  void line(double x0, double y0, double x1, double y1, double width, Rgb c) {
    const double length = std::hypot(x1 - x0, y1 - y0);
    const int steps = std::max(1, static_cast<int>(std::ceil(length * 2.0)));
    for (int k = 0; k <= steps; ++k) {
      const double s = static_cast<double>(k) / steps;
      disc(x0 + s * (x1 - x0), y0 + s * (y1 - y0), width / 2.0, c);
    }
  }
  PlotImage take() { return std::move(image_); }

private:
  PlotImage image_;
};

// Perceptually ordered ramp (dark blue → teal → green → yellow), piecewise linear.
Rgb ramp(double x) {
  static const std::array<std::array<double, 3>, 5> stops = {
      {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};
  x = std::clamp(x, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(x), stops.size() - 2);
  const double f = x - k;
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = static_cast<std::uint8_t>(std::lround(stops[k][c] + f * (stops[k + 1][c] - stops[k][c])));
  return out;
}

}  // namespace

PlotImage render_path_plot(const PaperPathResult& r) {
  constexpr int kPlotWidth = 1200, kPlotHeight = 600, kMargin = 24;
  Canvas canvas(kPlotWidth + 2 * kMargin, kPlotHeight + 2 * kMargin, Rgb{255, 255, 255});
  const int m = r.grid.rows, n = r.grid.columns;
  // Domain → pixels: angle left to right, height bottom to top.
  const auto px = [&](double angle) { return kMargin + angle / kTwoPi * kPlotWidth; };
  const auto py = [&](double u) { return kMargin + (1.0 - u) * kPlotHeight; };

  const double w_max = r.metrics.weight_max > 0.0 ? r.metrics.weight_max : 1.0;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) {
      const Rgb color = r.grid.empty(i, j) ? Rgb{150, 150, 150} : ramp(r.grid.at(i, j) / w_max);
      const int x0 = static_cast<int>(std::lround(px(kTwoPi * j / n))), x1 = static_cast<int>(std::lround(px(kTwoPi * (j + 1) / n)));
      const int y0 = static_cast<int>(std::lround(py(static_cast<double>(i + 1) / m))), y1 = static_cast<int>(std::lround(py(static_cast<double>(i) / m)));
      // One-pixel gaps between cells draw the grid lines.
      canvas.rect(x0 + 1, y0 + 1, x1, y1, color);
    }

  const PaperPathGeometry& g = r.geometry;
  const auto draw_curve = [&](auto height_of, double width, Rgb color) {
    constexpr int kSteps = 4000;
    double last_x = 0.0, last_y = 0.0;
    for (int k = 0; k <= kSteps; ++k) {
      const double t = static_cast<double>(k) / kSteps;
      const double x = px(g.angle(t)), y = py(height_of(t));
      // The angle wraps from 2π to 0 once per loop: do not draw that jump across the plot.
      if (k > 0 && std::abs(x - last_x) < kPlotWidth / 2.0) canvas.line(last_x, last_y, x, y, width, color);
      last_x = x;
      last_y = y;
    }
  };
  draw_curve([&](double t) { return g.position_height(t); }, 2.0, Rgb{230, 0, 230});
  draw_curve([&](double t) { return g.gaze_height(t); }, 2.0, Rgb{0, 220, 255});
  draw_curve([&](double t) { return g.base_height(t); }, 3.0, Rgb{255, 255, 255});

  for (std::size_t j = 0; j < r.control.heights.size(); ++j) {
    canvas.disc(px(r.control.angles[j]), py(r.control.heights[j]), 7.0, Rgb{0, 0, 0});
    canvas.disc(px(r.control.angles[j]), py(r.control.heights[j]), 5.0, Rgb{255, 255, 255});
  }
  // The start: the heaviest cell outlined in red, and red ticks above and below its column.
  const double sx = px(g.angle(g.start_parameter));
  canvas.line(sx, 0, sx, kMargin - 4, 3.0, Rgb{220, 0, 0});
  canvas.line(sx, kMargin + kPlotHeight + 4, sx, 2 * kMargin + kPlotHeight, 3.0, Rgb{220, 0, 0});
  const double cx0 = px(kTwoPi * r.start.column / n), cx1 = px(kTwoPi * (r.start.column + 1) / n);
  const double cy0 = py(static_cast<double>(r.start.row + 1) / m), cy1 = py(static_cast<double>(r.start.row) / m);
  canvas.line(cx0, cy0, cx1, cy0, 2.0, Rgb{220, 0, 0});
  canvas.line(cx1, cy0, cx1, cy1, 2.0, Rgb{220, 0, 0});
  canvas.line(cx1, cy1, cx0, cy1, 2.0, Rgb{220, 0, 0});
  canvas.line(cx0, cy1, cx0, cy0, 2.0, Rgb{220, 0, 0});
  return canvas.take();
}

void write_plot_image(const PlotImage& image, const std::filesystem::path& file) {
  write_file_atomically(file, [&](const std::filesystem::path& temporary) {
    auto out = OIIO::ImageOutput::create(temporary.string());
    if (!out)
      throw InputError("cannot write the plot " + file.string() + ": no image writer for '" +
                       file.extension().string() + "' files; use a .png name");
    const OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    if (!out->open(temporary.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.rgb.data()) ||
        !out->close())
      throw IoError("cannot write the plot " + file.string() + ": " + out->geterror());
  });
}

}  // namespace meshtour
