// Tests of the UTIA .bin reader, writer and reference lookup (engine/io/utia.h): the layout round trip,
// negative entries zeroed with a count, every class of bad file with its message, and the quadrilinear lookup
// at grid points, between them, above 75 degrees, across the azimuth's wrap, and under the colour convention.
#include "engine/io/utia.h"

#include "engine/core/error.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>

using namespace iblx;
using namespace iblx::test;

namespace {

// A table whose every entry differs: value = index + 1 scaled per channel.
std::vector<double> distinctTable() {
  std::vector<double> values(3 * kUtiaEntries);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < kUtiaEntries; ++i)
      values[std::size_t(c) * kUtiaEntries + i] = double(i + 1) * (c + 1) * 1e-5;
  return values;
}

glm::dvec3 direction(double thetaDeg, double phiDeg) {
  const double t = thetaDeg * std::numbers::pi / 180.0, p = phiDeg * std::numbers::pi / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

}  // namespace

TEST_CASE("utia: the .bin layout round-trips; negative entries become 0 and are counted") {
  ScratchDir dir;
  std::vector<double> values = distinctTable();
  values[5] = -0.25;
  values[kUtiaEntries + 7] = -1.0;
  const auto path = dir.file("material.bin");
  writeUtia(path, values);
  CHECK(std::filesystem::file_size(path) == kUtiaFileBytes);
  CHECK(looksLikeUtia(path));
  // Entry (c, ti, pi, tv, pv) sits at byte 8 (c * 82944 + ((ti * 48 + pi) * 6 + tv) * 48 + pv), as the
  // public readers agree.
  std::ifstream in(path, std::ios::binary);
  in.seekg(std::streamoff(8 * (2 * kUtiaEntries + utiaIndex(3, 10, 2, 47))));
  double stored = 0;
  in.read(reinterpret_cast<char*>(&stored), 8);
  CHECK(stored == values[2 * kUtiaEntries + utiaIndex(3, 10, 2, 47)]);

  const UtiaBrdf brdf = loadUtia(path);
  CHECK(brdf.negativeEntries == 2);
  CHECK(brdf.rgb[5] == 0.0f);
  CHECK(brdf.rgb[kUtiaEntries + 7] == 0.0f);
  CHECK(brdf.rgb[9] == float(values[9]));
}

TEST_CASE("utia: bad files are refused with the file and the problem") {
  ScratchDir dir;
  const auto truncated = dir.file("short.bin");
  writeBytes(truncated, std::vector<unsigned char>(1000));
  CHECK(contains(errorMessage([&] { loadUtia(truncated); }), "short.bin: truncated UTIA file: 1000 bytes"));
  CHECK_FALSE(looksLikeUtia(truncated));
  const auto oversized = dir.file("long.bin");
  writeBytes(oversized, std::vector<unsigned char>(kUtiaFileBytes + 8));
  CHECK(contains(errorMessage([&] { loadUtia(oversized); }), "oversized UTIA file"));
  CHECK(contains(errorMessage([&] { loadUtia(dir.file("none.bin")); }), "none.bin"));

  std::vector<double> values(3 * kUtiaEntries, 0.5);
  values[kUtiaEntries + utiaIndex(2, 1, 1, 0)] = std::numeric_limits<double>::quiet_NaN();
  const auto nan = dir.file("nan.bin");
  writeUtia(nan, values);
  CHECK(contains(
      errorMessage([&] { loadUtia(nan); }),
      "nan.bin: channel G at theta_i 30, phi_i 7.5, theta_v 15, phi_v 0 deg is not a finite number"));
  values[kUtiaEntries + utiaIndex(2, 1, 1, 0)] = 1e300;
  writeUtia(nan, values);
  CHECK(contains(errorMessage([&] { loadUtia(nan); }), "above the largest BRDF value iblx accepts"));
}

TEST_CASE("utia: the lookup is quadrilinear, clamps theta above 75 degrees and wraps phi") {
  UtiaBrdf brdf;
  brdf.rgb.resize(3 * kUtiaEntries);
  const std::vector<double> values = distinctTable();
  for (std::size_t k = 0; k < values.size(); ++k) brdf.rgb[k] = float(values[k]);
  const auto at = [&](int ti, int pi, int tv, int pv, int c) {
    return double(brdf.rgb[std::size_t(c) * kUtiaEntries + utiaIndex(ti, pi, tv, pv)]);
  };
  // Grid points: the stored value.
  const glm::dvec3 grid = evalUtia(brdf, utiaDirection(2, 5), utiaDirection(4, 40));
  for (int c = 0; c < 3; ++c) CHECK(grid[c] == doctest::Approx(at(2, 5, 4, 40, c)).epsilon(1e-9));
  // Halfway in theta_i and phi_v: the mean of the four neighbours.
  const glm::dvec3 mid = evalUtia(brdf, direction(37.5, 37.5), direction(60.0, 303.75));
  const double expected =
      0.25 * (at(2, 5, 4, 40, 0) + at(3, 5, 4, 40, 0) + at(2, 5, 4, 41, 0) + at(3, 5, 4, 41, 0));
  CHECK(mid[0] == doctest::Approx(expected).epsilon(1e-9));
  // Above 75 degrees the last samples hold.
  CHECK(evalUtia(brdf, direction(85.0, 15.0), utiaDirection(1, 0))[1] ==
        doctest::Approx(at(5, 2, 1, 0, 1)).epsilon(1e-9));
  // phi just below 360 degrees lies between the last sample and the first.
  const glm::dvec3 wrap = evalUtia(brdf, direction(15.0, 356.25), utiaDirection(0, 0));
  CHECK(wrap[2] == doctest::Approx(0.5 * (at(1, 47, 0, 0, 2) + at(1, 0, 0, 0, 2))).epsilon(1e-9));
  // Below the horizon: nothing.
  CHECK(evalUtia(brdf, {0.0, 0.6, -0.8}, utiaDirection(1, 0)) == glm::dvec3(0.0));
}

TEST_CASE("utia: the colour convention scales before and after the optional sRGB decoding") {
  UtiaBrdf brdf;
  brdf.rgb.assign(3 * kUtiaEntries, 0.5f);
  const glm::dvec3 wi = utiaDirection(1, 3), wo = utiaDirection(2, 9);
  CHECK(evalUtia(brdf, wi, wo).x == doctest::Approx(0.5));
  CHECK(evalUtia(brdf, wi, wo, {2.0, false, 3.0}).x == doctest::Approx(3.0));
  // prescale 1/140, sRGB, scale 100 (one public reader's reading of the database).
  const double decoded = std::pow((0.5 / 140.0 + 0.055) / 1.055, 2.4);
  const double v = 0.5 / 140.0;
  CHECK(evalUtia(brdf, wi, wo, {1.0 / 140.0, true, 100.0}).x ==
        doctest::Approx(100.0 * (v <= 0.04045 ? v / 12.92 : decoded)));
}
