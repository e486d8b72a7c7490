// Tests of the figure library (engine/analysis/plot.h): Canvas primitives and text, tick choice and labels,
// the log-log plot geometry (slope, breaks, bands, empty plots), the colormap, heat maps and PNG output.
#include "engine/analysis/plot.h"

#include "engine/core/error.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

using namespace iblx;

namespace {

constexpr Rgb8 kWhite{255, 255, 255};
constexpr Rgb8 kRed{200, 20, 20};
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// Non-background pixels inside and outside a rectangle [x0, x1) x [y0, y1).
struct Footprint {
  int inside = 0, outside = 0;
  int minX = 1 << 30, maxX = -1, minY = 1 << 30, maxY = -1;
};

Footprint footprint(const Canvas& canvas, Rgb8 background, int x0, int y0, int x1, int y1) {
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
std::optional<double> meanRowOfColor(const Canvas& canvas, int column, Rgb8 color) {
  double sum = 0;
  int count = 0;
  for (int y = 0; y < canvas.height(); ++y)
    if (canvas.at(column, y) == color) sum += y, ++count;
  if (count == 0) return std::nullopt;
  return sum / count;
}

int countColor(const Canvas& canvas, Rgb8 color, int x0, int x1) {
  int count = 0;
  for (int y = 0; y < canvas.height(); ++y)
    for (int x = x0; x < x1; ++x) count += canvas.at(x, y) == color;
  return count;
}

double luma(Rgb8 c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

std::filesystem::path tempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("iblx_plot_test_" + name);
}

}  // namespace

TEST_CASE("Canvas: set/at round trip, out-of-bounds writes are ignored") {
  Canvas canvas(7, 5, kWhite);
  CHECK(canvas.width() == 7);
  CHECK(canvas.height() == 5);
  CHECK(canvas.bytes().size() == 7 * 5 * 3);
  canvas.set(3, 2, kRed);
  CHECK(canvas.at(3, 2) == kRed);
  CHECK(canvas.at(2, 2) == kWhite);
  // Row-major, top row first, 3 bytes per pixel.
  CHECK(canvas.bytes()[3 * (2 * 7 + 3)] == kRed.r);
  CHECK(canvas.bytes()[3 * (2 * 7 + 3) + 1] == kRed.g);
  for (auto [x, y] : std::array<std::pair<int, int>, 4>{{{-1, 0}, {7, 0}, {0, -1}, {0, 5}}})
    canvas.set(x, y, kRed);
  CHECK(footprint(canvas, kWhite, 0, 0, 7, 5).inside == 1);
}

TEST_CASE("Canvas: fillRect covers exactly the pixels whose centres are inside, clipped") {
  Canvas canvas(10, 8, kWhite);
  canvas.fillRect(2, 3, 5, 7, kRed);  // x 2..4, y 3..6
  const Footprint f = footprint(canvas, kWhite, 2, 3, 5, 7);
  CHECK(f.inside == 3 * 4);
  CHECK(f.outside == 0);
  // Corners in any order; fractional edges select by pixel centre.
  Canvas other(10, 8, kWhite);
  other.fillRect(3.4, 1.4, 1.6, 0.6, kRed);  // no row centre (0.5, 1.5) lies in [0.6, 1.4)
  CHECK(footprint(other, kWhite, 0, 0, 10, 8).inside == 0);
  other.fillRect(3.6, 2.6, 1.4, 0.4, kRed);  // x = 1, 2, 3; y = 0, 1, 2
  const Footprint g = footprint(other, kWhite, 1, 0, 4, 3);
  CHECK(g.inside == 9);
  CHECK(g.outside == 0);
  // Clipping: a rectangle hanging over every edge fills the canvas and nothing breaks.
  Canvas clipped(4, 3, kWhite);
  clipped.fillRect(-10, -10, 100, 100, kRed);
  CHECK(footprint(clipped, kRed, 0, 0, 4, 3).inside == 0);
}

TEST_CASE("Canvas: blendRect mixes the colour by alpha") {
  Canvas canvas(4, 4, kWhite);
  canvas.blendRect(0, 0, 2, 2, {0, 0, 0}, 0.25);
  CHECK(canvas.at(1, 1) == Rgb8{191, 191, 191});
  CHECK(canvas.at(2, 2) == kWhite);
}

TEST_CASE("Canvas: lines colour their path and nothing 3+ px away") {
  SUBCASE("horizontal") {
    Canvas canvas(40, 20, kWhite);
    canvas.line(5, 10.5, 35, 10.5, kRed, 1.5);
    for (int x = 6; x < 35; ++x) CHECK(canvas.at(x, 10) == kRed);
    for (int x = 0; x < 40; ++x) {
      CHECK(canvas.at(x, 7) == kWhite);
      CHECK(canvas.at(x, 13) == kWhite);
    }
    CHECK(canvas.at(1, 10) == kWhite);
    CHECK(canvas.at(38, 10) == kWhite);
  }
  SUBCASE("diagonal") {
    Canvas canvas(40, 40, kWhite);
    canvas.line(5, 5, 35, 35, kRed, 2.5);
    for (int i = 6; i < 35; ++i) CHECK(canvas.at(i, i) == kRed);
    // Perpendicular distance of pixel (x, y) from the diagonal is |x - y| / sqrt 2: |x - y| >= 5 is >= 3.5
    // px.
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x)
        if (std::abs(x - y) >= 5) CHECK(canvas.at(x, y) == kWhite);
  }
}

TEST_CASE("Canvas: text stays inside its textWidth x lineHeight box; vertical text is taller than wide") {
  const std::string s = "Hello 1e-3 gjpqy";
  for (int scale : {1, 2, 3}) {
    Canvas canvas(300, 80, kWhite);
    canvas.text(10, 20, s, kRed, scale);
    const Footprint f =
        footprint(canvas, kWhite, 10, 20, 10 + Canvas::textWidth(s, scale), 20 + Canvas::lineHeight(scale));
    CHECK(f.inside > 20 * scale * scale);
    CHECK(f.outside == 0);
    // Wide: the glyphs span most of the advertised width.
    CHECK(f.maxX - f.minX + 1 > Canvas::textWidth(s, scale) * 8 / 10);
  }
  CHECK(Canvas::textWidth("abc", 2) == 2 * Canvas::textWidth("abc"));
  CHECK(Canvas::textWidth("abcdef") > Canvas::textWidth("abc"));

  Canvas canvas(80, 300, kWhite);
  canvas.textVertical(20, 150, s, kRed, 2);
  const int w = Canvas::textWidth(s, 2), h = Canvas::lineHeight(2);
  const Footprint f = footprint(canvas, kWhite, 20, 150 - w / 2 - 1, 20 + h, 150 + w / 2 + 1);
  CHECK(f.outside == 0);
  CHECK(f.maxY - f.minY > 4 * (f.maxX - f.minX));
  // Counter-clockwise: the first letter ("H") is at the bottom.
  Canvas first(80, 300, kWhite);
  first.textVertical(20, 150, "H     ", kRed, 2);
  CHECK(footprint(first, kWhite, 0, 0, 80, 300).minY > 150);

  Canvas centred(200, 40, kWhite);
  centred.textCentered(100, 10, "mmmm", kRed, 2);
  const Footprint c = footprint(centred, kWhite, 0, 0, 200, 40);
  CHECK(std::abs(0.5 * (c.minX + c.maxX + 1) - 100) <= 2);
}

TEST_CASE("plot ticks: decades, 1-2-5 and digits for short ranges, labels") {
  using plot_detail::logTicks;
  using plot_detail::tickLabel;
  const std::vector<double> decades = logTicks(1e-3, 2e1);
  REQUIRE(decades.size() == 5);
  const std::array<double, 5> expected{1e-3, 1e-2, 1e-1, 1, 10};
  for (std::size_t i = 0; i < 5; ++i) CHECK(decades[i] == doctest::Approx(expected[i]).epsilon(1e-12));

  const std::vector<double> short1 = logTicks(3, 7);
  CHECK(short1.size() >= 2);
  for (double t : short1) CHECK((t >= 3 && t <= 7));
  const std::vector<double> short2 = logTicks(0.15, 0.9);  // 2e-1, 5e-1
  REQUIRE(short2.size() == 2);
  CHECK(short2[0] == doctest::Approx(0.2));
  CHECK(short2[1] == doctest::Approx(0.5));
  const std::vector<double> fine = logTicks(3.1, 3.2);  // 3.12, 3.14, 3.16, 3.18
  CHECK(fine.size() >= 2);
  CHECK(fine.size() <= 5);
  for (double t : fine) CHECK((t >= 3.1 && t <= 3.2));

  CHECK(tickLabel(1e-3) == "1e-3");
  CHECK(tickLabel(2e-3) == "2e-3");
  CHECK(tickLabel(1) == "1");
  CHECK(tickLabel(5) == "5");
  CHECK(tickLabel(10) == "1e1");
  CHECK(tickLabel(1e6) == "1e6");
  CHECK(tickLabel(3.25) == "3.25");
  CHECK(tickLabel(0.0325) == "3.25e-2");
  CHECK(tickLabel(3.105) == "3.105");
  CHECK(tickLabel(9.9999999) == "1e1");
}

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
  const auto frame = plot_detail::logLogFrame(plot, 900, 600);
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
  const auto frame = plot_detail::logLogFrame(plot, 900, 600);
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
  const auto frame = plot_detail::logLogFrame(plot, 900, 600);
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
    const auto frame = plot_detail::logLogFrame(p, 900, 600);
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
  const auto frame = plot_detail::logLogFrame(plot, 900, 600);
  // Right of the plot area are the legend swatches: the palette colours.
  for (int k = 0; k < 8; ++k)
    CHECK(countColor(canvas, paletteColor(k), int(frame.right) + 2, canvas.width()) > 10);
  CHECK(paletteColor(0) != paletteColor(1));
  CHECK(paletteColor(10) == paletteColor(0));
}

TEST_CASE("colormap: luma rises monotonically, NaN is the masked grey") {
  double previous = -1;
  for (int i = 0; i < 256; ++i) {
    const double l = luma(colormap(i / 255.0));
    CHECK(l > previous);
    previous = l;
  }
  CHECK(luma(colormap(0)) < 40);
  CHECK(luma(colormap(1)) > 200);
  CHECK(colormap(-5) == colormap(0));
  CHECK(colormap(7) == colormap(1));
  // Dark blue at the bottom, yellow at the top.
  CHECK(colormap(0).b > colormap(0).r);
  CHECK((colormap(1).r > 200 && colormap(1).g > 200 && colormap(1).b < 100));
  CHECK(colormap(kNaN) == kMaskedGrey);
  CHECK((kMaskedGrey.r == kMaskedGrey.g && kMaskedGrey.g == kMaskedGrey.b));
}

TEST_CASE("heat map: values map to dark and bright at the scaled pixel positions, NaN is grey") {
  HeatMap map;
  map.title = "relative error";
  map.unit = "relative squared error";
  map.width = 4;
  map.height = 2;
  map.values = {1e-4, 1e-3, 1e-2, 1e-1, 1e0, kNaN, 5e-3, 1e-7};
  map.low = 1e-4;
  map.high = 1;
  const Canvas canvas = drawHeatMap(map);
  // 4x2 scales by 64 to 256x128; find the image through its top-left pixel (value 1e-4 -> colormap(0)).
  const Rgb8 darkest = colormap(0), brightest = colormap(1);
  int left = -1, top = -1;
  for (int y = 0; y < canvas.height() && left < 0; ++y)
    for (int x = 0; x < canvas.width(); ++x)
      if (canvas.at(x, y) == darkest) {
        left = x, top = y;
        break;
      }
  REQUIRE(left >= 0);
  const int zoom = 64;
  const auto cell = [&](int x, int y) {
    return canvas.at(left + x * zoom + zoom / 2, top + y * zoom + zoom / 2);
  };
  CHECK(cell(0, 0) == darkest);
  CHECK(canvas.at(left + zoom - 1, top + zoom - 1) == darkest);
  CHECK(canvas.at(left + zoom, top) != darkest);
  CHECK(cell(0, 1) == brightest);  // 1e0
  CHECK(luma(cell(0, 1)) > 200);
  CHECK(luma(cell(0, 0)) < 40);
  CHECK(cell(1, 1) == kMaskedGrey);            // NaN
  CHECK(cell(2, 0) == colormap(0.5));          // 1e-2 is half way in log space
  CHECK(cell(3, 1) == darkest);                // below low clamps
  CHECK(luma(cell(1, 0)) < luma(cell(2, 0)));  // 1e-3 < 1e-2
  CHECK(canvas.width() > 256);                 // room for the colorbar
  // The colorbar holds the whole map: its brightest and darkest colours appear right of the image.
  CHECK(countColor(canvas, brightest, left + 4 * zoom + 1, canvas.width()) > 0);

  HeatMap bad = map;
  bad.values.pop_back();
  CHECK_THROWS_AS(drawHeatMap(bad), Error);
  bad = map;
  bad.low = 0;
  CHECK_THROWS_AS(drawHeatMap(bad), Error);
}

TEST_CASE("Canvas writePng: a PNG file, and an Error naming an unwritable path") {
  Canvas canvas(16, 8, kWhite);
  canvas.fillRect(2, 2, 10, 6, kRed);
  const std::filesystem::path path = tempPath("out.png");
  std::filesystem::remove(path);
  canvas.writePng(path);
  REQUIRE(std::filesystem::exists(path));
  std::ifstream file(path, std::ios::binary);
  std::array<char, 8> signature{};
  file.read(signature.data(), 8);
  CHECK(std::string(signature.data(), 8) == std::string("\x89PNG\r\n\x1a\n", 8));
  std::filesystem::remove(path);

  const std::filesystem::path bad = tempPath("no_such_dir") / "sub" / "out.png";
  try {
    canvas.writePng(bad);
    FAIL("no exception");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find(bad.string()) != std::string::npos);
  }
}
