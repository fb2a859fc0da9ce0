#include "tour/path_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <numbers>

#include "core/angles.h"
#include "pathgen/path_file.h"
#include "tour/bitmap_text.h"
#include "tracer/image_writer.h"

namespace meshtour {
namespace {

using Rgb = std::array<std::uint8_t, 3>;
constexpr int kTextScale = 2;  // every label: 12 px per character, 14 px capitals

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
  // A one-pixel outline just outside r.
  void frame(const PlotRect& r, Rgb c) {
    rect(r.x0 - 1, r.y0 - 1, r.x1 + 1, r.y0, c);
    rect(r.x0 - 1, r.y1, r.x1 + 1, r.y1 + 1, c);
    rect(r.x0 - 1, r.y0, r.x0, r.y1, c);
    rect(r.x1, r.y0, r.x1 + 1, r.y1, c);
  }
  void text(int x, int y, std::string_view s, Rgb c) { draw_text(image_, x, y, s, c, kTextScale); }
  PlotImage take() { return std::move(image_); }

private:
  PlotImage image_;
};

std::string format_weight(double w) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", w);
  return text;
}

// Margins around the heat map: tick labels and the y title on the left and top, the x title and
// the legend below, the colour bar and its labels on the right.
constexpr int kLeft = 90, kTop = 44, kPlotWidth = 1200, kPlotHeight = 600;
constexpr int kBarGap = 40, kBarWidth = 28, kRight = 240, kBottom = 132;
constexpr int kCapHeight = 7 * kTextScale;

}  // namespace

PathPlotLayout path_plot_layout() {
  PathPlotLayout l;
  l.width = kLeft + kPlotWidth + kRight;
  l.height = kTop + kPlotHeight + kBottom;
  l.heat_map = {kLeft, kTop, kLeft + kPlotWidth, kTop + kPlotHeight};
  l.colour_bar = {kLeft + kPlotWidth + kBarGap, kTop, kLeft + kPlotWidth + kBarGap + kBarWidth, kTop + kPlotHeight};
  l.legend = {kLeft, kTop + kPlotHeight + 86, kLeft + kPlotWidth, kTop + kPlotHeight + 86 + 40};
  l.text_scale = kTextScale;
  return l;
}

// Perceptually ordered ramp (dark blue → teal → green → yellow), piecewise linear.
Rgb weight_color(double x) {
  static const std::array<std::array<double, 3>, 5> stops = {
      {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};
  x = std::clamp(x, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(x), stops.size() - 2);
  const double f = x - k;
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = static_cast<std::uint8_t>(std::lround(stops[k][c] + f * (stops[k + 1][c] - stops[k][c])));
  return out;
}

PlotImage render_path_plot(const PaperPathResult& r) {
  namespace color = plot_colors;
  const PathPlotLayout layout = path_plot_layout();
  const PlotRect& map = layout.heat_map;
  Canvas canvas(layout.width, layout.height, color::background);
  const int m = r.grid.rows, n = r.grid.columns;
  // Domain → pixels: angle left to right, height bottom to top.
  const auto px = [&](double angle) { return map.x0 + angle / kFullTurn * kPlotWidth; };
  const auto py = [&](double u) { return map.y0 + (1.0 - u) * kPlotHeight; };

  const double w_max = r.metrics.weight_max > 0.0 ? r.metrics.weight_max : 1.0;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) {
      const Rgb c = r.grid.empty(i, j) ? color::empty_cell : weight_color(r.grid.at(i, j) / w_max);
      const int x0 = static_cast<int>(std::lround(px(kFullTurn * j / n))), x1 = static_cast<int>(std::lround(px(kFullTurn * (j + 1) / n)));
      const int y0 = static_cast<int>(std::lround(py(static_cast<double>(i + 1) / m))), y1 = static_cast<int>(std::lround(py(static_cast<double>(i) / m)));
      // One-pixel gaps between cells draw the grid lines.
      canvas.rect(x0 + 1, y0 + 1, x1, y1, c);
    }

  const PaperPathGeometry& g = r.geometry;
  const auto draw_curve = [&](auto height_of, double width, Rgb c) {
    constexpr int kSteps = 4000;
    double last_x = 0.0, last_y = 0.0;
    for (int k = 0; k <= kSteps; ++k) {
      const double t = static_cast<double>(k) / kSteps;
      const double x = px(g.angle(t)), y = py(height_of(t));
      // The angle wraps from 2π to 0 once per loop: do not draw that jump across the plot.
      if (k > 0 && std::abs(x - last_x) < kPlotWidth / 2.0) canvas.line(last_x, last_y, x, y, width, c);
      last_x = x;
      last_y = y;
    }
  };
  draw_curve([&](double t) { return g.position_height(t); }, 2.0, color::position);
  draw_curve([&](double t) { return g.gaze_height(t); }, 2.0, color::gaze);
  draw_curve([&](double t) { return g.base_height(t); }, 3.0, color::base);

  const auto control_point = [&](double x, double y) {
    canvas.disc(x, y, 7.0, color::control_ring);
    canvas.disc(x, y, 5.0, color::base);
  };
  for (std::size_t j = 0; j < r.control.heights.size(); ++j) control_point(px(r.control.angles[j]), py(r.control.heights[j]));
  // The start: the heaviest cell outlined in red, and red ticks above and below its column.
  const double sx = px(g.angle(g.start_parameter));
  canvas.line(sx, map.y0 - 16, sx, map.y0 - 3, 3.0, color::start);
  canvas.line(sx, map.y1 + 3, sx, map.y1 + 12, 3.0, color::start);
  const double cx0 = px(kFullTurn * r.start.column / n), cx1 = px(kFullTurn * (r.start.column + 1) / n);
  const double cy0 = py(static_cast<double>(r.start.row + 1) / m), cy1 = py(static_cast<double>(r.start.row) / m);
  canvas.line(cx0, cy0, cx1, cy0, 2.0, color::start);
  canvas.line(cx1, cy0, cx1, cy1, 2.0, color::start);
  canvas.line(cx1, cy1, cx0, cy1, 2.0, color::start);
  canvas.line(cx0, cy1, cx0, cy0, 2.0, color::start);

  // Axes: a frame, ticks every 45° and every quarter of the height, labelled.
  canvas.frame(map, color::text);
  for (int degrees = 0; degrees <= 360; degrees += 45) {
    const int x = static_cast<int>(std::lround(px(degrees * kFullTurn / 360.0)));
    canvas.rect(x - 1, map.y1, x + 1, map.y1 + 8, color::text);
    const std::string label = std::to_string(degrees) + "°";
    canvas.text(x - text_width(label, kTextScale) / 2, map.y1 + 16, label, color::text);
  }
  for (int quarter = 0; quarter <= 4; ++quarter) {
    const int y = static_cast<int>(std::lround(py(quarter / 4.0)));
    canvas.rect(map.x0 - 8, y - 1, map.x0, y + 1, color::text);
    static const char* const kLabels[] = {"0", "0.25", "0.5", "0.75", "1"};
    canvas.text(map.x0 - 12 - text_width(kLabels[quarter], kTextScale), y - kCapHeight / 2, kLabels[quarter], color::text);
  }
  const std::string x_title = "angle around the up axis (degrees)";
  canvas.text((map.x0 + map.x1 - text_width(x_title, kTextScale)) / 2, map.y1 + 46, x_title, color::text);
  canvas.text(map.x0 - 60, 6, "height (fraction of the bounding cylinder: 0 bottom, 1 top)", color::text);

  // Colour bar: the ramp from W = 0 (bottom row) to Wmax (top row), labelled at both ends and the middle.
  const PlotRect& bar = layout.colour_bar;
  for (int y = bar.y0; y < bar.y1; ++y)
    canvas.rect(bar.x0, y, bar.x1, y + 1, weight_color(static_cast<double>(bar.y1 - 1 - y) / (bar.y1 - 1 - bar.y0)));
  canvas.frame(bar, color::text);
  const auto bar_label = [&](int y, const std::string& label) {
    canvas.rect(bar.x1, y - 1, bar.x1 + 6, y + 1, color::text);
    canvas.text(bar.x1 + 10, y - kCapHeight / 2, label, color::text);
  };
  bar_label(bar.y0, format_weight(r.metrics.weight_max));
  bar_label((bar.y0 + bar.y1) / 2, format_weight(r.metrics.weight_max / 2));
  bar_label(bar.y1 - 1, "0");
  canvas.text(bar.x0, 6, "cell weight W", color::text);

  // Legend: a dark box (the base curve is white) with a sample of every mark, left to right.
  const PlotRect& legend = layout.legend;
  canvas.rect(legend.x0, legend.y0, legend.x1, legend.y1, color::legend_box);
  int pen = legend.x0 + 14;
  const int mid = (legend.y0 + legend.y1) / 2;
  const auto entry = [&](const std::string& label, auto draw_sample) {
    draw_sample(pen, pen + 36);
    pen += 36 + 10;
    canvas.text(pen, mid - kCapHeight / 2, label, color::legend_text);
    pen += text_width(label, kTextScale) + 30;
  };
  entry("base curve", [&](int x0, int x1) { canvas.line(x0, mid, x1, mid, 3.0, color::base); });
  entry("gaze", [&](int x0, int x1) { canvas.line(x0, mid, x1, mid, 2.0, color::gaze); });
  entry("position", [&](int x0, int x1) { canvas.line(x0, mid, x1, mid, 2.0, color::position); });
  entry("control point", [&](int x0, int x1) { control_point((x0 + x1) / 2.0, mid); });
  entry("start", [&](int x0, int x1) { canvas.line((x0 + x1) / 2.0, mid - 12, (x0 + x1) / 2.0, mid + 12, 3.0, color::start); });
  entry("empty cell", [&](int x0, int x1) { canvas.rect(x0 + 6, mid - 10, x1 - 6, mid + 10, color::empty_cell); });
  return canvas.take();
}

void write_plot_image(const PlotImage& image, const std::filesystem::path& file) {
  write_8bit_image(file, image.rgb, image.width, image.height, 3, SrgbTag::untagged, "plot");
}

}  // namespace meshtour
