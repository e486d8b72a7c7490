// ALTA's parametrisations (engine/io/alta_params.h): every name ALTA writes, the forward maps against ALTA's
// own test values and closed forms, and the inverses against the forward maps on random direction pairs.
#include "engine/io/alta_params.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

using namespace iblx;

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The coordinates that are azimuths or differences of azimuths: compared modulo a whole turn.
bool isAngle(AltaParam p, int k) {
  switch (p) {
    case AltaParam::RusinThPhTdPd:
    case AltaParam::SphericalTlPlTvPv:
      return k == 1 || k == 3;
    case AltaParam::RusinThTdPd:
    case AltaParam::IsotropicTvTlDphi:
    case AltaParam::Stark3d:
    case AltaParam::Neumann3d:
      return k == 2;
    default:
      return false;
  }
}

double difference(AltaParam p, int k, double a, double b) {
  double d = a - b;
  if (isAngle(p, k)) d = std::remainder(d, 2.0 * kPi);
  return std::abs(d);
}

}  // namespace

TEST_CASE("alta params: every name ALTA writes is read, with its dimension") {
  std::set<std::string> names;
  for (AltaParam p : altaParams()) {
    CAPTURE(altaParamName(p));
    CHECK(names.insert(altaParamName(p)).second);
    CHECK(findAltaParam(altaParamName(p)) == p);
    CHECK(altaParamDimension(p) >= 1);
    CHECK(altaParamDimension(p) <= 6);
  }
  CHECK(names.size() == 22);
  // ALTA writes its SCHLICK_VK as SCHLICK_VH; the enum's name is read too.
  CHECK(findAltaParam("SCHLICK_VH") == AltaParam::SchlickVk);
  CHECK(findAltaParam("SCHLICK_VK") == AltaParam::SchlickVk);
  CHECK_FALSE(findAltaParam("RUSIN_TH_PH_TD").has_value());  // documented by ALTA, not read by it
  CHECK(altaParamDimension(AltaParam::Stereographic) == 4);
  CHECK(altaParamDimension(AltaParam::CosTk) == 1);
  CHECK(altaParamDimension(AltaParam::IsotropicTlTvProjDphi) == 3);
}

TEST_CASE("alta params: forward maps agree with ALTA's own test values and with closed forms") {
  // ALTA's half-vector tests: V = (1, 0, 0), L = (0, 1, 0) gives theta_h = pi/2, phi_h = pi/4, theta_d =
  // pi/4 and phi_d = -pi/2 from the view; from the light (Rusinkiewicz's difference vector, here) phi_d is
  // +pi/2.
  const auto k = altaRawCoordinates(AltaParam::RusinThPhTdPd, {0, 1, 0}, {1, 0, 0});
  CHECK(k[0] == doctest::Approx(kPi / 2));
  CHECK(k[1] == doctest::Approx(kPi / 4));
  CHECK(k[2] == doctest::Approx(kPi / 4));
  CHECK(k[3] == doctest::Approx(kPi / 2));
  // A mirror pair about the normal: theta_h = 0, theta_d = theta.
  const double theta = 0.7;
  const auto m = altaRawCoordinates(AltaParam::RusinThTdPd, direction(theta, kPi), direction(theta, 0.0));
  CHECK(m[0] == doctest::Approx(0.0).epsilon(1e-9));
  CHECK(m[1] == doctest::Approx(theta));

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 wi = direction(std::acos(0.05 + 0.95 * u(rng)), 2.0 * kPi * u(rng));
    const glm::dvec3 wo = direction(std::acos(0.05 + 0.95 * u(rng)), 2.0 * kPi * u(rng));
    const auto rusin = altaRawCoordinates(AltaParam::RusinThTdPd, wi, wo);
    // Stark's coordinates from Rusinkiewicz's: |B~| = sin theta_d, |H~_p| = cos theta_d sin theta_h.
    const auto stark = altaRawCoordinates(AltaParam::Stark2d, wi, wo);
    CHECK(stark[1] == doctest::Approx(std::sin(rusin[1])).epsilon(1e-9));
    CHECK(stark[0] == doctest::Approx(std::cos(rusin[1]) * std::sin(rusin[0])).epsilon(1e-9));
    CHECK(altaRawCoordinates(AltaParam::CosTlv, wi, wo)[0] == doctest::Approx(glm::dot(wi, wo)));
    CHECK(altaRawCoordinates(AltaParam::CosTh, wi, wo)[0] == doctest::Approx(std::cos(rusin[0])));
    // The projected azimuth difference: (theta_V cos D, theta_V sin D) with D = phi_L - phi_V.
    const auto proj = altaRawCoordinates(AltaParam::IsotropicTlTvProjDphi, wi, wo);
    const auto iso = altaRawCoordinates(AltaParam::IsotropicTvTlDphi, wi, wo);
    CHECK(proj[0] == doctest::Approx(iso[1]));
    CHECK(std::hypot(proj[1], proj[2]) == doctest::Approx(iso[0]));
    CHECK(std::remainder(std::atan2(proj[2], proj[1]) - iso[2], 2.0 * kPi) ==
          doctest::Approx(0.0).epsilon(1e-9));
    // The stereographic projection of each direction.
    const auto stereo = altaRawCoordinates(AltaParam::Stereographic, wi, wo);
    CHECK(stereo[0] == doctest::Approx(wo.x / (1.0 + wo.z)));
    CHECK(stereo[3] == doctest::Approx(wi.y / (1.0 + wi.z)));
    // RETRO: theta_VL is the angle between V and L.
    const auto retro = altaRawCoordinates(AltaParam::RetroTlTvlProjDphi, wi, wo);
    CHECK(std::hypot(retro[1], retro[2]) == doctest::Approx(std::acos(glm::dot(wi, wo))).epsilon(1e-9));
  }
  // Retro-reflection (V = L) is the origin of RETRO's projected plane.
  const auto retro =
      altaRawCoordinates(AltaParam::RetroTlTvlProjDphi, direction(0.4, 1.0), direction(0.4, 1.0));
  CHECK(retro[0] == doctest::Approx(0.4));
  CHECK(std::abs(retro[1]) < 1e-6);
  CHECK(std::abs(retro[2]) < 1e-6);
}

TEST_CASE("alta params: each inverse gives a direction pair with the coordinates it was given") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (AltaParam p : altaParams()) {
    CAPTURE(altaParamName(p));
    const int dims = altaParamDimension(p);
    double worst = 0.0;
    for (int i = 0; i < 500; ++i) {
      const glm::dvec3 wi = direction(std::acos(0.05 + 0.9 * u(rng)), 2.0 * kPi * u(rng));
      const glm::dvec3 wo = direction(std::acos(0.05 + 0.9 * u(rng)), 2.0 * kPi * u(rng));
      const auto x = altaRawCoordinates(p, wi, wo);
      const auto pair = altaDirections(p, std::span(x).first(std::size_t(dims)));
      REQUIRE(pair.has_value());
      CHECK(glm::length(pair->first) == doctest::Approx(1.0));
      CHECK(glm::length(pair->second) == doctest::Approx(1.0));
      const auto back = altaRawCoordinates(p, pair->first, pair->second);
      for (int k = 0; k < dims; ++k)
        worst = std::max(worst, difference(p, k, back[std::size_t(k)], x[std::size_t(k)]));
    }
    CHECK(worst < 1e-9);
  }
  // Coordinates no direction pair has.
  CHECK_FALSE(altaDirections(AltaParam::Stark2d, std::vector<double>{0.9, 0.9}).has_value());
  CHECK_FALSE(altaDirections(AltaParam::Neumann3d, std::vector<double>{0.9, 0.5, 0.0}).has_value());
}
