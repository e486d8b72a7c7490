// Tests of the shared log axes (engine/analysis/log_axes.h): tick choice and labels, label thinning, the data
// ranges (padded, whole decades) and the data-to-pixel mapping.
#include "engine/analysis/log_axes.h"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
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
