// Probes of a rendered Canvas shared by the figure tests (tests/analysis): where the non-background pixels
// are, how many pixels have a colour, the mean row of a colour in a column, and luma.
#pragma once

#include "engine/analysis/canvas.h"

#include <algorithm>
#include <optional>

namespace iblx::test {

inline constexpr Rgb8 kWhite{255, 255, 255};
inline constexpr Rgb8 kRed{200, 20, 20};

// Non-background pixels inside and outside a rectangle [x0, x1) x [y0, y1).
struct Footprint {
  int inside = 0, outside = 0;
  int minX = 1 << 30, maxX = -1, minY = 1 << 30, maxY = -1;
};

inline Footprint footprint(const Canvas& canvas, Rgb8 background, int x0, int y0, int x1, int y1) {
  Footprint f;
  for (int y = 0; y < canvas.height(); ++y)
    for (int x = 0; x < canvas.width(); ++x) {
      if (canvas.at(x, y) == background) continue;
      const bool in = x >= x0 && x < x1 && y >= y0 && y < y1;
      (in ? f.inside : f.outside)++;
      f.minX = std::min(f.minX, x), f.maxX = std::max(f.maxX, x);
      f.minY = std::min(f.minY, y), f.maxY = std::max(f.maxY, y);
    }
  return f;
}

// Mean row of the pixels of exactly this colour in one column of the canvas; nullopt if none.
inline std::optional<double> meanRowOfColor(const Canvas& canvas, int column, Rgb8 color) {
  double sum = 0;
  int count = 0;
  for (int y = 0; y < canvas.height(); ++y)
    if (canvas.at(column, y) == color) sum += y, ++count;
  if (count == 0) return std::nullopt;
  return sum / count;
}

// Pixels of exactly this colour in the columns [x0, x1).
inline int countColor(const Canvas& canvas, Rgb8 color, int x0, int x1) {
  int count = 0;
  for (int y = 0; y < canvas.height(); ++y)
    for (int x = x0; x < x1; ++x) count += canvas.at(x, y) == color;
  return count;
}

inline double luma(Rgb8 c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

}  // namespace iblx::test
