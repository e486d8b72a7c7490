// The log-log line plots of the convergence study (error against samples or time): one line per series with
// an optional spread band, a slope guide and a legend, drawn on a Canvas.
#pragma once

#include "engine/analysis/canvas.h"
#include "engine/analysis/log_axes.h"

#include <limits>
#include <string>
#include <vector>

namespace iblx {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;         // the line (mean or median over seeds)
  std::vector<double> yLow, yHigh;  // optional spread band (same size as x, or empty)
  Rgb8 color{};                     // {0,0,0} = take the palette color of its index
  bool dashed = false;
};

struct LogLogPlot {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
  // Optional guide line of this slope (e.g. -1 for MSE ∝ 1/N) drawn light grey through the first point of the
  // first series, labelled "slope -1"; NaN = none.
  double guideSlope = std::numeric_limits<double>::quiet_NaN();
};

// Axes with decade ticks labelled "1e-3", "1", "1e1" (2x and 5x, then 1..9x, ticks are added when a range
// holds fewer than 2 decades), a light grid at the labelled ticks, bands then lines in log-log space, and a
// legend (swatch + label per series) in an upper corner of the plot area that the data leave free (upper
// right preferred), or outside on the right when there are more than 6 series. Points with x <= 0, y <= 0 or
// non-finite coordinates are skipped and break the line (and band). Ranges: min/max over all valid points and
// band ends, padded by 5% in log space; a single value is widened to one decade around it. A plot without a
// valid point draws the axes and a "no data" note. Never throws for data.
Canvas drawLogLogPlot(const LogLogPlot& plot, int width = 900, int height = 600);

// Where drawLogLogPlot puts the data: the plot area in pixels and the log10 ranges it spans.
struct LogLogFrame : LogLogAxes {
  bool hasData = false;
};
LogLogFrame logLogFrame(const LogLogPlot& plot, int width, int height);

}  // namespace iblx
