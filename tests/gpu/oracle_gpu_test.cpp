// The oracle's variance (engine/render/oracle.h): the GPU's two sweeps against a CPU twin in double, the
// twin's formula against the oracle actually sampled, and the oracle below what the methods reach.
#include "engine/io/latlong_texel.h"
#include "engine/io/synthetic_envs.h"
#include "engine/render/oracle.h"
#include "engine/render/renderer.h"
#include "engine/render/metrics.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGaussNode = 0.21132486540518713;  // 2-point Gauss-Legendre on [0, 1]

glm::dvec3 texelRadiance(const EnvImage& env, int x, int y) {
  const float* p = &env.rgb[3 * env.index(x, y)];
  return {p[0], p[1], p[2]};
}
double luminance(glm::dvec3 c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

// One pixel's oracle in double, for a Lambert BRDF of albedo `albedo` and 2x2 Gauss points in every texel
// (what the GPU uses with maxFineSubdivisions = 1): the texel weights, and the variance of one sample.
struct PixelOracle {
  std::vector<double> weights;             // w_t, row-major
  std::vector<glm::dvec3> texelIntegrals;  // L_t * integral over t of f cos
  glm::dvec3 mean{0.0}, variance{0.0};
  double total = 0.0;
};
double lambertCos(glm::dvec3 n, glm::dvec3 d, double albedo) {
  return albedo / kPi * std::max(0.0, glm::dot(n, d));
}
PixelOracle pixelOracle(const EnvImage& env, glm::dvec3 n, double albedo) {
  const int W = env.width, H = env.height;
  const std::vector<float> solidAngles = rowSolidAngles(W, H);
  const glm::dvec2 points[4] = {{kGaussNode, kGaussNode},
                                {1 - kGaussNode, kGaussNode},
                                {kGaussNode, 1 - kGaussNode},
                                {1 - kGaussNode, 1 - kGaussNode}};
  PixelOracle o;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double integral = 0.0;
      for (const glm::dvec2 t : points) integral += lambertCos(n, texelToDirection(x, y, t, W, H), albedo);
      integral *= solidAngles[std::size_t(y)] / 4.0;
      const glm::dvec3 contribution = texelRadiance(env, x, y) * integral;
      o.texelIntegrals.push_back(contribution);
      o.weights.push_back(luminance(contribution));
      o.mean += contribution;
      o.total += o.weights.back();
    }
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double w = o.weights[std::size_t(y * W + x)];
      if (!(w > 0.0)) continue;
      const glm::dvec3 c = texelRadiance(env, x, y) * (solidAngles[std::size_t(y)] * o.total / w);
      glm::dvec3 sum(0.0);
      for (const glm::dvec2 t : points) {
        const glm::dvec3 d = c * lambertCos(n, texelToDirection(x, y, t, W, H), albedo) - o.mean;
        sum += d * d;
      }
      o.variance += sum * (w / o.total / 4.0);
    }
  return o;
}

}  // namespace

TEST_CASE("oracle: the GPU's variance per pixel is its CPU twin's, and the twin is the sampled oracle's") {
  const EnvImage env = smoothSky(32, 16);
  const Scene scene = sceneWith(env, "lambert", {{"albedo", "0.7"}}, 12);
  ReferenceOptions options;
  options.maxFineSubdivisions = 1;  // 2x2 Gauss points in every texel, as the twin has them
  const OracleVariance oracle = computeOracleVariance(gpuContext(), gpuCompiler(), scene, options);
  REQUIRE(oracle.variance.size() == 3 * 12 * 12);
  int compared = 0;
  for (std::size_t p = 0; p < scene.gbuffer.pixels.size(); p += 7) {
    const gpu::GPixel& g = scene.gbuffer.pixels[p];
    if (g.normal.w == 0.0f) continue;
    const glm::dvec3 n = glm::normalize(glm::dvec3(g.normal.x, g.normal.y, g.normal.z));
    const PixelOracle twin = pixelOracle(env, n, 0.7);
    for (int c = 0; c < 3; ++c) {
      CAPTURE(p);
      CAPTURE(c);
      CHECK(oracle.mean[3 * p + std::size_t(c)] == doctest::Approx(twin.mean[c]).epsilon(1e-4));
      // The variance is 1e-3 to 1e-2 of the mean squared here: float sums of squares of small differences.
      CHECK(oracle.variance[3 * p + std::size_t(c)] ==
            doctest::Approx(twin.variance[c]).epsilon(2e-3).scale(1e-6 * twin.mean[c] * twin.mean[c]));
    }
    ++compared;
  }
  CHECK(compared > 10);

  // The oracle sampled: texel by its weight, direction uniform in the texel (texelToDirection keeps area),
  // estimate L f cos / pdf. Its sample variance meets the twin's within the noise of a variance estimate
  // (relative standard error about sqrt(kurtosis - 1) / sqrt(N); 5 of those bound it).
  const gpu::GPixel& g = scene.gbuffer.pixels[std::size_t(6 * 12 + 5)];
  REQUIRE(g.normal.w != 0.0f);
  const glm::dvec3 n = glm::normalize(glm::dvec3(g.normal.x, g.normal.y, g.normal.z));
  const PixelOracle twin = pixelOracle(env, n, 0.7);
  std::vector<double> cdf(twin.weights.size());
  double running = 0.0;
  for (std::size_t t = 0; t < cdf.size(); ++t) cdf[t] = running += twin.weights[t];
  const std::vector<float> solidAngles = rowSolidAngles(env.width, env.height);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int samples = 200000;
  glm::dvec3 sum(0.0), sumSquares(0.0), sumFourth(0.0);
  std::vector<glm::dvec3> estimates;
  for (int i = 0; i < samples; ++i) {
    const auto t = std::size_t(std::upper_bound(cdf.begin(), cdf.end(), u(rng) * running) - cdf.begin());
    const int x = int(t) % env.width, y = int(t) / env.width;
    const glm::dvec3 d = texelToDirection(x, y, {u(rng), u(rng)}, env.width, env.height);
    const double pdf = twin.weights[t] / twin.total / solidAngles[std::size_t(y)];
    const glm::dvec3 e = texelRadiance(env, x, y) * lambertCos(n, d, 0.7) / pdf;
    estimates.push_back(e);
    sum += e;
  }
  const glm::dvec3 mean = sum / double(samples);
  for (const glm::dvec3& e : estimates) {
    const glm::dvec3 d = (e - mean) * (e - mean);
    sumSquares += d;
    sumFourth += d * d;
  }
  for (int c = 0; c < 3; ++c) {
    const double variance = sumSquares[c] / double(samples - 1);
    const double kurtosis = sumFourth[c] / double(samples) / (variance * variance);
    const double relativeError = std::sqrt(std::max(kurtosis - 1.0, 0.0) / samples);
    INFO("channel " << c << ": sampled " << variance << ", twin " << twin.variance[c] << ", relative error "
                    << relativeError);
    CHECK(mean[c] ==
          doctest::Approx(twin.mean[c]).epsilon(5.0 * std::sqrt(variance / samples) / twin.mean[c]));
    CHECK(std::abs(variance / twin.variance[c] - 1.0) < 5.0 * relativeError);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("oracle: with a pixel stride, each block's centre pixel gets the full image's figures") {
  // 13 x 13 with stride 3: blocks' centres at 1, 4, 7, 10 and the last block's (12, 13) clamped to 12.
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", {{"roughness", "0.3"}}, 13);
  const OracleVariance full = computeOracleVariance(gpuContext(), gpuCompiler(), scene);
  const OracleVariance strided = computeOracleVariance(gpuContext(), gpuCompiler(), scene, {}, 3);
  REQUIRE(strided.width == 5);
  REQUIRE(strided.height == 5);
  CHECK(strided.pixelStride == 3);
  REQUIRE(strided.variance.size() == 3 * 25);
  double mse = 0.0;
  int objectPixels = 0;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) {
      const int x = std::min(3 * i + 1, 12), y = std::min(3 * j + 1, 12);
      const std::size_t at = std::size_t(j * 5 + i), source = std::size_t(y * 13 + x);
      CAPTURE(x);
      CAPTURE(y);
      for (int c = 0; c < 3; ++c) {
        CHECK(strided.mean[3 * at + std::size_t(c)] ==
              doctest::Approx(full.mean[3 * source + std::size_t(c)]).epsilon(1e-5));
        CHECK(strided.variance[3 * at + std::size_t(c)] ==
              doctest::Approx(full.variance[3 * source + std::size_t(c)]).epsilon(1e-4));
      }
      if (scene.gbuffer.pixels[source].normal.w == 0.0f) continue;
      for (int c = 0; c < 3; ++c) mse += double(full.variance[3 * source + std::size_t(c)]) / 3.0;
      ++objectPixels;
    }
  REQUIRE(objectPixels > 5);
  CHECK(strided.mseTimesSpp == doctest::Approx(mse / objectPixels).epsilon(1e-4));
  // The figures over the picked pixels estimate the image's: a smooth sky and a wide lobe vary slowly.
  CHECK(strided.mseTimesSpp == doctest::Approx(full.mseTimesSpp).epsilon(0.5));
  // A method's error on the same pixels, against the oracle's integral there: the full image's exact answer
  // has none; 0.1 added to every channel of every pixel gives MSE 0.01 and relMSE 0.01 w(r), times the spp.
  std::vector<float> image = full.mean;
  const OraclePixelsError exact = errorOnOraclePixels(strided, scene.gbuffer, image, 10);
  CHECK(exact.mseTimesSpp < 1e-9);
  double relMse = 0.0;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) {
      const std::size_t source = std::size_t(std::min(3 * j + 1, 12) * 13 + std::min(3 * i + 1, 12));
      if (scene.gbuffer.pixels[source].normal.w == 0.0f) continue;
      for (int c = 0; c < 3; ++c)
        relMse += 0.01 * relativeErrorWeight(strided.mean[3 * std::size_t(j * 5 + i) + std::size_t(c)]) / 3.0;
    }
  for (float& v : image) v += 0.1f;
  const OraclePixelsError off = errorOnOraclePixels(strided, scene.gbuffer, image, 10);
  CHECK(off.mseTimesSpp == doctest::Approx(0.1).epsilon(1e-4));
  CHECK(off.relMseTimesSpp == doctest::Approx(10.0 * relMse / objectPixels).epsilon(1e-3));
  // Per pixel: the same pixels and figures, whose mean is the MSE·spp above.
  const std::vector<OraclePixelError> pixels = oraclePixelErrors(strided, scene.gbuffer, image, 10);
  REQUIRE(pixels.size() == std::size_t(objectPixels));
  double meanSquaredError = 0.0;
  for (const OraclePixelError& p : pixels) {
    CAPTURE(p.x);
    CAPTURE(p.y);
    CHECK((p.x % 3 == 1 || p.x == 12));
    CHECK((p.y % 3 == 1 || p.y == 12));
    const std::size_t at = std::size_t((p.y == 12 ? 4 : p.y / 3) * 5 + (p.x == 12 ? 4 : p.x / 3));
    CHECK(p.mean == doctest::Approx(
                        (strided.mean[3 * at] + strided.mean[3 * at + 1] + strided.mean[3 * at + 2]) / 3.0));
    CHECK(p.variance == doctest::Approx((strided.variance[3 * at] + strided.variance[3 * at + 1] +
                                         strided.variance[3 * at + 2]) /
                                        3.0));
    CHECK(p.squaredErrorTimesSpp == doctest::Approx(0.1).epsilon(1e-4));
    meanSquaredError += p.squaredErrorTimesSpp / double(pixels.size());
  }
  CHECK(meanSquaredError == doctest::Approx(off.mseTimesSpp).epsilon(1e-9));
  CHECK_THROWS_AS(oraclePixelErrors(strided, scene.gbuffer, std::vector<float>(3), 10), Error);
  CHECK_THROWS_AS(errorOnOraclePixels(strided, scene.gbuffer, std::vector<float>(3), 10), Error);
  CHECK_THROWS_AS(computeOracleVariance(gpuContext(), gpuCompiler(), scene, {}, 0), Error);
  checkNoNewValidationErrors();
}

TEST_CASE("oracle: below the variance per sample every method measures, on a sun and a narrow lobe") {
  // A luminance pdf at texel resolution: no method that draws one direction per sample from such a pdf does
  // better, and the methods here draw from coarser ones. Measured with `random` (i.i.d. samples: MSE x spp is
  // the variance per sample).
  const Scene scene = sceneWith(sunAndZeroHalf(64, 32), "ggx", {{"roughness", "0.2"}}, 16);
  const OracleVariance oracle = computeOracleVariance(gpuContext(), gpuCompiler(), scene);
  const std::vector<float> reference = oracle.mean;
  REQUIRE(oracle.mseTimesSpp > 0.0);
  for (const char* name : {"env-hier", "mis", "product"}) {
    MethodSpec spec;
    spec.method = name;
    spec.sequence = "random";
    Renderer renderer(gpuContext(), gpuCompiler(), scene, resolveMethod(spec, *scene.brdf), 3);
    renderer.runPass(256);
    const ErrorMetrics e = compareToReference(scene.gbuffer, renderer.meanRgb(), reference);
    const double perSample = e.mse * 256.0;
    INFO(std::string(name) << ": MSE x spp " << perSample << ", the oracle's " << oracle.mseTimesSpp);
    CHECK(perSample > oracle.mseTimesSpp);
  }
  checkNoNewValidationErrors();
}
