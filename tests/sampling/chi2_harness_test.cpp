// Tests of the shared chi-square harness (tests/support/chi2.h): incomplete gamma, known passes and failures.
#include "tests/support/chi2.h"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 uniformDirection(glm::dvec2 u) {
  const double z = 1.0 - 2.0 * u.y, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u.x;
  return {r * std::cos(phi), z, r * std::sin(phi)};
}

std::vector<glm::dvec3> uniformSphere(std::size_t n, uint64_t seed) {
  std::vector<glm::dvec3> w;
  for (const glm::dvec2 u : iblx::test::uniformPoints(n, seed)) w.push_back(uniformDirection(u));
  return w;
}

// A batched pdf from a per-direction function.
template <typename F>
iblx::test::BatchPdf batched(F f) {
  return [f](std::span<const glm::dvec3> ws) {
    std::vector<double> p;
    p.reserve(ws.size());
    for (const glm::dvec3& w : ws) p.push_back(f(w));
    return p;
  };
}

// Regularised P(a, x) by the trapezoid rule on t^(a-1) e^-t / Gamma(a), for a >= 1.
double numericGammaP(double a, double x) {
  const int n = 200000;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = x * i / n, f = std::exp((a - 1.0) * std::log(std::max(t, 1e-300)) - t - std::lgamma(a));
    sum += (i == 0 || i == n) ? 0.5 * f : f;
  }
  return sum * x / n;
}

}  // namespace

using namespace iblx::test;

TEST_CASE("chi2: regularised incomplete gamma") {
  for (const double x : {0.1, 1.0, 2.5, 7.0, 30.0}) {
    CHECK(regularizedGammaQ(1.0, x) == doctest::Approx(std::exp(-x)).epsilon(1e-12));
    CHECK(regularizedGammaQ(0.5, x) == doctest::Approx(std::erfc(std::sqrt(x))).epsilon(1e-10));
  }
  CHECK(regularizedGammaQ(3.0, 2.0) == doctest::Approx(5.0 * std::exp(-2.0)).epsilon(1e-12));
  CHECK(regularizedGammaP(2.0, 0.0) == 0.0);
  // Small P keeps its relative precision: P(1, x) = 1 - e^-x = -expm1(-x).
  CHECK(regularizedGammaP(1.0, 1e-12) == doctest::Approx(-std::expm1(-1e-12)).epsilon(1e-12));
  // Both branches (series for x < a + 1, continued fraction beyond) against quadrature.
  for (const double x : {1.7, 6.0})
    CHECK(regularizedGammaP(2.5, x) == doctest::Approx(numericGammaP(2.5, x)).epsilon(1e-7));
  // Chi-square tails: Q(5, 5) = e^-5 (1 + 5 + 25/2 + 125/6 + 625/24); the 5 % point of one dof is 3.841.
  CHECK(chi2PValue(10.0, 10) == doctest::Approx(std::exp(-5.0) * (1 + 5 + 12.5 + 125.0 / 6 + 625.0 / 24)));
  CHECK(chi2PValue(3.841458820694124, 1) == doctest::Approx(0.05).epsilon(1e-9));
  CHECK(chi2PValue(1000.0, 1000) == doctest::Approx(0.4940).epsilon(1e-3));
}

TEST_CASE("chi2: uniform sphere passes and its pdf integrates to 1") {
  const auto samples = uniformSphere(100000, 1);
  const Chi2Result r = chi2Test(samples, batched([](glm::dvec3) { return 1.0 / (4.0 * kPi); }));
  INFO(r.message);
  CHECK(r.passed);
  CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(r.degreesOfFreedom == 51 * 25 - 1);
}

TEST_CASE("chi2: a wrong pdf fails and dumps its tables") {
  const auto samples = uniformSphere(100000, 2);
  Chi2Options o;
  o.label = "harness-self-test-wrong-pdf";
  const Chi2Result r =
      chi2Test(samples, batched([](glm::dvec3 w) { return (1.0 + 0.3 * w.y) / (4.0 * kPi); }), o);
  CHECK_FALSE(r.passed);
  CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-6));
  const auto at = r.message.find("tables in ");
  REQUIRE(at != std::string::npos);
  const std::filesystem::path table = r.message.substr(at + 10);
  CHECK(std::filesystem::exists(table));
  std::filesystem::remove(table);
}

TEST_CASE("chi2: a sample where the pdf is zero fails outright") {
  const auto samples = uniformSphere(20000, 3);
  Chi2Options o;
  o.label = "harness-self-test-zero-cell";
  const Chi2Result r =
      chi2Test(samples, batched([](glm::dvec3 w) { return w.y > 0.0 ? 1.0 / (2.0 * kPi) : 0.0; }), o);
  CHECK_FALSE(r.passed);
  CHECK(r.message.find("expected count is 0") != std::string::npos);
  std::filesystem::remove(r.message.substr(r.message.find("tables in ") + 10));
}

TEST_CASE("chi2: adaptive refinement integrates a sharp-edged pdf") {
  // Uniform on a (phi, cos(theta)) box whose edges cut sub-cells away from their midpoints: the plain
  // midpoint rule overestimates its mass by ~2 %, the refined rule does not.
  const double s = 2.0 * kPi / (51 * 4), phi0 = 32.2 * s, phi1 = 48.8 * s, z0 = -1 + 55.2 * 0.02,
               z1 = -1 + 72.25 * 0.02;
  const double density = 1.0 / ((phi1 - phi0) * (z1 - z0));
  std::vector<glm::dvec3> samples;
  for (const glm::dvec2 u : uniformPoints(100000, 4)) {
    const double phi = phi0 + u.x * (phi1 - phi0), z = z0 + u.y * (z1 - z0), r = std::sqrt(1.0 - z * z);
    samples.push_back({r * std::cos(phi), z, r * std::sin(phi)});
  }
  const auto pdf = batched([&](glm::dvec3 w) {
    double phi = std::atan2(w.z, w.x);
    if (phi < 0.0) phi += 2.0 * kPi;
    return (phi >= phi0 && phi < phi1 && w.y >= z0 && w.y < z1) ? density : 0.0;
  });
  Chi2Options o;
  o.label = "harness-self-test-box";
  const Chi2Result refined = chi2Test(samples, pdf, o);
  INFO(refined.message);
  CHECK(refined.passed);
  CHECK(refined.pdfIntegral == doctest::Approx(1.0).epsilon(1e-4));
  o.maxRefineDepth = 0;
  const Chi2Result plain = chi2Test(samples, pdf, o);
  CHECK_FALSE(plain.passed);
  CHECK(plain.pdfIntegral == doctest::Approx(1.02).epsilon(0.01));
  std::filesystem::remove(plain.message.substr(plain.message.find("tables in ") + 10));
}
