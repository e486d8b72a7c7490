// Tests of the MERL .binary reader and writer (engine/io/merl.h): write -> read round trip, every bad file a
// user can hand us (each must throw iblx::Error naming the file), invalid bins, and the index math of the
// reference lookup (bin centres, layout, reciprocity, isotropy, known angles).
#include "engine/io/merl.h"

#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cstring>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr double kPi = std::numbers::pi;

// Reflectance of bin `bin` in channel c: distinct for every bin and channel, and exact in float (bin < 2^21,
// two fractional bits), so a lookup in the wrong bin or channel shows.
double distinctValue(std::size_t bin, int c) {
  return double(bin) + 0.25 * c;
}

MerlBrdf distinctMaterial() {
  MerlBrdf brdf;
  brdf.rgb.resize(3 * kMerlBins);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < kMerlBins; ++i)
      brdf.rgb[std::size_t(c) * kMerlBins + i] = float(distinctValue(i, c));
  return brdf;
}

// Values of a plausible material for file round trips: positive, spread over a few decades, distinct per bin.
std::vector<double> fileValues() {
  std::vector<double> v(3 * kMerlBins);
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = 1e-3 * double(k % 100003 + 1) * (1.0 + double(k / kMerlBins));
  return v;
}

// The bytes writeMerl writes for fileValues(), made once (the bad-file subcases each start from them).
const std::vector<unsigned char>& goodFileBytes() {
  static const std::vector<unsigned char> bytes = [] {
    ScratchDir dir;
    const auto path = dir.file("good.binary");
    writeMerl(path, fileValues());
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> b(std::size_t(std::filesystem::file_size(path)));
    in.read(reinterpret_cast<char*>(b.data()), std::streamsize(b.size()));
    return b;
  }();
  return bytes;
}

// splitmix64 points in [0,1)^2 (the io tests do not link the sampling test support).
class Points {
 public:
  explicit Points(std::uint64_t seed) : state_(seed) {}
  double next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return double((z ^ (z >> 31)) >> 11) * 0x1p-53;
  }

 private:
  std::uint64_t state_;
};

// Uniform direction on the upper hemisphere (z > 0 except for u = 1, which next() never returns).
glm::dvec3 upperDirection(Points& p) {
  const double z = 1.0 - p.next(), phi = 2.0 * kPi * p.next();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

glm::dvec3 rotateZ(glm::dvec3 v, double a) {
  return {v.x * std::cos(a) - v.y * std::sin(a), v.x * std::sin(a) + v.y * std::cos(a), v.z};
}

void checkErrorNamesFile(const std::filesystem::path& path, const std::string& message) {
  INFO("message: " << message);
  CHECK(contains(message, path.string()));
  CHECK_FALSE(contains(message, "<"));  // errorMessage's markers for "not an iblx::Error" or "no exception"
}

std::string ivec3Text(glm::ivec3 v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

}  // namespace

TEST_CASE("merl: writeMerl -> loadMerl round trip") {
  ScratchDir dir;
  const auto path = dir.file("material.binary");
  const std::vector<double> values = fileValues();
  writeMerl(path, values);
  CHECK(std::filesystem::file_size(path) == kMerlFileBytes);

  // The bytes: little-endian int32 header 90, 90, 180, then value / scale as little-endian doubles.
  const std::vector<unsigned char>& bytes = goodFileBytes();  // written from the same values
  REQUIRE(bytes.size() == kMerlFileBytes);
  const std::vector<unsigned char> header{90, 0, 0, 0, 90, 0, 0, 0, 180, 0, 0, 0};
  CHECK(std::vector<unsigned char>(bytes.begin(), bytes.begin() + 12) == header);
  for (int c = 0; c < 3; ++c) {
    const std::size_t k = std::size_t(c) * kMerlBins + 12345;
    std::uint64_t bits = 0;
    for (int b = 7; b >= 0; --b) bits = bits << 8 | bytes[12 + 8 * k + std::size_t(b)];
    CHECK(std::bit_cast<double>(bits) == values[k] / kMerlChannelScale[std::size_t(c)]);
  }

  WarningCapture warnings;
  const MerlBrdf brdf = loadMerl(path);
  CHECK(warnings.messages.empty());
  CHECK(brdf.invalidBins == 0);
  REQUIRE(brdf.rgb.size() == 3 * kMerlBins);
  // Scale on write, scale back on read: the value again, up to float rounding.
  std::size_t mismatches = 0;
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!(std::abs(double(brdf.rgb[k]) - values[k]) <= 1e-7 * values[k])) ++mismatches;
  CHECK(mismatches == 0);
}

TEST_CASE("merl: writeMerl rejects a wrong value count and an unwritable path") {
  ScratchDir dir;
  const auto path = dir.file("short.binary");
  const std::vector<double> few(100, 1.0);
  const std::string message = errorMessage([&] { writeMerl(path, few); });
  checkErrorNamesFile(path, message);
  CHECK(contains(message, "100 values"));
  const auto nowhere = dir.file("no_such_dir") / "m.binary";
  const std::string unwritable = errorMessage([&] { writeMerl(nowhere, fileValues()); });
  checkErrorNamesFile(nowhere, unwritable);
  CHECK(contains(unwritable, "cannot write"));
}

TEST_CASE("merl: bad files throw iblx::Error naming the file and the problem") {
  ScratchDir dir;
  const std::vector<unsigned char>& bytes = goodFileBytes();
  const std::string expectedBytes = std::to_string(kMerlFileBytes);

  SUBCASE("missing file") {
    const auto path = dir.file("missing.binary");
    const std::string message = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "cannot open"));
  }
  SUBCASE("a directory") {
    const auto path = dir.file("folder.binary");
    std::filesystem::create_directory(path);
    const std::string message = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "cannot open"));
  }
  SUBCASE("truncated by one double") {
    const auto path = dir.file("truncated.binary");
    writeBytes(path, std::vector<unsigned char>(bytes.begin(), bytes.end() - 8));
    const std::string message = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "truncated"));
    CHECK(contains(message, std::to_string(kMerlFileBytes - 8)));
    CHECK(contains(message, expectedBytes));
  }
  SUBCASE("oversized by one double") {
    const auto path = dir.file("oversized.binary");
    std::vector<unsigned char> longer = bytes;
    longer.insert(longer.end(), 8, 0);
    writeBytes(path, longer);
    const std::string message = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "oversized"));
    CHECK(contains(message, std::to_string(kMerlFileBytes + 8)));
    CHECK(contains(message, expectedBytes));
  }
  SUBCASE("empty file") {
    const auto path = dir.file("empty.binary");
    writeBytes(path, {});
    const std::string message = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "truncated"));
    CHECK(contains(message, " 0 bytes"));
  }
  SUBCASE("wrong header with the right size") {
    const auto path = dir.file("header.binary");
    std::vector<unsigned char> wrong = bytes;
    wrong[8] = 90;  // (90, 90, 90)
    writeBytes(path, wrong);
    const std::string message = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "header"));
    CHECK(contains(message, "(90, 90, 90)"));
    // A byte-swapped (big-endian) header shows its values as read.
    for (int d = 0; d < 3; ++d) {
      std::swap(wrong[4 * d], wrong[4 * d + 3]);
      std::swap(wrong[4 * d + 1], wrong[4 * d + 2]);
    }
    wrong[8 + 3] = 180;
    writeBytes(path, wrong);
    const std::string swapped = errorMessage([&] { loadMerl(path); });
    checkErrorNamesFile(path, swapped);
    CHECK(contains(swapped, "(1509949440, 1509949440, -1275068416)"));
  }
}

TEST_CASE("merl: invalid bins load as 0 in all channels with one counting warning") {
  ScratchDir dir;
  const auto path = dir.file("holes.binary");
  std::vector<double> values = fileValues();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const auto set = [&](std::size_t bin, int c, double v) { values[std::size_t(c) * kMerlBins + bin] = v; };
  // MERL's "below horizon" marker: -1 in all three channels.
  const std::vector<std::size_t> allChannels{0, 17, 700000, kMerlBins - 1};
  for (std::size_t bin : allChannels)
    for (int c = 0; c < 3; ++c) set(bin, c, -1.0);
  // One bad channel is enough to drop the bin.
  const std::vector<std::size_t> oneChannel{100, 200, 300, 400, 500};
  set(100, 1, -1.0);
  set(200, 2, nan);
  set(300, 0, inf);
  set(400, 0, -1e-300);  // negative, though it rounds to -0 in float
  set(500, 2, -inf);
  writeMerl(path, values);

  WarningCapture warnings;
  const MerlBrdf brdf = loadMerl(path);
  CHECK(brdf.invalidBins == allChannels.size() + oneChannel.size());
  REQUIRE(warnings.messages.size() == 1);
  const std::string& warning = warnings.messages[0];
  INFO(warning);
  CHECK(contains(warning, path.string()));
  CHECK(contains(warning, "9 of 1458000 MERL bins are invalid"));
  for (const auto* bins : {&allChannels, &oneChannel})
    for (std::size_t bin : *bins) {
      CAPTURE(bin);
      for (int c = 0; c < 3; ++c) CHECK(brdf.rgb[std::size_t(c) * kMerlBins + bin] == 0.0f);
      CHECK(std::signbit(brdf.rgb[bin]) == false);
    }
  // Neighbours keep their values; every value is finite and >= 0.
  for (int c = 0; c < 3; ++c)
    CHECK(brdf.rgb[std::size_t(c) * kMerlBins + 101] == float(values[std::size_t(c) * kMerlBins + 101]));
  std::size_t bad = 0;
  for (float v : brdf.rgb) bad += !(std::isfinite(v) && v >= 0.0f);
  CHECK(bad == 0);
}

TEST_CASE("merl: merlBinIndex layout") {
  CHECK(merlBinIndex(0, 0, 0) == 0);
  CHECK(merlBinIndex(0, 0, 1) == 1);
  CHECK(merlBinIndex(0, 1, 0) == 180);
  CHECK(merlBinIndex(1, 0, 0) == 180 * 90);
  CHECK(merlBinIndex(89, 89, 179) == kMerlBins - 1);
  // phi_d fastest, then theta_d, then theta_h: the nested loops count 0, 1, 2, ...
  std::size_t expected = 0, wrong = 0;
  for (int i = 0; i < kMerlThetaHBins; ++i)
    for (int j = 0; j < kMerlThetaDBins; ++j)
      for (int k = 0; k < kMerlPhiDBins; ++k) wrong += merlBinIndex(i, j, k) != expected++;
  CHECK(wrong == 0);
  CHECK(kMerlFileBytes == 34992012);
}

TEST_CASE("merl: known angles and bins") {
  const glm::dvec3 n(0.0, 0.0, 1.0);
  const MerlAngles normal = merlAngles(n, n);
  CHECK(normal.thetaH == 0.0);
  CHECK(normal.thetaD == 0.0);
  CHECK(normal.phiD == 0.0);
  CHECK(merlBin(normal) == glm::ivec3(0, 0, 0));

  // Mirror pair at 40 degrees: h = n, theta_d = 40 degrees, wi's azimuth 0.
  const double a = 40.0 * kPi / 180.0;
  const MerlAngles mirror = merlAngles({std::sin(a), 0.0, std::cos(a)}, {-std::sin(a), 0.0, std::cos(a)});
  CHECK(mirror.thetaH == doctest::Approx(0.0).epsilon(1e-12));
  CHECK(mirror.thetaD == doctest::Approx(a).epsilon(1e-12));
  CHECK(mirror.phiD == doctest::Approx(0.0).epsilon(1e-12));

  // wo = n, wi at 61 degrees in the xz plane: h at 30.5 degrees, theta_d = 30.5 degrees (mid-bin: the theta_d
  // bins are 1 degree wide); wi lies in the plane of h and n, on the far side of h: phi_d = 0.
  const double b = 61.0 * kPi / 180.0;
  const MerlAngles tilted = merlAngles({std::sin(b), 0.0, std::cos(b)}, n);
  CHECK(tilted.thetaH == doctest::Approx(b / 2.0).epsilon(1e-12));
  CHECK(tilted.thetaD == doctest::Approx(b / 2.0).epsilon(1e-12));
  CHECK(tilted.phiD == doctest::Approx(0.0).epsilon(1e-12));
  // The same pair turned to wi in the yz plane: phi_d is wi's azimuth in the frame of h, so it stays 0.
  const MerlAngles turned = merlAngles({0.0, std::sin(b), std::cos(b)}, n);
  CHECK(turned.phiD == doctest::Approx(0.0).epsilon(1e-12));
  // wi and wo swapped: phi_d + pi, folded back to 0.
  CHECK(merlAngles(n, {std::sin(b), 0.0, std::cos(b)}).phiD == doctest::Approx(0.0).epsilon(1e-12));

  // Bins: theta_h is square-root warped, 30.5 degrees is u = sqrt(30.5 / 90) = 0.582 -> bin 52; theta_d
  // linear -> bin 30; the ends of the domain clamp.
  CHECK(merlBin(tilted) == glm::ivec3(52, 30, 0));
  CHECK(merlBin({kPi / 2.0, kPi / 2.0, kPi}) == glm::ivec3(89, 89, 179));
  CHECK(merlBin({-1.0, -1.0, -1.0}) == glm::ivec3(0, 0, 0));
  CHECK(merlBin({std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0}) == glm::ivec3(0, 0, 0));
  // theta_h bin k starts at (k/90)^2 pi/2.
  const double start = (10.0 / 90.0) * (10.0 / 90.0) * (kPi / 2.0);
  CHECK(merlBin({start * (1.0 + 1e-9), 0.0, 0.0}).x == 10);
  CHECK(merlBin({start * (1.0 - 1e-9), 0.0, 0.0}).x == 9);

  // Below the horizon f is 0.
  const MerlBrdf brdf = distinctMaterial();
  CHECK(evalMerl(brdf, {0.0, 0.6, -0.8}, n) == glm::dvec3(0.0));
  CHECK(evalMerl(brdf, n, {1.0, 0.0, 0.0}) == glm::dvec3(0.0));
  CHECK(evalMerl(brdf, n, n) == glm::dvec3(0.0, 0.25, 0.5));
}

TEST_CASE("merl: every bin centre above the horizon maps back to its bin") {
  std::size_t above = 0, mismatches = 0;
  std::string first;
  double worstAngle = 0.0;
  for (int i = 0; i < kMerlThetaHBins; ++i)
    for (int j = 0; j < kMerlThetaDBins; ++j)
      for (int k = 0; k < kMerlPhiDBins; ++k) {
        const DirectionPair p = merlBinCenter(i, j, k);
        if (!(p.wi.z > 0.0 && p.wo.z > 0.0)) continue;
        ++above;
        const MerlAngles a = merlAngles(p.wi, p.wo);
        const glm::ivec3 bin = merlBin(a);
        // The angles themselves, against the definition of the centre.
        const double u = (i + 0.5) / 90.0;
        worstAngle = std::max({worstAngle, std::abs(a.thetaH - u * u * kPi / 2.0),
                               std::abs(a.thetaD - (j + 0.5) / 90.0 * kPi / 2.0),
                               std::abs(a.phiD - (k + 0.5) / 180.0 * kPi)});
        if (bin != glm::ivec3(i, j, k)) {
          if (mismatches++ == 0) first = ivec3Text({i, j, k}) + " -> " + ivec3Text(bin);
        }
      }
  INFO("first mismatch: " << first);
  CHECK(mismatches == 0);
  CHECK(worstAngle < 1e-9);
  // About 3/4 of the bins have both directions above the horizon (theta_h + theta_d < pi/2 covers much).
  CHECK(above > kMerlBins / 2);
  CHECK(above < kMerlBins);
}

TEST_CASE("merl: evalMerl is reciprocal") {
  const MerlBrdf brdf = distinctMaterial();
  Points points(42);
  std::size_t asymmetric = 0, notABin = 0;
  for (int n = 0; n < 200000; ++n) {
    const glm::dvec3 wi = upperDirection(points), wo = upperDirection(points);
    const glm::dvec3 f = evalMerl(brdf, wi, wo);
    // The value is one bin's, channel by channel, and the bin is the one merlBin names.
    const std::size_t bin = std::size_t(f.x);
    const glm::ivec3 b = merlBin(merlAngles(wi, wo));
    notABin += f != glm::dvec3(distinctValue(bin, 0), distinctValue(bin, 1), distinctValue(bin, 2)) ||
               bin != merlBinIndex(b.x, b.y, b.z);
    asymmetric += evalMerl(brdf, wo, wi) != f;
  }
  CHECK(notABin == 0);
  CHECK(asymmetric == 0);
}

TEST_CASE("merl: evalMerl is isotropic (both directions rotated about the normal)") {
  const MerlBrdf brdf = distinctMaterial();
  Points points(7);
  std::size_t tried = 0, wrong = 0;
  while (tried < 50000) {
    const int i = std::min(int(points.next() * 90), 89), j = std::min(int(points.next() * 90), 89),
              k = std::min(int(points.next() * 180), 179);
    const DirectionPair p = merlBinCenter(i, j, k);
    if (!(p.wi.z > 0.0 && p.wo.z > 0.0)) continue;
    ++tried;
    const double phi = 2.0 * kPi * points.next();
    const glm::dvec3 f = evalMerl(brdf, rotateZ(p.wi, phi), rotateZ(p.wo, phi));
    const std::size_t bin = merlBinIndex(i, j, k);
    wrong += f != glm::dvec3(distinctValue(bin, 0), distinctValue(bin, 1), distinctValue(bin, 2));
  }
  CHECK(wrong == 0);
}

TEST_CASE("merl: a finite value beyond 1e15 is refused naming the file and the bin") {
  ScratchDir dir;
  std::vector<unsigned char> bytes = goodFileBytes();
  const double huge = 3e38;
  std::memcpy(bytes.data() + 12 + 8 * 5, &huge, 8);  // bin 5 of the red channel (little-endian host)
  const auto path = dir.file("huge.binary");
  writeBytes(path, bytes);
  const std::string message = errorMessage([&] { loadMerl(path); });
  checkErrorNamesFile(path, message);
  CHECK(contains(message, "bin 5 of channel R holds"));
  CHECK(contains(message, "above the largest BRDF value iblx accepts (1e15)"));
}
