// Log-log line plots (loglog_plot.h): grid, spread bands, lines, slope guide, axes and legend.
#include "engine/analysis/loglog_plot.h"

#include "engine/analysis/palette.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

namespace iblx {
namespace {

using Point = Canvas::Point;

constexpr Rgb8 kGridGrey{228, 228, 228};   // decade grid
constexpr Rgb8 kGuideGrey{165, 165, 165};  // slope guide
constexpr Rgb8 kNoteGrey{120, 120, 120};
constexpr int kTitleScale = 3;  // plot title
constexpr double kLineThickness = 2.5;
constexpr double kBandAlpha = 0.2;
constexpr std::size_t kMaxLegendInside = 6;

Rgb8 seriesColor(const PlotSeries& s, std::size_t index) {
  return s.color == Rgb8{0, 0, 0} ? paletteColor(index) : s.color;
}

int widestLabel(const std::vector<double>& ticks) {
  int widest = 0;
  for (double t : ticks) widest = std::max(widest, Canvas::textWidth(tickLabel(t), kFigureTextScale));
  return widest;
}

struct LegendLayout {
  double width = 0, height = 0, rowHeight = 0;
};

constexpr double kSwatchWidth = 30, kLegendPadding = 10, kLegendGap = 8;

LegendLayout legendLayout(const LogLogPlot& plot) {
  if (plot.series.empty()) return {};
  int widest = 0;
  for (const PlotSeries& s : plot.series)
    widest = std::max(widest, Canvas::textWidth(s.label, kFigureTextScale));
  const double rowHeight = Canvas::lineHeight(kFigureTextScale) + 4;
  return {2 * kLegendPadding + kSwatchWidth + kLegendGap + widest,
          2 * kLegendPadding + rowHeight * double(plot.series.size()) - 4, rowHeight};
}

// Runs of consecutive valid points in pixel space; an invalid point ends a run.
std::vector<std::vector<Point>> pixelRuns(const std::vector<double>& xs, const std::vector<double>& ys,
                                          const LogLogFrame& frame) {
  std::vector<std::vector<Point>> runs(1);
  const std::size_t n = std::min(xs.size(), ys.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (validLogLogPoint(xs[i], ys[i])) {
      runs.back().push_back({frame.pixelX(xs[i]), frame.pixelY(ys[i])});
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  if (runs.back().empty()) runs.pop_back();
  return runs;
}

// Dash pattern along arc length (pixels), so a dashed line looks the same at any point density.
std::vector<std::vector<Point>> dashes(const std::vector<Point>& run) {
  constexpr double kOn = 12, kOff = 7;
  std::vector<std::vector<Point>> out;
  if (run.size() == 1) return {run};
  double phase = 0;  // position inside the current on+off period
  bool drawing = true;
  out.push_back({run.front()});
  for (std::size_t i = 1; i < run.size(); ++i) {
    Point a = run[i - 1];
    const Point b = run[i];
    double remaining = std::hypot(b.x - a.x, b.y - a.y);
    while (remaining > 0) {
      const double untilSwitch = (drawing ? kOn : kOn + kOff) - phase;
      const double step = std::min(untilSwitch, remaining);
      const double f = step / remaining;
      a = {a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f};
      remaining -= step;
      phase += step;
      if (drawing) out.back().push_back(a);
      if (step == untilSwitch) {
        drawing = !drawing;
        if (drawing) {
          phase = 0;
          out.push_back({a});
        }
      }
    }
  }
  std::erase_if(out, [](const std::vector<Point>& d) { return d.size() < 2; });
  return out;
}

// The band between yLow and yHigh as one-pixel columns, linearly interpolated in log space between valid
// neighbours; half-open column ranges so a column is never blended twice.
void drawBand(Canvas& canvas, const PlotSeries& s, const LogLogFrame& frame, Rgb8 color) {
  const std::size_t n = s.x.size();
  if (s.yLow.size() != n || s.yHigh.size() != n) return;
  const auto valid = [&](std::size_t i) {
    return validLogLogPoint(s.x[i], s.yLow[i]) && validLogLogPoint(s.x[i], s.yHigh[i]);
  };
  for (std::size_t i = 1; i < n; ++i) {
    if (!valid(i - 1) || !valid(i)) continue;
    double xa = frame.pixelX(s.x[i - 1]), xb = frame.pixelX(s.x[i]);
    double lowA = frame.pixelY(s.yLow[i - 1]), lowB = frame.pixelY(s.yLow[i]);
    double highA = frame.pixelY(s.yHigh[i - 1]), highB = frame.pixelY(s.yHigh[i]);
    if (xa > xb) std::swap(xa, xb), std::swap(lowA, lowB), std::swap(highA, highB);
    const auto [first, last] = pixelSpan(xa, xb, canvas.width());
    for (int column = first; column < last; ++column) {
      const double f = xb > xa ? (column + 0.5 - xa) / (xb - xa) : 0.0;
      const double low = lowA + (lowB - lowA) * f, high = highA + (highB - highA) * f;
      // At least one pixel tall so a collapsed band still shows where it is.
      const double mid = 0.5 * (low + high), half = std::max(0.5 * std::abs(low - high), 0.5);
      canvas.blendRect(column, std::max(mid - half, frame.top), column + 1,
                       std::min(mid + half, frame.bottom), color, kBandAlpha);
    }
  }
}

// Unlabelled 2..9 x 10^k ticks when decades are far enough apart to show them.
std::vector<double> minorTicks(double log10Lo, double log10Hi, double pixelsPerDecade) {
  std::vector<double> ticks;
  if (pixelsPerDecade < 40) return ticks;
  for (int e = int(std::floor(log10Lo)); e <= int(std::ceil(log10Hi)); ++e)
    for (int m = 2; m <= 9; ++m) {
      const double l = e + std::log10(double(m));
      if (l >= log10Lo && l <= log10Hi) ticks.push_back(std::pow(10.0, l));
    }
  return ticks;
}

std::string slopeLabel(double slope) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "slope %g", slope);
  return buffer;
}

// Clips the segment a-b to the rectangle (Liang-Barsky); nullopt if it misses.
std::optional<std::pair<Point, Point>> clipSegment(Point a, Point b, double x0, double y0, double x1,
                                                   double y1) {
  double t0 = 0, t1 = 1;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const std::array<double, 4> p{-dx, dx, -dy, dy}, q{a.x - x0, x1 - a.x, a.y - y0, y1 - a.y};
  for (std::size_t i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return std::nullopt;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
  }
  if (t0 > t1) return std::nullopt;
  return std::pair{Point{a.x + t0 * dx, a.y + t0 * dy}, Point{a.x + t1 * dx, a.y + t1 * dy}};
}

// How much of the data (sampled every ~2 px along the lines) falls inside a box, to place the legend.
std::size_t dataInBox(const std::vector<std::vector<std::vector<Point>>>& seriesRuns, double x0, double y0,
                      double x1, double y1) {
  std::size_t count = 0;
  const auto inside = [&](Point p) { return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1; };
  for (const auto& runs : seriesRuns)
    for (const auto& run : runs) {
      if (run.size() == 1) count += inside(run[0]);
      for (std::size_t i = 1; i < run.size(); ++i) {
        const Point a = run[i - 1], b = run[i];
        const int steps = std::max(1, int(std::hypot(b.x - a.x, b.y - a.y) / 2));
        for (int k = 0; k < steps; ++k) {
          const double f = double(k) / steps;
          count += inside({a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f});
        }
      }
    }
  return count;
}

}  // namespace

LogLogFrame logLogFrame(const LogLogPlot& plot, int width, int height) {
  LogLogBounds bounds;
  for (const PlotSeries& s : plot.series) {
    const bool hasBand = s.yLow.size() == s.x.size() && s.yHigh.size() == s.x.size();
    for (std::size_t i = 0; i < s.x.size(); ++i)
      for (double y : {i < s.y.size() ? s.y[i] : std::nan(""), hasBand ? s.yLow[i] : std::nan(""),
                       hasBand ? s.yHigh[i] : std::nan("")})
        bounds.add(s.x[i], y);
  }
  LogLogFrame frame;
  frame.hasData = !bounds.empty();
  const LogRange xRange = paddedRange(bounds.x), yRange = paddedRange(bounds.y);
  frame.log10XMin = xRange.lo, frame.log10XMax = xRange.hi;
  frame.log10YMin = yRange.lo, frame.log10YMax = yRange.hi;

  const int lineHeight = Canvas::lineHeight(kFigureTextScale);
  const double tickLength = 6, gap = 8;
  const double yLabelSpace = plot.yLabel.empty() ? 0 : lineHeight + 20;
  frame.left =
      14 + yLabelSpace + widestLabel(ticksForLog10Range(frame.log10YMin, frame.log10YMax)) + gap + tickLength;
  frame.top = plot.title.empty() ? 24 : 18 + Canvas::lineHeight(kTitleScale) + 14;
  frame.bottom = height - (14 + tickLength + gap + lineHeight + (plot.xLabel.empty() ? 0 : lineHeight + 10));
  const std::vector<double> xTicks = ticksForLog10Range(frame.log10XMin, frame.log10XMax);
  // Half of the last x label may hang past the plot area.
  double rightMargin = std::max(
      28.0, xTicks.empty() ? 0.0 : Canvas::textWidth(tickLabel(xTicks.back()), kFigureTextScale) / 2.0 + 12);
  if (plot.series.size() > kMaxLegendInside)
    rightMargin = std::max(rightMargin, legendLayout(plot).width + 28);
  frame.right = width - rightMargin;
  // Tiny canvases still get a (degenerate but finite) plot area rather than an inverted one.
  frame.right = std::max(frame.right, frame.left + 1);
  frame.bottom = std::max(frame.bottom, frame.top + 1);
  return frame;
}

Canvas drawLogLogPlot(const LogLogPlot& plot, int width, int height) {
  Canvas canvas(width, height, kPaper);
  const LogLogFrame frame = logLogFrame(plot, width, height);
  const Canvas::ClipRect plotArea{frame.left, frame.top, frame.right, frame.bottom};
  const double plotWidth = frame.right - frame.left, plotHeight = frame.bottom - frame.top;

  const std::vector<double> xTicks = ticksForLog10Range(frame.log10XMin, frame.log10XMax);
  const std::vector<double> yTicks = ticksForLog10Range(frame.log10YMin, frame.log10YMax);

  // Grid at the major ticks, under everything else.
  for (double t : xTicks)
    canvas.fillRect(std::round(frame.pixelX(t)), frame.top, std::round(frame.pixelX(t)) + 1, frame.bottom,
                    kGridGrey);
  for (double t : yTicks)
    canvas.fillRect(frame.left, std::round(frame.pixelY(t)), frame.right, std::round(frame.pixelY(t)) + 1,
                    kGridGrey);

  // Pixel-space runs of every series, for drawing and to find a free corner for the legend.
  std::vector<std::vector<std::vector<Point>>> seriesRuns;
  for (const PlotSeries& s : plot.series) seriesRuns.push_back(pixelRuns(s.x, s.y, frame));

  // Slope guide through the first valid point of the first series.
  if (std::isfinite(plot.guideSlope) && !seriesRuns.empty() && !seriesRuns[0].empty()) {
    const PlotSeries& first = plot.series[0];
    std::size_t i = 0;
    while (!validLogLogPoint(first.x[i], first.y[i])) ++i;
    const double lx = std::log10(first.x[i]), ly = std::log10(first.y[i]);
    const auto at = [&](double log10X) {
      return Point{frame.pixelX(std::pow(10.0, log10X)),
                   frame.pixelY(std::pow(10.0, ly + plot.guideSlope * (log10X - lx)))};
    };
    if (const auto clipped = clipSegment(at(frame.log10XMin), at(frame.log10XMax), frame.left, frame.top,
                                         frame.right, frame.bottom)) {
      const std::vector<Point> guide{clipped->first, clipped->second};
      for (const auto& dash : dashes(guide)) canvas.polyline(dash, kGuideGrey, 1.5, plotArea);
      // Label beside the far part of the line, on the side away from it.
      const Point a = clipped->first, b = clipped->second;
      const Point p{a.x + 0.8 * (b.x - a.x), a.y + 0.8 * (b.y - a.y)};
      const std::string label = slopeLabel(plot.guideSlope);
      const double labelWidth = Canvas::textWidth(label, kFigureTextScale),
                   labelHeight = Canvas::lineHeight(kFigureTextScale);
      double tx = p.x + 8, ty = plot.guideSlope < 0 ? p.y - 8 - labelHeight : p.y + 8;
      tx = std::clamp(tx, frame.left + 4, frame.right - labelWidth - 4);
      ty = std::clamp(ty, frame.top + 4, frame.bottom - labelHeight - 4);
      canvas.text(tx, ty, label, kGuideGrey, kFigureTextScale);
    }
  }

  for (std::size_t k = 0; k < plot.series.size(); ++k)
    drawBand(canvas, plot.series[k], frame, seriesColor(plot.series[k], k));
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const Rgb8 color = seriesColor(plot.series[k], k);
    for (const auto& run : seriesRuns[k]) {
      if (plot.series[k].dashed)
        for (const auto& dash : dashes(run)) canvas.polyline(dash, color, kLineThickness, plotArea);
      else
        canvas.polyline(run, color, kLineThickness, plotArea);
      // Isolated points would otherwise be invisible; sparse series get markers so samples are visible.
      if (run.size() == 1 || plot.series[k].x.size() <= 24)
        for (const Point& p : run) canvas.polyline(std::span(&p, 1), color, 6.0, plotArea);
    }
  }

  // Axes: a frame, ticks outside it, labels.
  canvas.fillRect(frame.left - 1, frame.top - 1, frame.right + 1, frame.top, kInk);
  canvas.fillRect(frame.left - 1, frame.bottom, frame.right + 1, frame.bottom + 1, kInk);
  canvas.fillRect(frame.left - 1, frame.top, frame.left, frame.bottom, kInk);
  canvas.fillRect(frame.right, frame.top, frame.right + 1, frame.bottom, kInk);
  const int lineHeight = Canvas::lineHeight(kFigureTextScale);
  const double tickLength = 6, gap = 8;
  for (double t :
       minorTicks(frame.log10XMin, frame.log10XMax, plotWidth / (frame.log10XMax - frame.log10XMin))) {
    const double x = std::round(frame.pixelX(t));
    canvas.fillRect(x, frame.bottom + 1, x + 1, frame.bottom + 1 + tickLength / 2, kInk);
  }
  for (double t :
       minorTicks(frame.log10YMin, frame.log10YMax, plotHeight / (frame.log10YMax - frame.log10YMin))) {
    const double y = std::round(frame.pixelY(t));
    canvas.fillRect(frame.left - 1 - tickLength / 2, y, frame.left - 1, y + 1, kInk);
  }
  std::vector<double> xPositions, yPositions;
  for (double t : xTicks) xPositions.push_back(frame.pixelX(t));
  for (double t : yTicks) yPositions.push_back(frame.pixelY(t));
  const std::size_t xStride = labelStride(xPositions, widestLabel(xTicks));
  const std::size_t yStride = labelStride(yPositions, lineHeight);
  for (std::size_t i = 0; i < xTicks.size(); ++i) {
    const double x = std::round(xPositions[i]);
    canvas.fillRect(x, frame.bottom + 1, x + 1, frame.bottom + 1 + tickLength, kInk);
    if (i % xStride == 0)
      canvas.textCentered(x + 0.5, frame.bottom + 1 + tickLength + gap / 2, tickLabel(xTicks[i]), kInk,
                          kFigureTextScale);
  }
  for (std::size_t i = 0; i < yTicks.size(); ++i) {
    const double y = std::round(yPositions[i]);
    canvas.fillRect(frame.left - 1 - tickLength, y, frame.left - 1, y + 1, kInk);
    if (i % yStride == 0) {
      const std::string label = tickLabel(yTicks[i]);
      // Glyph bodies sit in the upper ~7/12 of the line; centre that on the tick.
      canvas.text(frame.left - 1 - tickLength - gap - Canvas::textWidth(label, kFigureTextScale),
                  y - 4 * kFigureTextScale, label, kInk, kFigureTextScale);
    }
  }
  if (!plot.xLabel.empty())
    canvas.textCentered(0.5 * (frame.left + frame.right), height - 12 - lineHeight + 2 * kFigureTextScale,
                        plot.xLabel, kInk, kFigureTextScale);
  if (!plot.yLabel.empty())
    canvas.textVertical(14, 0.5 * (frame.top + frame.bottom), plot.yLabel, kInk, kFigureTextScale);
  if (!plot.title.empty())
    canvas.textCentered(0.5 * (frame.left + frame.right), 18, plot.title, kInk, kTitleScale);

  if (!frame.hasData)
    canvas.textCentered(0.5 * (frame.left + frame.right), 0.5 * (frame.top + frame.bottom) - lineHeight / 2.0,
                        "no data", kNoteGrey, kFigureTextScale);

  // Legend: inside in the corner with the least data under it (upper right first), or outside on the right.
  const LegendLayout legend = legendLayout(plot);
  if (legend.width > 0) {
    double boxX = frame.right + 16, boxY = frame.top;
    if (plot.series.size() <= kMaxLegendInside) {
      const double inset = 10;
      const std::array<Point, 4> corners{
          Point{frame.right - inset - legend.width, frame.top + inset},
          Point{frame.left + inset, frame.top + inset},
          Point{frame.left + inset, frame.bottom - inset - legend.height},
          Point{frame.right - inset - legend.width, frame.bottom - inset - legend.height}};
      std::size_t best = 0, bestCount = std::numeric_limits<std::size_t>::max();
      for (std::size_t c = 0; c < corners.size(); ++c) {
        const std::size_t count =
            dataInBox(seriesRuns, corners[c].x - 4, corners[c].y - 4, corners[c].x + legend.width + 4,
                      corners[c].y + legend.height + 4);
        if (count < bestCount) best = c, bestCount = count;
      }
      boxX = corners[best].x, boxY = corners[best].y;
    }
    canvas.fillRect(boxX, boxY, boxX + legend.width, boxY + legend.height, kPaper);
    canvas.fillRect(boxX, boxY, boxX + legend.width, boxY + 1, kGridGrey);
    canvas.fillRect(boxX, boxY + legend.height - 1, boxX + legend.width, boxY + legend.height, kGridGrey);
    canvas.fillRect(boxX, boxY, boxX + 1, boxY + legend.height, kGridGrey);
    canvas.fillRect(boxX + legend.width - 1, boxY, boxX + legend.width, boxY + legend.height, kGridGrey);
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
      const PlotSeries& s = plot.series[k];
      const Rgb8 color = seriesColor(s, k);
      const double rowTop = boxY + kLegendPadding + legend.rowHeight * double(k);
      const double midY = rowTop + 4 * kFigureTextScale + 0.5;
      const double x0 = boxX + kLegendPadding, x1 = x0 + kSwatchWidth;
      if (!s.yLow.empty()) canvas.blendRect(x0, midY - 6, x1, midY + 6, color, kBandAlpha);
      const std::vector<Point> swatch{{x0, midY}, {x1, midY}};
      if (s.dashed) {
        canvas.polyline(std::vector<Point>{{x0, midY}, {x0 + 11, midY}}, color, kLineThickness);
        canvas.polyline(std::vector<Point>{{x1 - 11, midY}, {x1, midY}}, color, kLineThickness);
      } else {
        canvas.polyline(swatch, color, kLineThickness);
      }
      canvas.text(x1 + kLegendGap, rowTop, s.label, kInk, kFigureTextScale);
    }
  }
  return canvas;
}

}  // namespace iblx
