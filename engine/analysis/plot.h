// Figures for the convergence study: a small RGB8 raster (Canvas) with lines, rectangles and stb_easy_font
// text, log-log line plots with spread bands, and per-pixel error heat maps, written as PNG.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
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

// A categorical palette of 10 distinguishable colors (Tableau 10), cycling.
Rgb8 paletteColor(std::size_t index);

struct HeatMap {
  std::string title;
  int width = 0, height = 0;   // of the image
  std::vector<double> values;  // width*height, row-major, top row first; NaN = masked (drawn grey)
  double low = 0, high = 1;    // value range, mapped log10 when logScale
  bool logScale = true;        // values <= 0 with logScale count as `low`
  std::string unit;            // colorbar caption, e.g. "relative squared error"
};

// The image scaled by an integer factor so it is at least 256 px on its long side (nearest neighbour, pixels
// stay visible), coloured by colormap(), a colorbar with 3-5 labelled ticks (decades when logScale), the unit
// along the colorbar and the title. Throws Error for a size mismatch, high <= low, or low <= 0 with logScale.
Canvas drawHeatMap(const HeatMap& map);

// Our own dark-blue -> teal -> green -> yellow map (a smooth spline through six control points whose luma
// rises steadily); t is clamped to [0, 1]; NaN gives kMaskedGrey.
Rgb8 colormap(double t);
inline constexpr Rgb8 kMaskedGrey{128, 128, 128};

// Exposed for tests and for callers that want the same axis conventions.
namespace plot_detail {

// Tick values inside [lo, hi] (lo, hi > 0), ascending: the decades; if fewer than 2, also 2x and 5x; if still
// fewer than 2, every 1..9 x 10^k; if still fewer than 2, 2 to 5 evenly spaced ticks at a 1-2-5 step.
std::vector<double> logTicks(double lo, double hi);
// "1e-3", "2e-3", "1", "5", "1e1", "2e2"; other mantissas print with the fewest digits (up to 6) that give
// the value: "3.25", "3.25e-2".
std::string tickLabel(double v);

// Where drawLogLogPlot puts the data: the plot area in pixels and the log10 ranges it spans.
struct LogLogFrame {
  double left = 0, top = 0, right = 0, bottom = 0;  // plot area, pixels
  double log10XMin = 0, log10XMax = 1, log10YMin = 0, log10YMax = 1;
  bool hasData = false;
  double pixelX(double x) const;  // x > 0
  double pixelY(double y) const;  // y > 0
};
LogLogFrame logLogFrame(const LogLogPlot& plot, int width, int height);

}  // namespace plot_detail
}  // namespace iblx
