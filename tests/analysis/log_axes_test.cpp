// Tests of the shared log axes (engine/analysis/log_axes.h): tick choice and labels, label thinning, the data
// ranges (padded, whole decades) and the data-to-pixel mapping.
#include "engine/analysis/log_axes.h"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using namespace iblx;

TEST_CASE("log axes: ticks are decades, 1-2-5 and digits for short ranges; labels") {
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

TEST_CASE("log axes: ticksForLog10Range is logTicks of the range's ends") {
  const std::vector<double> decades = ticksForLog10Range(-3, 1);
  REQUIRE(decades.size() == 5);
  const std::vector<double> direct = logTicks(1e-3, 10);
  REQUIRE(direct.size() == decades.size());
  for (std::size_t i = 0; i < direct.size(); ++i) CHECK(decades[i] == direct[i]);
  // A whole-decade range gets exactly its decades.
  const std::vector<double> one = ticksForLog10Range(2, 3);
  REQUIRE(one.size() == 2);
  CHECK(one[0] == doctest::Approx(100));
  CHECK(one[1] == doctest::Approx(1000));
}

TEST_CASE("log axes: labelStride labels every k-th tick so labels keep 12 px apart") {
  const std::vector<double> positions{0, 40, 80, 120, 160};
  CHECK(labelStride(positions, 20) == 1);  // 20 + 12 <= 40
  CHECK(labelStride(positions, 28) == 1);  // 28 + 12 == 40
  CHECK(labelStride(positions, 29) == 2);
  CHECK(labelStride(positions, 100) == 3);  // ceil(112 / 40)
  // Descending positions (y ticks on screen) and the narrowest gap decide.
  CHECK(labelStride(std::vector<double>{100, 90, 40}, 10) == 3);  // ceil(22 / 10)
  // Fewer than two ticks, or ticks on top of each other: every label.
  CHECK(labelStride(std::vector<double>{}, 50) == 1);
  CHECK(labelStride(std::vector<double>{7}, 50) == 1);
  CHECK(labelStride(std::vector<double>{7, 7}, 50) == 1);
}

TEST_CASE("log axes: LogLogBounds spans the points valid on log-log axes only") {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  CHECK(validLogLogPoint(1e-300, 1e300));
  for (auto [x, y] :
       std::array<std::pair<double, double>, 6>{{{0, 1}, {1, 0}, {-1, 1}, {1, nan}, {inf, 1}, {1, -inf}}})
    CHECK_FALSE(validLogLogPoint(x, y));

  LogLogBounds bounds;
  CHECK(bounds.empty());
  // (x, y) = (1, 1e-2), (10, 1e-3), (100, 1e-4); the invalid points add to neither axis, even where their
  // other coordinate would widen it; the x without a y (the longer vector) is ignored.
  const std::vector<double> xs{1, 10, 1e6, 100, -5, 1e9}, ys{1e-2, 1e-3, 0, 1e-4, 1e-9};
  bounds.add(xs, ys);
  REQUIRE_FALSE(bounds.empty());
  CHECK(bounds.x.lo == doctest::Approx(0));
  CHECK(bounds.x.hi == doctest::Approx(2));
  CHECK(bounds.y.lo == doctest::Approx(-4));
  CHECK(bounds.y.hi == doctest::Approx(-2));
  bounds.add(1e3, nan);
  CHECK(bounds.x.hi == doctest::Approx(2));
  bounds.add(1e3, 1);
  CHECK(bounds.x.hi == doctest::Approx(3));
  CHECK(bounds.y.hi == doctest::Approx(0));

  LogLogBounds none;
  none.add(std::vector<double>{0, nan, 1}, std::vector<double>{1, 1, -1});
  CHECK(none.empty());
  CHECK(none.y.empty());
}

TEST_CASE("log axes: paddedRange pads by 5%, widens one value to a decade; wholeDecades rounds out") {
  LogRange r;
  r.add(-3);
  r.add(1);
  const LogRange padded = paddedRange(r);
  CHECK(padded.lo == doctest::Approx(-3.2));
  CHECK(padded.hi == doctest::Approx(1.2));
  LogRange single;
  single.add(0.25);
  CHECK(paddedRange(single).lo == doctest::Approx(-0.25));
  CHECK(paddedRange(single).hi == doctest::Approx(0.75));
  CHECK(paddedRange(LogRange{}).lo == 0);
  CHECK(paddedRange(LogRange{}).hi == 1);

  LogRange data;
  data.add(-2.7);
  data.add(0.2);
  CHECK(wholeDecades(data).lo == -3);
  CHECK(wholeDecades(data).hi == 1);
  LogRange exact;  // already whole decades: unchanged
  exact.add(-4);
  exact.add(-1);
  CHECK(wholeDecades(exact).lo == -4);
  CHECK(wholeDecades(exact).hi == -1);
  // Inside one decade, or a single value on a decade: at least one decade wide.
  CHECK(wholeDecades(single).lo == 0);
  CHECK(wholeDecades(single).hi == 1);
  LogRange onDecade;
  onDecade.add(2);
  CHECK(wholeDecades(onDecade).lo == 2);
  CHECK(wholeDecades(onDecade).hi == 3);
  CHECK(wholeDecades(LogRange{}).lo == 0);
  CHECK(wholeDecades(LogRange{}).hi == 1);
}

TEST_CASE("log axes: LogLogAxes maps the log10 ranges onto the plot area, y up") {
  LogLogAxes axes;
  axes.left = 50, axes.right = 450, axes.top = 10, axes.bottom = 210;
  axes.log10XMin = 0, axes.log10XMax = 4, axes.log10YMin = -3, axes.log10YMax = 1;
  CHECK(axes.pixelX(1) == doctest::Approx(50));
  CHECK(axes.pixelX(1e4) == doctest::Approx(450));
  CHECK(axes.pixelX(100) == doctest::Approx(250));
  CHECK(axes.pixelY(1e-3) == doctest::Approx(210));
  CHECK(axes.pixelY(10) == doctest::Approx(10));
  CHECK(axes.pixelY(0.1) == doctest::Approx(110));
  // A power law y = x^-1 is a straight line of pixel slope (height / y decades) / (width / x decades).
  const double slope = (axes.pixelY(1e-2) - axes.pixelY(1)) / (axes.pixelX(100) - axes.pixelX(1));
  CHECK(slope == doctest::Approx((200.0 / 4) / (400.0 / 4)));
}
