// Tests of the figures' raster (engine/analysis/canvas.h): set/at, rectangles, lines, text and PNG output.
#include "engine/analysis/canvas.h"

#include "engine/core/error.h"
#include "tests/support/canvas_probes.h"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

using namespace iblx;
using namespace iblx::test;

namespace {

std::filesystem::path tempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("iblx_canvas_test_" + name);
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
