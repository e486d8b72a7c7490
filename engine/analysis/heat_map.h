// Per-pixel heat maps of the convergence study (e.g. each method's relative squared error): the image in the
// colormap, scaled up so its pixels stay visible, beside a labelled colorbar, drawn on a Canvas.
#pragma once

#include "engine/analysis/canvas.h"

#include <string>
#include <vector>

namespace iblx {

struct HeatMap {
  std::string title;
  int width = 0, height = 0;   // of the image
  std::vector<double> values;  // width*height, row-major, top row first; NaN = masked (drawn grey)
  double low = 0, high = 1;    // value range, mapped log10 when logScale
  bool logScale = true;        // values <= 0 with logScale count as `low`
  std::string unit;            // colorbar caption, e.g. "relative squared error"
};

// The image scaled by an integer factor so it is at least 256 px on its long side (nearest neighbour, pixels
// stay visible), coloured by colormap() (palette.h), a colorbar with 3-5 labelled ticks (decades when
// logScale), the unit along the colorbar and the title. Throws Error for a size mismatch, high <= low, or
// low <= 0 with logScale.
Canvas drawHeatMap(const HeatMap& map);

}  // namespace iblx
