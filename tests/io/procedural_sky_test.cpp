// Tests of the default procedural sky: valid radiance, the sun where docs/DESIGN.md §3 says it is and as bright as
// the hard case needs, ground darker than sky, determinism.
#include "engine/io/procedural_sky.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace iblx;

namespace {

std::vector<double> weights(const EnvImage& image) {
  std::vector<double> w;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) w.push_back(image.weight(x, y));
  return w;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST_CASE("makeProceduralSky: default map is finite, non-negative, 256x128") {
  const EnvImage sky = makeProceduralSky();
  CHECK(sky.width == 256);
  CHECK(sky.height == 128);
  REQUIRE(sky.rgb.size() == 3 * sky.texelCount());
  for (float v : sky.rgb) REQUIRE((std::isfinite(v) && v >= 0.0f));
}

TEST_CASE("makeProceduralSky: the sun is where its options put it, >= 1e3 x the median texel") {
  const ProceduralSkyOptions options;
  const EnvImage sky = makeProceduralSky(options);
  // Sun direction by docs/DESIGN.md §3: elevation e, azimuth a -> theta = 90 - e, phi = a.
  const double degree = kPi / 180.0;
  const glm::dvec3 sunDirection =
      latLongToDirection({options.sunAzimuthDegrees / 360.0, (90.0 - options.sunElevationDegrees) / 180.0});
  CHECK(sunDirection.y == doctest::Approx(std::sin(options.sunElevationDegrees * degree)));
  const glm::dvec2 uv = directionToLatLong(sunDirection);
  const int sunX = int(uv.x * sky.width), sunY = int(uv.y * sky.height);

  const std::vector<double> w = weights(sky);
  const auto brightest = std::max_element(w.begin(), w.end()) - w.begin();
  CHECK(brightest % sky.width == sunX);
  CHECK(brightest / sky.width == sunY);
  const double med = median(w);
  CHECK(med > 0.2);
  CHECK(sky.weight(sunX, sunY) >= 1.0e3 * med);
  // The default sun is fully inside its texel's neighbourhood: about sunRadiance there, ~1e4 x the sky.
  CHECK(sky.weight(sunX, sunY) == doctest::Approx(options.sunRadiance).epsilon(0.05));
}

TEST_CASE("makeProceduralSky: anti-aliased sun carries the energy of the disc") {
  // Sum over texels of weight x exact texel solid angle, sky without sun subtracted, equals the sun's
  // radiance times the solid angle of its disc, 2 pi (1 - cos r): supersampling weighted by sin(theta) makes
  // it so.
  ProceduralSkyOptions options;
  options.glowRadiance = 0.0;
  const EnvImage withSun = makeProceduralSky(options);
  options.sunRadiance = 0.0;
  const EnvImage withoutSun = makeProceduralSky(options);
  double energy = 0.0;
  int partial = 0;
  for (int y = 0; y < withSun.height; ++y)
    for (int x = 0; x < withSun.width; ++x) {
      const double sun = withSun.weight(x, y) - withoutSun.weight(x, y);
      energy += sun * latLongTexelSolidAngle(y, withSun.width, withSun.height);
      if (sun > 0.01 * ProceduralSkyOptions{}.sunRadiance && sun < 0.99 * ProceduralSkyOptions{}.sunRadiance)
        ++partial;
    }
  const double radius = options.sunAngularRadiusDegrees * kPi / 180.0;
  const double expected = ProceduralSkyOptions{}.sunRadiance * 2.0 * kPi * (1.0 - std::cos(radius));
  CHECK(energy == doctest::Approx(expected).epsilon(0.03));
  CHECK(partial >= 4);  // the edge is spread over several partially covered texels
}

TEST_CASE("makeProceduralSky: ground is darker than sky, sky brighter near the horizon") {
  ProceduralSkyOptions options;
  options.sunRadiance = 0.0;
  options.glowRadiance = 0.0;
  const EnvImage sky = makeProceduralSky(options);
  double darkestSky = 1e30, brightestSky = 0.0, brightestGround = 0.0, darkestGround = 1e30;
  for (int y = 0; y < sky.height; ++y) {
    const double elevation = 90.0 - 180.0 * (y + 0.5) / sky.height;
    for (int x = 0; x < sky.width; ++x) {
      const double w = sky.weight(x, y);
      if (elevation > 3.0) {
        darkestSky = std::min(darkestSky, w);
        brightestSky = std::max(brightestSky, w);
      } else if (elevation < -3.0) {
        brightestGround = std::max(brightestGround, w);
        darkestGround = std::min(darkestGround, w);
      }
    }
  }
  CHECK(brightestGround < darkestSky);
  CHECK(darkestSky > 0.3);
  CHECK(brightestSky < 1.5);
  CHECK(darkestGround > 0.04);
  CHECK(brightestGround < 0.2);
  CHECK(sky.weight(0, sky.height / 2 - 2) > sky.weight(0, 0));  // horizon brighter than zenith
}

TEST_CASE("makeProceduralSky: deterministic, sun below the horizon hidden, invalid options rejected") {
  ProceduralSkyOptions options;
  options.width = 64;
  options.height = 32;
  const EnvImage a = makeProceduralSky(options), b = makeProceduralSky(options);
  REQUIRE(a.rgb.size() == b.rgb.size());
  CHECK(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0);

  options.sunElevationDegrees = -30.0;
  const std::vector<double> w = weights(makeProceduralSky(options));
  CHECK(*std::max_element(w.begin(), w.end()) < 2.0);

  ProceduralSkyOptions bad;
  bad.width = 1;
  CHECK_THROWS_AS(makeProceduralSky(bad), Error);
  bad = {};
  bad.sunAngularRadiusDegrees = 0.0;
  CHECK_THROWS_AS(makeProceduralSky(bad), Error);
  bad = {};
  bad.sunRadiance = -1.0;
  CHECK_THROWS_AS(makeProceduralSky(bad), Error);
}
