// Log axes shared by the figures (loglog_plot, heat_map's colorbar) and the viewer's convergence plot: which
// ticks a log range gets and how they are labelled, the log10 range of the data (padded, or rounded out to
// whole decades) and the mapping from data to a plot area. No drawing, so any canvas can use it.
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace iblx {

// Tick values inside [lo, hi] (lo, hi > 0), ascending: the decades; if fewer than 2, also 2x and 5x; if still
// fewer than 2, every 1..9 x 10^k; if still fewer than 2, 2 to 5 evenly spaced ticks at a 1-2-5 step.
std::vector<double> logTicks(double lo, double hi);
// The same for a range given by its log10 ends: logTicks(10^log10Lo, 10^log10Hi).
std::vector<double> ticksForLog10Range(double log10Lo, double log10Hi);
// "1e-3", "2e-3", "1", "5", "1e1", "2e2"; other mantissas print with the fewest digits (up to 6) that give
// the value: "3.25", "3.25e-2".
std::string tickLabel(double v);
// Label every k-th tick (the k returned, at least 1) so that labels `extent` pixels long, centred on ticks at
// these pixel positions, keep at least 12 pixels apart.
std::size_t labelStride(std::span<const double> pixelPositions, double extent);

// A point can be drawn on log-log axes: both coordinates finite and positive.
bool validLogLogPoint(double x, double y);

// An interval of log10 values; empty until a value is added.
struct LogRange {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double log10Value);
  bool empty() const { return !(lo <= hi); }
};

// The log10 ranges of the valid points (validLogLogPoint) added: x and y grow together, so a point with an
// invalid coordinate adds to neither.
struct LogLogBounds {
  LogRange x, y;
  void add(double xValue, double yValue);
  // The points (xs[i], ys[i]) for i below the shorter size.
  void add(std::span<const double> xs, std::span<const double> ys);
  bool empty() const { return x.empty(); }
};

// The range padded by 5% of its width on each side; a single value is widened to one decade around it; an
// empty range gives [0, 1] (1 to 10).
LogRange paddedRange(LogRange log10Range);
// The range rounded out to whole decades, at least one decade wide, so slopes can be read off the grid; an
// empty range gives [0, 1].
LogRange wholeDecades(LogRange log10Range);

// The mapping from data to a plot area: log10 ranges onto a pixel rectangle, y growing downwards on screen.
struct LogLogAxes {
  double left = 0, top = 0, right = 0, bottom = 0;  // plot area, pixels
  double log10XMin = 0, log10XMax = 1, log10YMin = 0, log10YMax = 1;
  double pixelX(double x) const;  // x > 0: log10XMin at left, log10XMax at right
  double pixelY(double y) const;  // y > 0: log10YMin at bottom, log10YMax at top
};

}  // namespace iblx
