#pragma once
// The raster that plots and overviews are drawn on.
#include <cstdint>
#include <vector>

namespace meshtour {

/// An 8-bit RGB raster, row 0 at the top.
struct PlotImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

}  // namespace meshtour
