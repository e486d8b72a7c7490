// Heat maps (heat_map.h): the scaled image, its frame, the colorbar with its ticks and the captions.
#include "engine/analysis/heat_map.h"

#include "engine/analysis/log_axes.h"
#include "engine/analysis/palette.h"
#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace iblx {
namespace {

// Linear ticks at a 1, 2 or 5 x 10^k step giving 3 to 5 ticks.
std::vector<double> linearTicks(double lo, double hi) {
  const double span = hi - lo;
  for (double step = std::pow(10.0, std::floor(std::log10(span / 5))); step <= span;) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double s = m * step;
      std::vector<double> ticks;
      for (double v = std::ceil(lo / s - 1e-9) * s; v <= hi + 1e-9 * span; v += s)
        ticks.push_back(std::abs(v) < 1e-9 * span ? 0.0 : v);
      if (ticks.size() <= 5) return ticks;
    }
    step *= 10;
  }
  return {lo, hi};
}

std::string linearLabel(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

}  // namespace

Canvas drawHeatMap(const HeatMap& map) {
  if (map.width <= 0 || map.height <= 0 ||
      map.values.size() != std::size_t(map.width) * std::size_t(map.height))
    throw Error("heat map '" + map.title + "': " + std::to_string(map.values.size()) + " values for a " +
                std::to_string(map.width) + "x" + std::to_string(map.height) + " image");
  if (!(map.high > map.low) || (map.logScale && !(map.low > 0)))
    throw Error("heat map '" + map.title + "': invalid value range [" + linearLabel(map.low) + ", " +
                linearLabel(map.high) + "]" +
                (map.logScale ? " for a log scale (needs 0 < low < high)" : ""));

  const auto toUnit = [&](double v) {
    if (std::isnan(v)) return v;
    if (map.logScale)
      return v <= map.low
                 ? 0.0
                 : (std::log10(v) - std::log10(map.low)) / (std::log10(map.high) - std::log10(map.low));
    return (v - map.low) / (map.high - map.low);
  };

  const int zoom = std::max(1, int(std::ceil(256.0 / std::max(map.width, map.height))));
  const int imageWidth = map.width * zoom, imageHeight = map.height * zoom;
  const int lineHeight = Canvas::lineHeight(kFigureTextScale);
  const double margin = 20, tickLength = 5, gap = 6, barWidth = 22;
  const double top = map.title.empty() ? margin : 16 + Canvas::lineHeight(kFigureTextScale) + 14;
  const double barHeight = std::max(double(imageHeight), 180.0);

  // Colorbar ticks: decades (at most 5, thinned keeping the top one), or 1-2-5 linear steps.
  std::vector<double> ticks = map.logScale ? logTicks(map.low, map.high) : linearTicks(map.low, map.high);
  if (ticks.size() > 5) {
    const std::size_t stride = (ticks.size() - 1 + 3) / 4;
    std::vector<double> thinned;
    for (std::size_t i = 0; i < ticks.size(); ++i)
      if ((ticks.size() - 1 - i) % stride == 0) thinned.push_back(ticks[i]);
    ticks = thinned;
  }
  const auto barY = [&](double v) { return top + (1 - toUnit(v)) * barHeight; };
  // Too few ticks inside: label the ends too, unless that would collide with a tick label.
  if (ticks.size() < 3)
    for (double end : {map.low, map.high}) {
      const bool clear = std::all_of(ticks.begin(), ticks.end(),
                                     [&](double t) { return std::abs(barY(t) - barY(end)) >= lineHeight; });
      if (clear) ticks.push_back(end);
    }
  std::sort(ticks.begin(), ticks.end());
  const auto label = [&](double v) { return map.logScale ? tickLabel(v) : linearLabel(v); };
  int widest = 0;
  for (double t : ticks) widest = std::max(widest, Canvas::textWidth(label(t), kFigureTextScale));

  // The caption runs up beside the bar when it fits, else it goes under the figure, right-aligned with the
  // colorbar labels: a smaller font would be unreadable in print.
  const int captionWidth = Canvas::textWidth(map.unit, kFigureTextScale);
  const bool captionAlongBar = !map.unit.empty() && captionWidth <= barHeight;
  const bool captionBelow = !map.unit.empty() && !captionAlongBar;
  const double barLeft = margin + imageWidth + 24;
  const double labelsLeft = barLeft + barWidth + tickLength + gap;
  const double captionLeft = labelsLeft + widest + 12;
  const double contentRight = captionAlongBar ? captionLeft + lineHeight : labelsLeft + widest;
  const double blockBottom = top + barHeight + lineHeight / 2.0;  // the lowest tick label may hang below
  const double captionTop = blockBottom + 8;
  const double canvasWidth =
      std::ceil(std::max({contentRight + margin, Canvas::textWidth(map.title, kFigureTextScale) + 2 * margin,
                          captionBelow ? captionWidth + 2 * margin : 0.0}));
  const double canvasHeight = std::ceil((captionBelow ? captionTop + lineHeight : blockBottom) + margin);
  Canvas canvas(int(canvasWidth), int(canvasHeight), kPaper);

  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const double t = toUnit(map.values[std::size_t(y) * std::size_t(map.width) + std::size_t(x)]);
      canvas.fillRect(margin + x * zoom, top + y * zoom, margin + (x + 1) * zoom, top + (y + 1) * zoom,
                      colormap(t));
    }
  // A hairline frame so the image edge reads against white even where values are bright.
  const auto frameRect = [&](double x0, double y0, double x1, double y1) {
    canvas.fillRect(x0 - 1, y0 - 1, x1 + 1, y0, kInk);
    canvas.fillRect(x0 - 1, y1, x1 + 1, y1 + 1, kInk);
    canvas.fillRect(x0 - 1, y0, x0, y1, kInk);
    canvas.fillRect(x1, y0, x1 + 1, y1, kInk);
  };
  frameRect(margin, top, margin + imageWidth, top + imageHeight);

  for (int row = 0; row < int(barHeight); ++row)
    canvas.fillRect(barLeft, top + row, barLeft + barWidth, top + row + 1,
                    colormap(1 - row / (barHeight - 1)));
  frameRect(barLeft, top, barLeft + barWidth, top + barHeight);
  for (double t : ticks) {
    const double y = std::clamp(std::round(barY(t)), top, top + barHeight - 1);
    canvas.fillRect(barLeft + barWidth + 1, y, barLeft + barWidth + 1 + tickLength, y + 1, kInk);
    canvas.text(labelsLeft, y - 4 * kFigureTextScale, label(t), kInk, kFigureTextScale);
  }
  if (captionAlongBar)
    canvas.textVertical(captionLeft, top + barHeight / 2, map.unit, kInk, kFigureTextScale);
  if (captionBelow)
    canvas.text(std::max(margin, std::min(contentRight, canvasWidth - margin) - captionWidth), captionTop,
                map.unit, kInk, kFigureTextScale);
  if (!map.title.empty()) canvas.textCentered(canvasWidth / 2.0, 16, map.title, kInk, kFigureTextScale);
  return canvas;
}

}  // namespace iblx
