// Tests of the log-log plots (engine/analysis/loglog_plot.h): the pixel slope of a 1/x line, breaks at
// invalid points, spread bands, empty plots and the legend.
#include "engine/analysis/loglog_plot.h"

#include "engine/analysis/palette.h"
#include "tests/support/canvas_probes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace iblx;
using namespace iblx::test;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("plot: y = 1/x is a straight line of the expected pixel slope") {
  LogLogPlot plot;
  plot.title = "error vs spp";
  plot.xLabel = "spp";
  plot.yLabel = "MSE";
  PlotSeries s;
  s.label = "1/x";
  s.color = kRed;
  for (int i = 1; i <= 1024; ++i) s.x.push_back(i), s.y.push_back(1.0 / i);
  plot.series.push_back(s);
  const Canvas canvas = drawLogLogPlot(plot, 900, 600);
  const auto frame = logLogFrame(plot, 900, 600);
  REQUIRE(frame.hasData);
  // One decade of padding-free data: 5% padding each side of log10(1024).
  CHECK(frame.log10XMax - frame.log10XMin == doctest::Approx(1.1 * std::log10(1024.0)));

  const int columnA = int(frame.pixelX(4)), columnB = int(frame.pixelX(256));
  const auto rowA = meanRowOfColor(canvas, columnA, kRed), rowB = meanRowOfColor(canvas, columnB, kRed);
  REQUIRE(rowA);
  REQUIRE(rowB);
  // The data rows are where the frame says (within the line's half thickness)...
  CHECK(std::abs(*rowA + 0.5 - frame.pixelY(1.0 / 4)) < 3);
  CHECK(std::abs(*rowB + 0.5 - frame.pixelY(1.0 / 256)) < 3);
  // ... and the slope is (height / y decades) / (width / x decades).
  const double measured = (*rowB - *rowA) / double(columnB - columnA);
  const double expected = ((frame.bottom - frame.top) / (frame.log10YMax - frame.log10YMin)) /
                          ((frame.right - frame.left) / (frame.log10XMax - frame.log10XMin));
  CHECK(measured == doctest::Approx(expected).epsilon(0.05));
  // Nothing red left of the first point or right of the last.
  CHECK(countColor(canvas, kRed, 0, int(frame.pixelX(1)) - 3) == 0);
  CHECK(countColor(canvas, kRed, int(frame.pixelX(1024)) + 4, canvas.width()) == 0);
}

TEST_CASE("plot: NaN and negative values break the line") {
  LogLogPlot plot;
  PlotSeries s;
  s.color = kRed;
  s.label = "broken";
  for (int i = 0; i <= 10; ++i) s.x.push_back(std::ldexp(1.0, i)), s.y.push_back(std::ldexp(1.0, -i));
  s.y[4] = kNaN;  // x = 16
  s.y[5] = -1;    // x = 32
  plot.series.push_back(s);
  const Canvas canvas = drawLogLogPlot(plot);
  const auto frame = logLogFrame(plot, 900, 600);
  const int gapStart = int(frame.pixelX(8)) + 6, gapEnd = int(frame.pixelX(64)) - 6;
  REQUIRE(gapEnd - gapStart > 50);
  CHECK(countColor(canvas, kRed, gapStart, gapEnd) == 0);
  CHECK(countColor(canvas, kRed, int(frame.pixelX(2)), int(frame.pixelX(8))) > 20);
  CHECK(countColor(canvas, kRed, int(frame.pixelX(64)), int(frame.pixelX(512))) > 20);
}

TEST_CASE("plot: a spread band blends the series colour between yLow and yHigh") {
  LogLogPlot plot;
  PlotSeries s;
  s.color = kRed;
  s.label = "band";
  for (int i = 0; i <= 10; ++i) {
    const double x = std::ldexp(1.0, i), y = 1 / x;
    s.x.push_back(x), s.y.push_back(y), s.yLow.push_back(y / 4), s.yHigh.push_back(y * 4);
  }
  plot.series.push_back(s);
  const Canvas canvas = drawLogLogPlot(plot);
  const auto frame = logLogFrame(plot, 900, 600);
  const int column = int(frame.pixelX(32));
  const double low = frame.pixelY(1.0 / 32 / 4), high = frame.pixelY(1.0 / 32 * 4);  // low is further down
  int blended = 0;
  for (int y = int(high) + 2; y < int(low) - 1; ++y) {
    const Rgb8 c = canvas.at(column, y);
    if (c == kRed) continue;  // the line itself
    // A mix of white and the series colour: red stays high, green and blue drop equally.
    const bool tinted = c.r > 230 && c.g < 240 && c.g > kRed.g && std::abs(int(c.g) - int(c.b)) <= 1;
    blended += tinted;
  }
  CHECK(blended > (low - high) * 0.6);
  // Just outside the band, the background (or grid) is untinted.
  const Rgb8 above = canvas.at(column, int(high) - 4), below = canvas.at(column, int(low) + 4);
  CHECK((above.r == above.g && above.g == above.b));
  CHECK((below.r == below.g && below.g == below.b));
}

TEST_CASE("plot: an empty plot draws axes and a no data note") {
  LogLogPlot plot;
  plot.title = "nothing";
  PlotSeries s;
  s.label = "all invalid";
  s.x = {1, 2, kNaN, -3};
  s.y = {0, -1, 1, 1};
  plot.series.push_back(s);
  for (const LogLogPlot& p : {LogLogPlot{}, plot}) {
    Canvas canvas(1, 1, kWhite);
    CHECK_NOTHROW(canvas = drawLogLogPlot(p));
    const auto frame = logLogFrame(p, 900, 600);
    CHECK_FALSE(frame.hasData);
    const int cx = int(0.5 * (frame.left + frame.right)), cy = int(0.5 * (frame.top + frame.bottom));
    // The note is in the centre of the plot area, where a grid line does not fall (ticks are decades 1, 10).
    CHECK(footprint(canvas, kWhite, cx - 60, cy - 15, cx + 60, cy + 15).inside > 30);
    CHECK(canvas.at(int(frame.left) - 1, cy) != kWhite);  // the left axis
  }
}

TEST_CASE("plot: legend shows each label with its colour; many series move it outside") {
  LogLogPlot plot;
  for (int k = 0; k < 8; ++k) {
    PlotSeries s;
    s.label = "method " + std::to_string(k);
    for (int i = 0; i <= 6; ++i) s.x.push_back(std::pow(4.0, i)), s.y.push_back((k + 1) * std::pow(4.0, -i));
    plot.series.push_back(s);
  }
  const Canvas canvas = drawLogLogPlot(plot);
  const auto frame = logLogFrame(plot, 900, 600);
  // Right of the plot area are the legend swatches: the palette colours.
  for (int k = 0; k < 8; ++k)
    CHECK(countColor(canvas, paletteColor(k), int(frame.right) + 2, canvas.width()) > 10);
  CHECK(paletteColor(0) != paletteColor(1));
  CHECK(paletteColor(10) == paletteColor(0));
}
