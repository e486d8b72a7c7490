// Tests of engine/sampling/piecewise_constant.h: hand-worked tables, degenerate input and sample/invert round
// trips.
#include "engine/sampling/piecewise_constant.h"

#include "engine/core/error.h"
#include "tests/support/chi2.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

using namespace iblx;

TEST_CASE("piecewise-constant-1d: hand-worked table {1, 3}") {
  const std::vector<double> f{1.0, 3.0};
  const PiecewiseConstant1D d(f);
  // integral = (1 + 3) / 2; cdf = {0, 1/4, 1}; pdf = f / integral = {1/2, 3/2}.
  CHECK(d.integral() == doctest::Approx(2.0));
  CHECK(d.cdf()[1] == doctest::Approx(0.25));
  CHECK(d.pdf(0.1) == doctest::Approx(0.5));
  CHECK(d.pdf(0.9) == doctest::Approx(1.5));
  // u = 0.5 is in bin 1 at offset (0.5 - 0.25) / 0.75 = 1/3, so x = (1 + 1/3) / 2 = 2/3.
  const auto s = d.sample(0.5);
  CHECK(s.bin == 1);
  CHECK(s.x == doctest::Approx(2.0 / 3.0));
  CHECK(s.pdf == doctest::Approx(1.5));
  // u = 0.125 is halfway through bin 0: x = 1/4.
  CHECK(d.sample(0.125).x == doctest::Approx(0.25));
  CHECK(*d.invert(2.0 / 3.0) == doctest::Approx(0.5));
  CHECK(*d.invert(0.25) == doctest::Approx(0.125));
  CHECK_FALSE(d.invert(1.0));
  CHECK_FALSE(d.invert(-0.1));
  CHECK(d.pdf(1.0) == 0.0);
}

TEST_CASE("piecewise-constant-1d: zero bins are never sampled") {
  const std::vector<double> f{0.0, 2.0, 0.0, 2.0};
  const PiecewiseConstant1D d(f);
  // cdf = {0, 0, 1/2, 1/2, 1}; integral = 1.
  CHECK(d.integral() == doctest::Approx(1.0));
  CHECK(d.sample(0.0).bin == 1);
  CHECK(d.sample(0.0).x == doctest::Approx(0.25));
  CHECK(d.sample(0.5).bin == 3);
  CHECK(d.sample(0.5).x == doctest::Approx(0.75));
  CHECK(d.sample(std::nextafter(1.0, 0.0)).bin == 3);
  CHECK(d.pdf(0.1) == 0.0);
  CHECK(d.pdf(0.3) == doctest::Approx(2.0));
  CHECK_FALSE(d.invert(0.1));
  for (const auto u : test::uniformPoints(1000, 7)) CHECK(d.func(d.sample(u.x).bin) > 0.0);
}

TEST_CASE("piecewise-constant-1d: all-zero function is uniform") {
  const std::vector<double> f(5, 0.0);
  const PiecewiseConstant1D d(f);
  CHECK(d.integral() == 0.0);
  CHECK(d.pdf(0.3) == 1.0);
  const auto s = d.sample(0.3);
  CHECK(s.x == doctest::Approx(0.3));
  CHECK(s.pdf == 1.0);
  CHECK(*d.invert(0.3) == doctest::Approx(0.3));
}

TEST_CASE("piecewise-constant-1d: rejects bad input") {
  CHECK_THROWS_AS(PiecewiseConstant1D(std::vector<double>{}), Error);
  CHECK_THROWS_AS(PiecewiseConstant1D(std::vector<double>{1.0, -1.0}), Error);
  CHECK_THROWS_AS(PiecewiseConstant1D(std::vector<double>{1.0, std::numeric_limits<double>::quiet_NaN()}),
                  Error);
  CHECK_THROWS_AS(PiecewiseConstant1D(std::vector<double>{std::numeric_limits<double>::infinity()}), Error);
}

TEST_CASE("piecewise-constant-1d: sample -> invert round trip over 1000 u") {
  const std::vector<double> f{0.5, 0.0, 7.0, 1e-6, 3.0, 0.0, 0.0, 2.0};
  const PiecewiseConstant1D d(f);
  for (const auto u : test::uniformPoints(1000, 11)) {
    const auto s = d.sample(u.x);
    REQUIRE(s.x >= 0.0);
    REQUIRE(s.x < 1.0);
    CHECK(s.pdf == doctest::Approx(d.pdf(s.x)));
    CHECK(s.pdf > 0.0);
    const auto back = d.invert(s.x);
    REQUIRE(back);
    CHECK(*back == doctest::Approx(u.x).epsilon(1e-9));
  }
  // The pdf integrates to 1: sum over bins of pdf / n.
  double sum = 0.0;
  for (int i = 0; i < d.size(); ++i) sum += d.pdf((i + 0.5) / d.size()) / d.size();
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("piecewise-constant-2d: hand-worked 2x2 table") {
  // Rows (v): {1, 3} and {0, 4}. Row integrals 2 and 2, integral 2; marginal cdf {0, 1/2, 1}.
  const std::vector<double> f{1.0, 3.0, 0.0, 4.0};
  const PiecewiseConstant2D d(f, 2, 2);
  CHECK(d.integral() == doctest::Approx(2.0));
  // u.y = 0.75 -> row 1 at offset 1/2 -> p.y = 3/4; row 1's cdf {0, 0, 1}: u.x = 0.5 -> bin 1, p.x = 3/4.
  const auto s = d.sample({0.5, 0.75});
  CHECK(s.bin == glm::ivec2(1, 1));
  CHECK(s.p.x == doctest::Approx(0.75));
  CHECK(s.p.y == doctest::Approx(0.75));
  CHECK(s.pdf == doctest::Approx(2.0));  // f / integral = 4 / 2
  // u = (0.125, 0.25) -> row 0 at offset 1/2 -> p.y = 1/4; row 0's cdf {0, 1/4, 1}: bin 0 at offset 1/2.
  const auto t = d.sample({0.125, 0.25});
  CHECK(t.bin == glm::ivec2(0, 0));
  CHECK(t.p.x == doctest::Approx(0.25));
  CHECK(t.p.y == doctest::Approx(0.25));
  CHECK(t.pdf == doctest::Approx(0.5));
  CHECK(d.pdf({0.25, 0.75}) == 0.0);
  CHECK_FALSE(d.invert({0.25, 0.75}));
  const auto u = d.invert({0.75, 0.75});
  REQUIRE(u);
  CHECK(u->x == doctest::Approx(0.5));
  CHECK(u->y == doctest::Approx(0.75));
  CHECK_THROWS_AS(PiecewiseConstant2D(f, 3, 2), Error);
}

TEST_CASE("piecewise-constant-2d: sample -> invert round trip over 1000 u") {
  // 5 x 3 with a zero row and zero entries; all-zero rows are never chosen.
  const std::vector<double> f{1, 0, 2, 5, 0.1, 0, 0, 0, 0, 0, 3, 3, 0, 1e-3, 8};
  const PiecewiseConstant2D d(f, 5, 3);
  double integral = 0.0;
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 5; ++u) integral += d.pdf({(u + 0.5) / 5.0, (v + 0.5) / 3.0}) / 15.0;
  CHECK(integral == doctest::Approx(1.0).epsilon(1e-12));
  for (const auto u : test::uniformPoints(1000, 13)) {
    const auto s = d.sample(u);
    CHECK(s.bin.y != 1);
    CHECK(s.pdf > 0.0);
    CHECK(s.pdf == doctest::Approx(d.pdf(s.p)));
    const auto back = d.invert(s.p);
    REQUIRE(back);
    CHECK(back->x == doctest::Approx(u.x).epsilon(1e-9));
    CHECK(back->y == doctest::Approx(u.y).epsilon(1e-9));
  }
}
