// Tests of the docs/DESIGN.md §3 conventions in engine/core/sphere_mapping.h and the texel warp in
// latlong_texel.h.
#include "engine/io/latlong_texel.h"
#include "engine/core/sphere_mapping.h"
#include "tests/support/chi2.h"

#include <doctest/doctest.h>

#include <cmath>
#include <utility>

using namespace iblx;

namespace {

// Uniform direction on the sphere from u in [0,1)^2 (z = cos(theta) uniform, Archimedes).
glm::dvec3 uniformDirection(glm::dvec2 u) {
  const double z = 1.0 - 2.0 * u.y, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u.x;
  return {r * std::cos(phi), z, r * std::sin(phi)};
}

}  // namespace

TEST_CASE("sphere_mapping: lat-long axes follow docs/DESIGN.md §3") {
  // v = 0 is +Y (top row), v = 1/2 the horizon; u = 0 is +X, u = 1/4 is +Z.
  CHECK(glm::length(latLongToDirection({0.0, 0.0}) - glm::dvec3(0, 1, 0)) < 1e-12);
  CHECK(glm::length(latLongToDirection({0.0, 0.5}) - glm::dvec3(1, 0, 0)) < 1e-12);
  CHECK(glm::length(latLongToDirection({0.25, 0.5}) - glm::dvec3(0, 0, 1)) < 1e-12);
  CHECK(glm::length(latLongToDirection({0.5, 1.0}) - glm::dvec3(0, -1, 0)) < 1e-12);
}

TEST_CASE("sphere_mapping: direction <-> lat-long round trip") {
  for (const glm::dvec2 u : test::uniformPoints(10000, 1)) {
    const glm::dvec3 w = uniformDirection(u);
    const glm::dvec2 uv = directionToLatLong(w);
    REQUIRE(uv.x >= 0.0);
    REQUIRE(uv.x < 1.0);
    REQUIRE(uv.y >= 0.0);
    REQUIRE(uv.y <= 1.0);
    CHECK(glm::length(latLongToDirection(uv) - w) < 1e-12);
    // And the other way, away from the poles where u is undefined.
    if (uv.y > 1e-6 && uv.y < 1.0 - 1e-6) {
      const glm::dvec2 back = directionToLatLong(latLongToDirection(uv));
      CHECK(std::abs(back.y - uv.y) < 1e-12);
      CHECK(std::min(std::abs(back.x - uv.x), 1.0 - std::abs(back.x - uv.x)) < 1e-9);
    }
  }
}

TEST_CASE("sphere_mapping: texel solid angles sum to 4 pi") {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{7, 1}, std::pair{4, 2}, std::pair{50, 25},
                             std::pair{64, 32}, std::pair{8192, 4096}}) {
    CAPTURE(w);
    CAPTURE(h);
    double sum = 0.0;
    for (int y = 0; y < h; ++y) {
      const double omega = latLongTexelSolidAngle(y, w, h);
      CHECK(omega > 0.0);
      // The exact integral 2 pi / W (cos(theta0) - cos(theta1)).
      const double direct = 2.0 * kPi / w * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
      CHECK(std::abs(omega - direct) <= 1e-12 * omega + 1e-15);
      sum += w * omega;
    }
    CHECK(sum == doctest::Approx(4.0 * kPi).epsilon(1e-12));
    const std::vector<float> rows = rowSolidAngles(w, h);
    REQUIRE(rows.size() == std::size_t(h));
    CHECK(rows[0] == float(latLongTexelSolidAngle(0, w, h)));
  }
  // One row is the whole sphere divided by W.
  CHECK(latLongTexelSolidAngle(0, 8, 1) == doctest::Approx(4.0 * kPi / 8.0).epsilon(1e-14));
}

TEST_CASE("sphere_mapping: cos(a) - cos(b) without cancellation, in angles and in v") {
  for (const auto& [a, b] :
       {std::pair{0.0, kPi}, std::pair{0.3, 1.9}, std::pair{2.0, 0.5}, std::pair{1.0, 1.0}}) {
    CHECK(cosDifference(a, b) == doctest::Approx(std::cos(a) - std::cos(b)).epsilon(1e-14).scale(1e-15));
    CHECK(cosDifferenceOfV(a / kPi, b / kPi) ==
          doctest::Approx(cosDifference(a, b)).epsilon(1e-14).scale(1e-15));
  }
  // A band one 8192-row texel wide at the pole: the plain difference keeps about half the digits.
  const double a = 1e-4, b = a + kPi / 8192.0;
  const long double la = a, lb = b;
  const double exact = double(2.0L * std::sin(0.5L * (la + lb)) * std::sin(0.5L * (lb - la)));
  CHECK(std::abs(cosDifference(a, b) - exact) <= 1e-14 * exact);
  CHECK(std::abs((std::cos(a) - std::cos(b)) - exact) > 1e-12 * exact);
}

TEST_CASE("sphere_mapping: camera pixels and sphere normals") {
  // Odd square image: the centre pixel sees the sphere head-on.
  const auto centre = sphereNormalAt(pixelToImagePlane(32, 32, 65, 65));
  REQUIRE(centre);
  CHECK(glm::length(*centre - glm::dvec3(0, 0, 1)) < 1e-12);
  // Even image: the four central pixels are within half a pixel of +Z.
  const auto nearCentre = sphereNormalAt(pixelToImagePlane(31, 31, 64, 64));
  REQUIRE(nearCentre);
  CHECK(nearCentre->z > 0.999);
  CHECK(nearCentre->x < 0.0);  // left of centre
  CHECK(nearCentre->y > 0.0);  // j = 0 is the top row, so row 31 is above centre
  // Corners are background; every sphere pixel has a unit normal facing the camera.
  for (const auto& [w, h] : {std::pair{64, 64}, std::pair{65, 33}, std::pair{128, 64}}) {
    CHECK_FALSE(sphereNormalAt(pixelToImagePlane(0, 0, w, h)));
    CHECK_FALSE(sphereNormalAt(pixelToImagePlane(w - 1, 0, w, h)));
    CHECK_FALSE(sphereNormalAt(pixelToImagePlane(0, h - 1, w, h)));
    CHECK_FALSE(sphereNormalAt(pixelToImagePlane(w - 1, h - 1, w, h)));
    int hits = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const CameraRay p = pixelToImagePlane(i, j, w, h);
        CHECK(std::abs(p.y) < 1.0);
        CHECK(std::abs(p.x) < double(w) / h);
        if (const auto n = sphereNormalAt(p)) {
          ++hits;
          CHECK(std::abs(glm::length(*n) - 1.0) < 1e-12);
          CHECK(n->z >= 0.0);
        }
      }
    // The sphere covers pi/4 of the square [-1,1]^2 at the centre of the image.
    CHECK(double(hits) / (h * h) == doctest::Approx(kPi / 4.0).epsilon(0.05));
  }
  // A wide image: x is scaled by W/H, so the left and right quarters are background.
  CHECK_FALSE(sphereNormalAt(pixelToImagePlane(10, 32, 128, 64)));
}

TEST_CASE("sphere_mapping: worldToEnv is a rotation about +Y") {
  for (const glm::dvec2 u : test::uniformPoints(1000, 2)) {
    const glm::dvec3 a = uniformDirection(u), b = uniformDirection({u.y, u.x});
    for (const double degrees : {0.0, 37.0, 90.0, -123.0}) {
      const glm::dvec3 ra = worldToEnv(a, degrees), rb = worldToEnv(b, degrees);
      CHECK(glm::length(ra) == doctest::Approx(1.0).epsilon(1e-12));
      CHECK(ra.y == doctest::Approx(a.y).epsilon(1e-12));  // about +Y
      // Proper rotation: preserves dot and cross products, and the inverse is the opposite angle.
      CHECK(glm::dot(ra, rb) == doctest::Approx(glm::dot(a, b)).epsilon(1e-12));
      CHECK(glm::length(glm::cross(ra, rb) - worldToEnv(glm::cross(a, b), degrees)) < 1e-12);
      CHECK(glm::length(worldToEnv(ra, -degrees) - a) < 1e-12);
    }
  }
  // 90 degrees: the map's phi = 0 feature (+X) is seen in the world at phi = 90 degrees (+Z), i.e. features
  // move towards increasing phi; the world's +X looks up the map at phi = 270 degrees (-Z).
  CHECK(glm::length(worldToEnv({0, 0, 1}, 90.0) - glm::dvec3(1, 0, 0)) < 1e-12);
  CHECK(glm::length(worldToEnv({1, 0, 0}, 90.0) - glm::dvec3(0, 0, -1)) < 1e-12);
  CHECK(directionToLatLong(worldToEnv({1, 0, 0}, 90.0)).x == doctest::Approx(0.75));
}

TEST_CASE("sphere_mapping: texel warp is uniform in phi and cos(theta) and invertible") {
  const int w = 50, h = 25;
  for (const glm::dvec2 u : test::uniformPoints(2000, 3)) {
    const glm::ivec2 texel(int(u.x * w), int(u.y * h));
    const glm::dvec2 t = glm::fract(u * 97.0);
    const glm::dvec3 d = texelToDirection(texel.x, texel.y, t, w, h);
    CHECK(std::abs(glm::length(d) - 1.0) < 1e-12);
    // phi and cos(theta) are affine in t.
    const double cos0 = std::cos(kPi * texel.y / h), cos1 = std::cos(kPi * (texel.y + 1) / h);
    CHECK(d.y == doctest::Approx(cos0 + t.y * (cos1 - cos0)).epsilon(1e-12));
    CHECK(directionToLatLong(d).x * w == doctest::Approx(texel.x + t.x).epsilon(1e-12));
    if (t.x > 1e-9 && t.x < 1 - 1e-9 && t.y > 1e-9 && t.y < 1 - 1e-9) {
      CHECK(directionToTexel(d, w, h) == texel);
      const glm::dvec2 back = directionToTexelOffset(d, texel, w, h);
      CHECK(std::abs(back.x - t.x) < 1e-9);
      CHECK(std::abs(back.y - t.y) < 1e-9);
    }
  }
  // Corners of the map stay inside it.
  CHECK(directionToTexel({0, 1, 0}, w, h) == glm::ivec2(0, 0));
  CHECK(directionToTexel({0, -1, 0}, w, h) == glm::ivec2(0, h - 1));
  // A phi that rounds up to 2 pi stays in the last column, as on the GPU (regression: the CPU used to wrap it
  // to column 0, so CPU twins and GPU disagreed on the pdf there).
  CHECK(directionToTexel({1, 0, -1e-17}, w, h).x == w - 1);
  // The last column wraps to phi = 2 pi: t.x close to 1 in column W-1.
  const glm::dvec3 seam = texelToDirection(w - 1, 3, {1.0 - 1e-12, 0.5}, w, h);
  CHECK(directionToTexelOffset(seam, {w - 1, 3}, w, h).x > 0.99);
}
