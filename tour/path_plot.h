#pragma once
// The --plot image of `meshtour path`: the grid weights as a heat map over the (angle, height)
// domain of the bounding cylinder, with the control points and the base, gaze and position
// curves drawn over it (what the paper's figures show for its pipeline).
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "pathgen/paper_path.h"
#include "tour/plot_image.h"

namespace meshtour {

/// A rectangle of the plot image in pixels: [x0, x1) × [y0, y1), row 0 at the top.
struct PlotRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Where render_path_plot puts things (fixed: the same for every path), for callers and tests.
struct PathPlotLayout {
  int width = 0, height = 0;  ///< the whole image
  PlotRect heat_map;          ///< the (angle, height) domain
  PlotRect colour_bar;        ///< the ramp, W = 0 at the bottom row, W = Wmax at the top row
  PlotRect legend;            ///< the curve and marker key (dark box)
  int text_scale = 2;         ///< bitmap_text scale of all labels
};
PathPlotLayout path_plot_layout();

/// The colours of the plot, named once for the drawing, the legend and tests.
namespace plot_colors {
inline constexpr std::array<std::uint8_t, 3> base{255, 255, 255}, gaze{0, 220, 255}, position{230, 0, 230},
    control_ring{0, 0, 0}, start{220, 0, 0}, empty_cell{150, 150, 150}, text{0, 0, 0}, legend_text{235, 235, 235},
    legend_box{45, 45, 45}, background{255, 255, 255};
}

/// The heat-map colour of a weight fraction W / Wmax in [0, 1]: dark blue through green to yellow.
std::array<std::uint8_t, 3> weight_color(double fraction);

/// Draws the plot. Angle 0..360° runs left to right, height 0..1 (fraction of the bounding
/// cylinder's height, bottom to top) bottom to top, both with labelled ticks. Cells: dark blue
/// (W = 0) through green to yellow (W = Wmax), empty cells grey, with a colour bar labelled 0 and
/// Wmax. Curves: base white, gaze cyan, position magenta; control points white discs; the start
/// column a red tick at both edges and its cell outlined in red; a legend names them all.
PlotImage render_path_plot(const PaperPathResult& result);

/// Writes `image` with OpenImageIO (format from the extension; .png recommended), atomically.
/// \throw InputError for an extension OpenImageIO cannot write, IoError if writing fails.
void write_plot_image(const PlotImage& image, const std::filesystem::path& file);

}  // namespace meshtour
