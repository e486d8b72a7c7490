// The raster the figures are drawn on: an RGB8 Canvas with rectangles, anti-aliased lines and stb_easy_font
// text, written as PNG; and the paper, ink and text scale that every figure (loglog_plot, heat_map) shares.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

struct Rgb8 {
  std::uint8_t r, g, b;
  friend bool operator==(const Rgb8&, const Rgb8&) = default;
};

// An RGB8 raster, row-major, top row first. Coordinates are in pixels with pixel (i, j) covering
// [i, i+1) x [j, j+1), so its centre is (i + 0.5, j + 0.5).
class Canvas {
 public:
  Canvas(int width, int height, Rgb8 background);

  int width() const { return width_; }
  int height() const { return height_; }
  Rgb8 at(int x, int y) const;     // the pixel; out of bounds is a programmer error (asserted)
  void set(int x, int y, Rgb8 c);  // ignores out-of-bounds
  void blend(int x, int y, Rgb8 c, double alpha);  // c over the pixel; ignores out-of-bounds

  // Fills the pixels whose centres lie in the half-open rectangle [x0, x1) x [y0, y1) (corners in any order),
  // so abutting rectangles never overlap or leave gaps.
  void fillRect(double x0, double y0, double x1, double y1, Rgb8 c);
  // Same pixels as fillRect, blended: alpha * c + (1 - alpha) * pixel.
  void blendRect(double x0, double y0, double x1, double y1, Rgb8 c, double alpha);

  // Anti-aliased: a pixel's coverage is 1 where its centre is within thickness/2 - 0.5 of the segment,
  // falling linearly to 0 at thickness/2 + 0.5; the colour is blended by coverage. Clipped to the canvas.
  void line(double x0, double y0, double x1, double y1, Rgb8 c, double thickness = 1.5);
  // A connected line through points (x, y pairs); joints are not darkened because coverage is the maximum
  // over the segments. Only pixels inside [clipX0, clipX1) x [clipY0, clipY1) are touched.
  struct Point {
    double x, y;
  };
  struct ClipRect {
    double x0 = -1e30, y0 = -1e30, x1 = 1e30, y1 = 1e30;
  };
  void polyline(std::span<const Point> points, Rgb8 c, double thickness, ClipRect clip);
  void polyline(std::span<const Point> points, Rgb8 c, double thickness = 1.5) {
    polyline(points, c, thickness, ClipRect{});
  }

  // stb_easy_font text, glyph quads scaled by an integer factor; (x, y) = top-left of a line of height
  // lineHeight(scale). Characters outside printable ASCII are drawn as '?'.
  void text(double x, double y, const std::string& s, Rgb8 c, int scale = 1);
  void textCentered(double cx, double y, const std::string& s, Rgb8 c, int scale = 1);
  // Rotated 90 degrees counter-clockwise (reads bottom to top), its footprint lineHeight(scale) wide with the
  // left edge at x and textWidth(s, scale) tall centred at cy: for y-axis labels.
  void textVertical(double x, double cy, const std::string& s, Rgb8 c, int scale = 1);
  static int textWidth(const std::string& s, int scale = 1);
  static int lineHeight(int scale = 1) { return 12 * scale; }

  std::span<const std::uint8_t> bytes() const { return pixels_; }  // width*height*3
  void writePng(const std::filesystem::path& path) const;          // throws Error naming the path

 private:
  int width_, height_;
  std::vector<std::uint8_t> pixels_;
};

// The pixel index range [first, last) whose centres lie in [a, b) (ends in any order), clamped to [0, size):
// the columns or rows that fillRect touches.
std::pair<int, int> pixelSpan(double a, double b, int size);

// The figures' paper, ink (text, axes and frames) and text scale (tick labels, axis labels, legends,
// captions).
inline constexpr Rgb8 kPaper{255, 255, 255};
inline constexpr Rgb8 kInk{40, 40, 40};
inline constexpr int kFigureTextScale = 2;

}  // namespace iblx
