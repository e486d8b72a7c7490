// Tests of the MIT CSAIL .dat reader, writer and reference lookup (engine/io/mit_brdf.h): the header's fields
// and the size they imply, unmeasured bins zeroed with a count, every class of bad file with its message, and
// the nearest-bin lookup at bin centres, with and without half data.
#include "engine/io/mit_brdf.h"

#include "engine/core/error.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cstring>
#include <limits>

using namespace iblx;
using namespace iblx::test;

namespace {

const MitDims kDims{4, 5, 6, 8, false};

std::vector<float> distinctValues(const MitDims& dims) {
  std::vector<float> values(3 * dims.bins());
  for (std::size_t k = 0; k < values.size(); ++k) values[k] = float(k + 1) * 1e-3f;
  return values;
}

// The file's bytes with header field `field` replaced.
std::vector<unsigned char> withField(std::vector<unsigned char> bytes, int field, std::int32_t value) {
  std::memcpy(bytes.data() + 4 * field, &value, 4);
  return bytes;
}

}  // namespace

TEST_CASE("mit .dat: the layout round-trips; unmeasured bins become 0 in every channel and are counted") {
  ScratchDir dir;
  std::vector<float> values = distinctValues(kDims);
  values[kDims.bins() + 3] = -1.0f;  // bin 3's green: the whole bin is unmeasured
  const auto path = dir.file("material.dat");
  writeMitBrdf(path, kDims, values);
  CHECK(std::filesystem::file_size(path) == 64 + 12 * kDims.bins());
  CHECK(looksLikeMitBrdf(path));
  const MitBrdf brdf = loadMitBrdf(path);
  CHECK(brdf.dims.thetaIn == 4);
  CHECK(brdf.dims.phiIn == 8);
  CHECK(brdf.unmeasuredBins == 1);
  for (int c = 0; c < 3; ++c) CHECK(brdf.rgb[std::size_t(c) * kDims.bins() + 3] == 0.0f);
  CHECK(brdf.rgb[4] == values[4]);
}

TEST_CASE("mit .dat: bad headers and sizes are refused naming the field or both sizes") {
  ScratchDir dir;
  const auto good = dir.file("good.dat");
  writeMitBrdf(good, kDims, distinctValues(kDims));
  const std::vector<unsigned char> bytes = readBytes(good);
  const auto check = [&](const std::string& name, const std::vector<unsigned char>& content,
                         const std::string& expected) {
    const auto path = dir.file(name);
    writeBytes(path, content);
    CHECK_FALSE(looksLikeMitBrdf(path));
    const std::string message = errorMessage([&] { loadMitBrdf(path); });
    INFO(message);
    CHECK(contains(message, name));
    CHECK(contains(message, expected));
  };
  check("param.dat", withField(bytes, 6, 2), "header field 6 (parameterisation) is 2, expected 1");
  check("binning.dat", withField(bytes, 7, 1), "header field 7 (binning) is 1");
  check("channels.dat", withField(bytes, 10, 1), "header field 10 (channels) is 1, expected 3");
  check("zero.dat", withField(bytes, 2, 0), "phi_diff has 0 bins");
  check("huge.dat", withField(bytes, 0, 1 << 30), "theta_in has 1073741824 bins");
  check("short.dat", std::vector<unsigned char>(bytes.begin(), bytes.end() - 4), "truncated MIT .dat file");
  check("header.dat", std::vector<unsigned char>(bytes.begin(), bytes.begin() + 20),
        "shorter than its 64-byte header");
  std::vector<float> values = distinctValues(kDims);
  values[7] = std::numeric_limits<float>::infinity();
  const auto inf = dir.file("inf.dat");
  writeMitBrdf(inf, kDims, values);
  CHECK(contains(errorMessage([&] { loadMitBrdf(inf); }),
                 "inf.dat: bin 7 of channel R is not a finite number"));
}

TEST_CASE("mit .dat: the lookup takes the bin of each angle, and folds phi_diff for half data") {
  for (const bool half : {false, true}) {
    CAPTURE(half);
    const MitDims dims{3, 4, 6, 5, half};
    MitBrdf brdf;
    brdf.dims = dims;
    brdf.rgb = distinctValues(dims);
    for (int ti = 0; ti < dims.thetaIn; ++ti)
      for (int to = 0; to < dims.thetaOut; ++to)
        for (int pd = 0; pd < dims.phiDiff; ++pd)
          for (int pi = 0; pi < dims.phiIn; ++pi) {
            const MitDirectionPair pair = mitBinCenter(dims, ti, to, pd, pi);
            const std::size_t index = dims.index(ti, to, pd, pi);
            const glm::dvec3 f = evalMitBrdf(brdf, pair.wi, pair.wo, 2.0);
            REQUIRE(f.x == doctest::Approx(2.0 * brdf.rgb[index]));
            REQUIRE(f.z == doctest::Approx(2.0 * brdf.rgb[2 * dims.bins() + index]));
          }
    if (half) {  // phi_diff and 2 pi - phi_diff are the same bin
      const MitDirectionPair a = mitBinCenter(dims, 1, 2, 1, 3);
      const glm::dvec3 mirrored{a.wo.x, a.wo.y, a.wo.z};
      const double phiIn = std::atan2(a.wi.y, a.wi.x);
      const double phiOut = std::atan2(a.wo.y, a.wo.x);
      const double m = 2.0 * phiIn - phiOut;  // the view mirrored about the plane of incidence
      const double s = std::hypot(mirrored.x, mirrored.y);
      CHECK(evalMitBrdf(brdf, a.wi, {s * std::cos(m), s * std::sin(m), mirrored.z}) ==
            evalMitBrdf(brdf, a.wi, a.wo));
    }
  }
  MitBrdf brdf;
  brdf.dims = kDims;
  brdf.rgb.assign(3 * kDims.bins(), 1.0f);
  CHECK(evalMitBrdf(brdf, {0.0, 0.6, -0.8}, {0.0, 0.0, 1.0}) == glm::dvec3(0.0));
}
