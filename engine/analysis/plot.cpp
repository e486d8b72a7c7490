// Raster figures for the convergence study: Canvas primitives, log-log plots and heat maps (see plot.h).
#include "engine/analysis/plot.h"

#include "engine/core/error.h"
#include "engine/io/image_write.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <tuple>

// stb_easy_font is header-only with static functions; it needs ceil() from <math.h> declared first.
#include <stb/stb_easy_font.h>

namespace iblx {
namespace {

// ---------------------------------------------------------------------------------------------------------
// Text: stb_easy_font glyph quads in a unit-scale coordinate system, (0, 0) = top-left of the line.

struct GlyphQuad {
  float x0, y0, x1, y1;
};

// stb_easy_font indexes a table with (c - 32) and reads one entry past it, so only 32..126 are safe.
std::string printableAscii(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return out;
}

std::vector<GlyphQuad> glyphQuads(const std::string& s) {
  std::string text = printableAscii(s);
  struct Vertex {
    float x, y, z;
    std::uint8_t rgba[4];
  };
  static_assert(sizeof(Vertex) == 16);
  // The densest glyphs use well under 32 quads of 4 vertices; stb truncates silently, so be generous.
  std::vector<Vertex> vertices(text.size() * 32 * 4 + 4);
  const int quadCount = stb_easy_font_print(0.0f, 0.0f, text.data(), nullptr, vertices.data(),
                                            int(vertices.size() * sizeof(Vertex)));
  std::vector<GlyphQuad> quads;
  quads.reserve(std::size_t(quadCount));
  for (int q = 0; q < quadCount; ++q) {
    // Vertices 0 and 2 are opposite corners of the axis-aligned quad.
    const Vertex& a = vertices[std::size_t(4 * q)];
    const Vertex& b = vertices[std::size_t(4 * q + 2)];
    quads.push_back({std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)});
  }
  return quads;
}

std::uint8_t mix(std::uint8_t from, std::uint8_t to, double alpha) {
  return std::uint8_t(std::lround(double(from) + (double(to) - double(from)) * alpha));
}

// Pixel index range [first, last) whose centres lie in [a, b), clamped to [0, size).
std::pair<int, int> pixelSpan(double a, double b, int size) {
  if (a > b) std::swap(a, b);
  const double first = std::ceil(a - 0.5), last = std::ceil(b - 0.5);
  return {int(std::clamp(first, 0.0, double(size))), int(std::clamp(last, 0.0, double(size)))};
}

double distanceToSegment(double px, double py, Canvas::Point a, Canvas::Point b) {
  const double dx = b.x - a.x, dy = b.y - a.y, lengthSquared = dx * dx + dy * dy;
  double t = lengthSquared > 0 ? ((px - a.x) * dx + (py - a.y) * dy) / lengthSquared : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(px - (a.x + t * dx), py - (a.y + t * dy));
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Canvas

Canvas::Canvas(int width, int height, Rgb8 background) : width_(width), height_(height) {
  if (width <= 0 || height <= 0)
    throw Error("canvas size " + std::to_string(width) + "x" + std::to_string(height) + " is not positive");
  pixels_.resize(3 * std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < pixels_.size(); i += 3) {
    pixels_[i] = background.r;
    pixels_[i + 1] = background.g;
    pixels_[i + 2] = background.b;
  }
}

Rgb8 Canvas::at(int x, int y) const {
  const bool inside = x >= 0 && y >= 0 && x < width_ && y < height_;
  IBLX_ASSERT(inside);
  if (!inside) return {0, 0, 0};
  const std::size_t i = 3 * (std::size_t(y) * std::size_t(width_) + std::size_t(x));
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void Canvas::set(int x, int y, Rgb8 c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const std::size_t i = 3 * (std::size_t(y) * std::size_t(width_) + std::size_t(x));
  pixels_[i] = c.r;
  pixels_[i + 1] = c.g;
  pixels_[i + 2] = c.b;
}

void Canvas::blend(int x, int y, Rgb8 c, double alpha) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_ || !(alpha > 0)) return;
  alpha = std::min(alpha, 1.0);
  const Rgb8 old = at(x, y);
  set(x, y, {mix(old.r, c.r, alpha), mix(old.g, c.g, alpha), mix(old.b, c.b, alpha)});
}

void Canvas::fillRect(double x0, double y0, double x1, double y1, Rgb8 c) {
  const auto [xFirst, xLast] = pixelSpan(x0, x1, width_);
  const auto [yFirst, yLast] = pixelSpan(y0, y1, height_);
  for (int y = yFirst; y < yLast; ++y)
    for (int x = xFirst; x < xLast; ++x) set(x, y, c);
}

void Canvas::blendRect(double x0, double y0, double x1, double y1, Rgb8 c, double alpha) {
  const auto [xFirst, xLast] = pixelSpan(x0, x1, width_);
  const auto [yFirst, yLast] = pixelSpan(y0, y1, height_);
  for (int y = yFirst; y < yLast; ++y)
    for (int x = xFirst; x < xLast; ++x) blend(x, y, c, alpha);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb8 c, double thickness) {
  const std::array<Point, 2> points{Point{x0, y0}, Point{x1, y1}};
  polyline(points, c, thickness);
}

void Canvas::polyline(std::span<const Point> points, Rgb8 c, double thickness, ClipRect clip) {
  if (points.empty() || !(thickness > 0)) return;
  const double reach = thickness / 2 + 0.5;
  double minX = points[0].x, maxX = minX, minY = points[0].y, maxY = minY;
  for (const Point& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return;
    minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
    minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
  }
  // The region a pixel may be touched in: the stroke's bounds, the clip rectangle and the canvas.
  const auto [xFirst, xLast] =
      pixelSpan(std::max(minX - reach, clip.x0), std::min(maxX + reach, clip.x1), width_);
  const auto [yFirst, yLast] =
      pixelSpan(std::max(minY - reach, clip.y0), std::min(maxY + reach, clip.y1), height_);
  if (xFirst >= xLast || yFirst >= yLast) return;
  // Coverage is the maximum over segments, then blended once, so a joint is not painted twice.
  const int maskWidth = xLast - xFirst;
  std::vector<float> coverage(std::size_t(maskWidth) * std::size_t(yLast - yFirst), 0.0f);
  const auto stroke = [&](Point a, Point b) {
    const auto [sx0, sx1] = pixelSpan(std::min(a.x, b.x) - reach, std::max(a.x, b.x) + reach, width_);
    const auto [sy0, sy1] = pixelSpan(std::min(a.y, b.y) - reach, std::max(a.y, b.y) + reach, height_);
    for (int y = std::max(sy0, yFirst); y < std::min(sy1, yLast); ++y)
      for (int x = std::max(sx0, xFirst); x < std::min(sx1, xLast); ++x) {
        const double d = distanceToSegment(x + 0.5, y + 0.5, a, b);
        const float cover = float(std::clamp(reach - d, 0.0, 1.0));
        float& cell = coverage[std::size_t(y - yFirst) * std::size_t(maskWidth) + std::size_t(x - xFirst)];
        cell = std::max(cell, cover);
      }
  };
  if (points.size() == 1) stroke(points[0], points[0]);  // a dot
  for (std::size_t i = 1; i < points.size(); ++i) stroke(points[i - 1], points[i]);
  for (int y = yFirst; y < yLast; ++y)
    for (int x = xFirst; x < xLast; ++x)
      blend(x, y, c, coverage[std::size_t(y - yFirst) * std::size_t(maskWidth) + std::size_t(x - xFirst)]);
}

void Canvas::text(double x, double y, const std::string& s, Rgb8 c, int scale) {
  scale = std::max(scale, 1);
  // Whole-pixel origins keep the glyph strokes crisp.
  const double ox = std::round(x), oy = std::round(y);
  for (const GlyphQuad& q : glyphQuads(s))
    fillRect(ox + q.x0 * scale, oy + q.y0 * scale, ox + q.x1 * scale, oy + q.y1 * scale, c);
}

void Canvas::textCentered(double cx, double y, const std::string& s, Rgb8 c, int scale) {
  text(cx - textWidth(s, scale) / 2.0, y, s, c, scale);
}

void Canvas::textVertical(double x, double cy, const std::string& s, Rgb8 c, int scale) {
  scale = std::max(scale, 1);
  const double ox = std::round(x), bottom = std::round(cy + textWidth(s, scale) / 2.0);
  // Counter-clockwise: the text's x runs up the canvas from `bottom`, the text's y (down) runs right.
  for (const GlyphQuad& q : glyphQuads(s))
    fillRect(ox + q.y0 * scale, bottom - q.x1 * scale, ox + q.y1 * scale, bottom - q.x0 * scale, c);
}

int Canvas::textWidth(const std::string& s, int scale) {
  std::string text = printableAscii(s);
  return stb_easy_font_width(text.data()) * std::max(scale, 1);
}

void Canvas::writePng(const std::filesystem::path& path) const {
  writePngRgb8(path, width_, height_, pixels_);
}

// ---------------------------------------------------------------------------------------------------------
// Palette and colormap

Rgb8 paletteColor(std::size_t index) {
  // Tableau 10 (the classic set): distinguishable, and still readable in print.
  static constexpr std::array<Rgb8, 10> kTableau10{{{31, 119, 180},
                                                    {255, 127, 14},
                                                    {44, 160, 44},
                                                    {214, 39, 40},
                                                    {148, 103, 189},
                                                    {140, 86, 75},
                                                    {227, 119, 194},
                                                    {127, 127, 127},
                                                    {188, 189, 34},
                                                    {23, 190, 207}}};
  return kTableau10[index % kTableau10.size()];
}

namespace {

double luma(const std::array<int, 3>& rgb) {
  return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

// 256 entries, one per 8-bit output level, so the map is computed once and its quantization can be checked.
std::array<Rgb8, 256> buildColormapTable() {
  // Evenly spaced sRGB control points, dark blue -> blue -> teal -> green -> yellow, chosen so that luma
  // rises by roughly equal steps (25 -> 220): ordered dark to bright, and still ordered in greyscale print.
  static constexpr std::array<std::array<double, 3>, 6> kControl{
      {{32, 18, 72}, {58, 58, 134}, {40, 112, 150}, {34, 160, 134}, {128, 202, 76}, {246, 230, 48}}};
  constexpr int kSegments = int(kControl.size()) - 1;
  std::array<Rgb8, 256> table{};
  std::array<int, 3> previous{};
  for (int i = 0; i < 256; ++i) {
    const double t = i / 255.0;
    const int segment = std::min(int(t * kSegments), kSegments - 1);
    const double u = t * kSegments - segment;
    // Catmull-Rom through the control points (ends repeated) for a map without visible kinks.
    const auto& p0 = kControl[std::size_t(std::max(segment - 1, 0))];
    const auto& p1 = kControl[std::size_t(segment)];
    const auto& p2 = kControl[std::size_t(segment + 1)];
    const auto& p3 = kControl[std::size_t(std::min(segment + 2, kSegments))];
    std::array<int, 3> rgb{};
    for (std::size_t c = 0; c < 3; ++c) {
      const double v =
          0.5 * (2 * p1[c] + (p2[c] - p0[c]) * u + (2 * p0[c] - 5 * p1[c] + 4 * p2[c] - p3[c]) * u * u +
                 (3 * p1[c] - p0[c] - 3 * p2[c] + p3[c]) * u * u * u);
      rgb[c] = int(std::lround(std::clamp(v, 0.0, 255.0)));
    }
    // The spline's luma rises by ~0.8 per level, less than one code of rounding noise; nudging green (the
    // heaviest luma weight) up by a code where rounding made luma stall keeps it strictly increasing.
    while (i > 0 && luma(rgb) <= luma(previous) && rgb[1] < 255) ++rgb[1];
    table[std::size_t(i)] = {std::uint8_t(rgb[0]), std::uint8_t(rgb[1]), std::uint8_t(rgb[2])};
    previous = rgb;
  }
  return table;
}

}  // namespace

Rgb8 colormap(double t) {
  if (std::isnan(t)) return kMaskedGrey;
  static const std::array<Rgb8, 256> kTable = buildColormapTable();
  return kTable[std::size_t(std::lround(std::clamp(t, 0.0, 1.0) * 255.0))];
}

// ---------------------------------------------------------------------------------------------------------
// Ticks

namespace plot_detail {

std::vector<double> logTicks(double lo, double hi) {
  if (!(lo > 0) || !(hi > 0) || !std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (lo > hi) std::swap(lo, hi);
  // A hair of tolerance so that a range ending exactly at a decade (up to rounding) includes it.
  const double tolerance = 1e-9;
  const auto collect = [&](std::span<const int> mantissas) {
    std::vector<double> ticks;
    const int firstExponent = int(std::floor(std::log10(lo))) - 1,
              lastExponent = int(std::ceil(std::log10(hi)));
    for (int e = firstExponent; e <= lastExponent; ++e)
      for (int m : mantissas) {
        const double v = m * std::pow(10.0, e);
        if (v >= lo * (1 - tolerance) && v <= hi * (1 + tolerance)) ticks.push_back(v);
      }
    return ticks;
  };
  static constexpr std::array<int, 1> kDecades{1};
  static constexpr std::array<int, 3> kOneTwoFive{1, 2, 5};
  static constexpr std::array<int, 9> kAllDigits{1, 2, 3, 4, 5, 6, 7, 8, 9};
  for (std::span<const int> mantissas : {std::span<const int>(kDecades), std::span<const int>(kOneTwoFive),
                                         std::span<const int>(kAllDigits)}) {
    std::vector<double> ticks = collect(mantissas);
    if (ticks.size() >= 2) return ticks;
  }
  // Less than a factor ~2 wide: evenly spaced ticks at a 1, 2 or 5 x 10^k step, 2 to 5 of them.
  if (!(hi > lo)) return {lo};
  for (double step = std::pow(10.0, std::floor(std::log10((hi - lo) / 5))); step <= hi - lo; step *= 10)
    for (double m : {1.0, 2.0, 5.0}) {
      std::vector<double> ticks;
      for (double k = std::ceil(lo / (m * step)); k * m * step <= hi; ++k) ticks.push_back(k * m * step);
      if (ticks.size() >= 2 && ticks.size() <= 5) return ticks;
    }
  return {lo, hi};
}

std::string tickLabel(double v) {
  if (!std::isfinite(v)) return "?";
  if (v == 0) return "0";
  const std::string sign = v < 0 ? "-" : "";
  v = std::abs(v);
  int exponent = int(std::floor(std::log10(v)));
  double mantissa = v / std::pow(10.0, exponent);
  // log10 can land one off near exact powers of ten; rounding to 6 digits can carry into the next decade.
  mantissa = std::round(mantissa * 1e5) / 1e5;
  if (mantissa >= 10) mantissa /= 10, ++exponent;
  if (mantissa < 1) mantissa *= 10, --exponent;
  // The fewest significant digits that still say this value, so 1-2-5 ticks read "2e-3", fine ones "3.105".
  char digits[32], power[16] = "";
  for (int precision = 1; precision <= 6; ++precision) {
    std::snprintf(digits, sizeof digits, "%.*g", precision, mantissa);
    if (std::abs(std::strtod(digits, nullptr) - mantissa) <= 1e-9 * mantissa) break;
  }
  if (exponent != 0) std::snprintf(power, sizeof power, "e%d", exponent);
  return sign + digits + power;
}

}  // namespace plot_detail

// ---------------------------------------------------------------------------------------------------------
// Log-log plot

namespace {

using plot_detail::LogLogFrame;
using Point = Canvas::Point;

constexpr Rgb8 kWhite{255, 255, 255};
constexpr Rgb8 kInk{40, 40, 40};           // text and axes
constexpr Rgb8 kGridGrey{228, 228, 228};   // decade grid
constexpr Rgb8 kGuideGrey{165, 165, 165};  // slope guide
constexpr Rgb8 kNoteGrey{120, 120, 120};
constexpr int kTextScale = 2;   // ticks, axis labels, legend
constexpr int kTitleScale = 3;  // plot title
constexpr double kLineThickness = 2.5;
constexpr double kBandAlpha = 0.2;
constexpr std::size_t kMaxLegendInside = 6;

bool validPoint(double x, double y) {
  return std::isfinite(x) && std::isfinite(y) && x > 0 && y > 0;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double log10Value) { lo = std::min(lo, log10Value), hi = std::max(hi, log10Value); }
  bool empty() const { return !(lo <= hi); }
};

// Log10 data range padded by 5% each side; a single value gets one decade around it.
std::pair<double, double> paddedRange(Range r) {
  if (r.empty()) return {0.0, 1.0};
  if (r.hi - r.lo < 1e-9) return {r.lo - 0.5, r.hi + 0.5};
  const double pad = 0.05 * (r.hi - r.lo);
  return {r.lo - pad, r.hi + pad};
}

Rgb8 seriesColor(const PlotSeries& s, std::size_t index) {
  return s.color == Rgb8{0, 0, 0} ? paletteColor(index) : s.color;
}

std::vector<double> ticksFor(double log10Lo, double log10Hi) {
  return plot_detail::logTicks(std::pow(10.0, log10Lo), std::pow(10.0, log10Hi));
}

int widestLabel(const std::vector<double>& ticks) {
  int widest = 0;
  for (double t : ticks) widest = std::max(widest, Canvas::textWidth(plot_detail::tickLabel(t), kTextScale));
  return widest;
}

struct LegendLayout {
  double width = 0, height = 0, rowHeight = 0;
};

constexpr double kSwatchWidth = 30, kLegendPadding = 10, kLegendGap = 8;

LegendLayout legendLayout(const LogLogPlot& plot) {
  if (plot.series.empty()) return {};
  int widest = 0;
  for (const PlotSeries& s : plot.series) widest = std::max(widest, Canvas::textWidth(s.label, kTextScale));
  const double rowHeight = Canvas::lineHeight(kTextScale) + 4;
  return {2 * kLegendPadding + kSwatchWidth + kLegendGap + widest,
          2 * kLegendPadding + rowHeight * double(plot.series.size()) - 4, rowHeight};
}

// Runs of consecutive valid points in pixel space; an invalid point ends a run.
std::vector<std::vector<Point>> pixelRuns(const std::vector<double>& xs, const std::vector<double>& ys,
                                          const LogLogFrame& frame) {
  std::vector<std::vector<Point>> runs(1);
  const std::size_t n = std::min(xs.size(), ys.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (validPoint(xs[i], ys[i])) {
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
    return validPoint(s.x[i], s.yLow[i]) && validPoint(s.x[i], s.yHigh[i]);
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

// Keeps every k-th label so that labels `extent` pixels long, `spacing` pixels apart, do not touch.
std::size_t labelStride(const std::vector<double>& pixelPositions, double extent) {
  double minSpacing = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < pixelPositions.size(); ++i)
    minSpacing = std::min(minSpacing, std::abs(pixelPositions[i] - pixelPositions[i - 1]));
  if (!std::isfinite(minSpacing) || minSpacing <= 0) return 1;
  return std::size_t(std::max(1.0, std::ceil((extent + 12) / minSpacing)));
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

namespace plot_detail {

double LogLogFrame::pixelX(double x) const {
  return left + (std::log10(x) - log10XMin) / (log10XMax - log10XMin) * (right - left);
}

double LogLogFrame::pixelY(double y) const {
  return bottom - (std::log10(y) - log10YMin) / (log10YMax - log10YMin) * (bottom - top);
}

LogLogFrame logLogFrame(const LogLogPlot& plot, int width, int height) {
  Range xRange, yRange;
  for (const PlotSeries& s : plot.series) {
    const bool hasBand = s.yLow.size() == s.x.size() && s.yHigh.size() == s.x.size();
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const double x = s.x[i];
      bool used = false;
      for (double y : {i < s.y.size() ? s.y[i] : std::nan(""), hasBand ? s.yLow[i] : std::nan(""),
                       hasBand ? s.yHigh[i] : std::nan("")})
        if (validPoint(x, y)) yRange.add(std::log10(y)), used = true;
      if (used) xRange.add(std::log10(x));
    }
  }
  LogLogFrame frame;
  frame.hasData = !xRange.empty();
  std::tie(frame.log10XMin, frame.log10XMax) = paddedRange(xRange);
  std::tie(frame.log10YMin, frame.log10YMax) = paddedRange(yRange);

  const int lineHeight = Canvas::lineHeight(kTextScale);
  const double tickLength = 6, gap = 8;
  const double yLabelSpace = plot.yLabel.empty() ? 0 : lineHeight + 20;
  frame.left = 14 + yLabelSpace + widestLabel(ticksFor(frame.log10YMin, frame.log10YMax)) + gap + tickLength;
  frame.top = plot.title.empty() ? 24 : 18 + Canvas::lineHeight(kTitleScale) + 14;
  frame.bottom = height - (14 + tickLength + gap + lineHeight + (plot.xLabel.empty() ? 0 : lineHeight + 10));
  const std::vector<double> xTicks = ticksFor(frame.log10XMin, frame.log10XMax);
  // Half of the last x label may hang past the plot area.
  double rightMargin = std::max(
      28.0, xTicks.empty() ? 0.0 : Canvas::textWidth(tickLabel(xTicks.back()), kTextScale) / 2.0 + 12);
  if (plot.series.size() > kMaxLegendInside)
    rightMargin = std::max(rightMargin, legendLayout(plot).width + 28);
  frame.right = width - rightMargin;
  // Tiny canvases still get a (degenerate but finite) plot area rather than an inverted one.
  frame.right = std::max(frame.right, frame.left + 1);
  frame.bottom = std::max(frame.bottom, frame.top + 1);
  return frame;
}

}  // namespace plot_detail

Canvas drawLogLogPlot(const LogLogPlot& plot, int width, int height) {
  Canvas canvas(width, height, kWhite);
  const LogLogFrame frame = plot_detail::logLogFrame(plot, width, height);
  const Canvas::ClipRect plotArea{frame.left, frame.top, frame.right, frame.bottom};
  const double plotWidth = frame.right - frame.left, plotHeight = frame.bottom - frame.top;

  const std::vector<double> xTicks = ticksFor(frame.log10XMin, frame.log10XMax);
  const std::vector<double> yTicks = ticksFor(frame.log10YMin, frame.log10YMax);

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
    while (!validPoint(first.x[i], first.y[i])) ++i;
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
      const double labelWidth = Canvas::textWidth(label, kTextScale),
                   labelHeight = Canvas::lineHeight(kTextScale);
      double tx = p.x + 8, ty = plot.guideSlope < 0 ? p.y - 8 - labelHeight : p.y + 8;
      tx = std::clamp(tx, frame.left + 4, frame.right - labelWidth - 4);
      ty = std::clamp(ty, frame.top + 4, frame.bottom - labelHeight - 4);
      canvas.text(tx, ty, label, kGuideGrey, kTextScale);
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
  const int lineHeight = Canvas::lineHeight(kTextScale);
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
      canvas.textCentered(x + 0.5, frame.bottom + 1 + tickLength + gap / 2, plot_detail::tickLabel(xTicks[i]),
                          kInk, kTextScale);
  }
  for (std::size_t i = 0; i < yTicks.size(); ++i) {
    const double y = std::round(yPositions[i]);
    canvas.fillRect(frame.left - 1 - tickLength, y, frame.left - 1, y + 1, kInk);
    if (i % yStride == 0) {
      const std::string label = plot_detail::tickLabel(yTicks[i]);
      // Glyph bodies sit in the upper ~7/12 of the line; centre that on the tick.
      canvas.text(frame.left - 1 - tickLength - gap - Canvas::textWidth(label, kTextScale),
                  y - 4 * kTextScale, label, kInk, kTextScale);
    }
  }
  if (!plot.xLabel.empty())
    canvas.textCentered(0.5 * (frame.left + frame.right), height - 12 - lineHeight + 2 * kTextScale,
                        plot.xLabel, kInk, kTextScale);
  if (!plot.yLabel.empty())
    canvas.textVertical(14, 0.5 * (frame.top + frame.bottom), plot.yLabel, kInk, kTextScale);
  if (!plot.title.empty())
    canvas.textCentered(0.5 * (frame.left + frame.right), 18, plot.title, kInk, kTitleScale);

  if (!frame.hasData)
    canvas.textCentered(0.5 * (frame.left + frame.right), 0.5 * (frame.top + frame.bottom) - lineHeight / 2.0,
                        "no data", kNoteGrey, kTextScale);

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
    canvas.fillRect(boxX, boxY, boxX + legend.width, boxY + legend.height, kWhite);
    canvas.fillRect(boxX, boxY, boxX + legend.width, boxY + 1, kGridGrey);
    canvas.fillRect(boxX, boxY + legend.height - 1, boxX + legend.width, boxY + legend.height, kGridGrey);
    canvas.fillRect(boxX, boxY, boxX + 1, boxY + legend.height, kGridGrey);
    canvas.fillRect(boxX + legend.width - 1, boxY, boxX + legend.width, boxY + legend.height, kGridGrey);
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
      const PlotSeries& s = plot.series[k];
      const Rgb8 color = seriesColor(s, k);
      const double rowTop = boxY + kLegendPadding + legend.rowHeight * double(k);
      const double midY = rowTop + 4 * kTextScale + 0.5;
      const double x0 = boxX + kLegendPadding, x1 = x0 + kSwatchWidth;
      if (!s.yLow.empty()) canvas.blendRect(x0, midY - 6, x1, midY + 6, color, kBandAlpha);
      const std::vector<Point> swatch{{x0, midY}, {x1, midY}};
      if (s.dashed) {
        canvas.polyline(std::vector<Point>{{x0, midY}, {x0 + 11, midY}}, color, kLineThickness);
        canvas.polyline(std::vector<Point>{{x1 - 11, midY}, {x1, midY}}, color, kLineThickness);
      } else {
        canvas.polyline(swatch, color, kLineThickness);
      }
      canvas.text(x1 + kLegendGap, rowTop, s.label, kInk, kTextScale);
    }
  }
  return canvas;
}

// ---------------------------------------------------------------------------------------------------------
// Heat map

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
  const int lineHeight = Canvas::lineHeight(kTextScale);
  const double margin = 20, tickLength = 5, gap = 6, barWidth = 22;
  const double top = map.title.empty() ? margin : 16 + Canvas::lineHeight(kTextScale) + 14;
  const double barHeight = std::max(double(imageHeight), 180.0);

  // Colorbar ticks: decades (at most 5, thinned keeping the top one), or 1-2-5 linear steps.
  std::vector<double> ticks =
      map.logScale ? plot_detail::logTicks(map.low, map.high) : linearTicks(map.low, map.high);
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
  const auto label = [&](double v) { return map.logScale ? plot_detail::tickLabel(v) : linearLabel(v); };
  int widest = 0;
  for (double t : ticks) widest = std::max(widest, Canvas::textWidth(label(t), kTextScale));

  // The caption runs up beside the bar when it fits, else it goes under the figure, right-aligned with the
  // colorbar labels: a smaller font would be unreadable in print.
  const int captionWidth = Canvas::textWidth(map.unit, kTextScale);
  const bool captionAlongBar = !map.unit.empty() && captionWidth <= barHeight;
  const bool captionBelow = !map.unit.empty() && !captionAlongBar;
  const double barLeft = margin + imageWidth + 24;
  const double labelsLeft = barLeft + barWidth + tickLength + gap;
  const double captionLeft = labelsLeft + widest + 12;
  const double contentRight = captionAlongBar ? captionLeft + lineHeight : labelsLeft + widest;
  const double blockBottom = top + barHeight + lineHeight / 2.0;  // the lowest tick label may hang below
  const double captionTop = blockBottom + 8;
  const double canvasWidth =
      std::ceil(std::max({contentRight + margin, Canvas::textWidth(map.title, kTextScale) + 2 * margin,
                          captionBelow ? captionWidth + 2 * margin : 0.0}));
  const double canvasHeight = std::ceil((captionBelow ? captionTop + lineHeight : blockBottom) + margin);
  Canvas canvas(int(canvasWidth), int(canvasHeight), kWhite);

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
    canvas.text(labelsLeft, y - 4 * kTextScale, label(t), kInk, kTextScale);
  }
  if (captionAlongBar) canvas.textVertical(captionLeft, top + barHeight / 2, map.unit, kInk, kTextScale);
  if (captionBelow)
    canvas.text(std::max(margin, std::min(contentRight, canvasWidth - margin) - captionWidth), captionTop,
                map.unit, kInk, kTextScale);
  if (!map.title.empty()) canvas.textCentered(canvasWidth / 2.0, 16, map.title, kInk, kTextScale);
  return canvas;
}

}  // namespace iblx
