#pragma once
// The --plot image of `meshtour path`: the grid weights as a heat map over the (angle, height)
// domain of the bounding cylinder, with the control points and the base, gaze and position
// curves drawn over it (what the paper's figures show for its pipeline).
#include <cstdint>
#include <filesystem>
#include <vector>

#include "pathgen/paper_path.h"

namespace meshtour {

/// An 8-bit RGB raster, row 0 at the top.
struct PlotImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

/// Draws the plot. Angle 0..2π runs left to right, height 0..1 bottom to top. Cells: dark blue
/// (W = 0) through green to yellow (W = Wmax), empty cells grey. Curves: base white, gaze cyan,
/// position magenta; control points white discs; the start column a red tick at both edges.
PlotImage render_path_plot(const PaperPathResult& result);

/// Writes `image` with OpenImageIO (format from the extension; .png recommended), atomically.
/// \throw InputError for an extension OpenImageIO cannot write, IoError if writing fails.
void write_plot_image(const PlotImage& image, const std::filesystem::path& file);

}  // namespace meshtour
