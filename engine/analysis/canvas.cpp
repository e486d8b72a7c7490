// The figures' raster (canvas.h): rectangles, anti-aliased lines, stb_easy_font text and PNG output.
#include "engine/analysis/canvas.h"

#include "engine/core/error.h"
#include "engine/io/image_write.h"

#include <algorithm>
#include <array>
#include <cmath>

// stb_easy_font is header-only with static functions; it needs ceil() from <math.h> declared first.
#include <stb/stb_easy_font.h>

namespace iblx {
namespace {

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

double distanceToSegment(double px, double py, Canvas::Point a, Canvas::Point b) {
  const double dx = b.x - a.x, dy = b.y - a.y, lengthSquared = dx * dx + dy * dy;
  double t = lengthSquared > 0 ? ((px - a.x) * dx + (py - a.y) * dy) / lengthSquared : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(px - (a.x + t * dx), py - (a.y + t * dy));
}

}  // namespace

std::pair<int, int> pixelSpan(double a, double b, int size) {
  if (a > b) std::swap(a, b);
  const double first = std::ceil(a - 0.5), last = std::ceil(b - 0.5);
  return {int(std::clamp(first, 0.0, double(size))), int(std::clamp(last, 0.0, double(size)))};
}

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

}  // namespace iblx
