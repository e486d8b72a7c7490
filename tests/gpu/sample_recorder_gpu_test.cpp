// The sample recorder (engine/render/sample_recorder.h, `iblx samples`) on lavapipe, for every method of the
// registry: the records are the integrator's own samples (their mean is the rendered pixel), each record's
// pdf is its technique's pdf at its direction, directions are in world space under an environment rotation,
// and MIS records carry both techniques in their split.
#include "engine/core/error.h"
#include "engine/render/sample_recorder.h"
#include "engine/sampling/product/env_hier_product.h"
#include "engine/sampling/env/mis_compensation.h"
#include "engine/core/sphere_mapping.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <map>
#include <tuple>

using namespace iblx;
using namespace iblx::test;

namespace {

// GGX with both lobes (so every BRDF technique applies and f is coloured) on a 24 px sphere; 32x16 maps, as
// the other render tests use, so the kernels come from the SPIR-V cache.
const std::vector<std::pair<std::string, std::string>> kGgxParams = {{"roughness", "0.3"},
                                                                     {"metallic", "0.5"}};

// Object pixels: the centre, near the left limb (grazing view) and high on the sphere.
constexpr std::array<std::pair<int, int>, 3> kPixels = {{{12, 12}, {2, 11}, {15, 3}}};

std::vector<RecordedSample> recordPasses(SampleRecorder& recorder, std::pair<int, int> pixel,
                                         std::span<const uint32_t> passes) {
  recorder.start(pixel.first, pixel.second);
  std::vector<RecordedSample> all;
  for (uint32_t spp : passes) {
    const auto pass = recorder.runPass(spp);
    all.insert(all.end(), pass.begin(), pass.end());
  }
  return all;
}

// The world-space shading frame of a G-buffer pixel.
struct PixelFrame {
  glm::dvec3 n, t, b, wo;
  glm::dvec3 toLocal(glm::dvec3 w) const { return {glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)}; }
};
PixelFrame pixelFrame(const Scene& scene, std::pair<int, int> pixel) {
  const gpu::GPixel& g = scene.gbuffer.pixels[std::size_t(pixel.second * scene.gbuffer.width + pixel.first)];
  PixelFrame f;
  f.n = glm::normalize(glm::dvec3(g.normal.x, g.normal.y, g.normal.z));
  f.t = glm::normalize(glm::dvec3(g.tangent.x, g.tangent.y, g.tangent.z));
  f.b = glm::cross(f.n, f.t);
  f.wo = glm::normalize(glm::dvec3(g.view.x, g.view.y, g.view.z));
  return f;
}

// Every method for the GGX scene with random points, and one of each method of the registry with Sobol'
// points (the sequence part is the same for all of them).
std::vector<MethodSpec> methodsToRecord(const BrdfInfo& brdf) {
  std::vector<MethodSpec> specs = allMethodSpecs(brdf, "random");
  for (const MethodInfo& m : methodRegistry()) {
    MethodSpec spec;
    spec.method = m.name;
    spec.sequence = "sobol";
    specs.push_back(spec);
  }
  return specs;
}

}  // namespace

TEST_CASE("samples: the records are the integrator's own samples (their mean is the rendered pixel)") {
  // Under a 1e6 sun beside a black half, estimates spread over orders of magnitude, so records of any other
  // pixel, seed or sample index would miss the rendered mean by far more than float rounding.
  const Scene scene = sceneWith(sunAndZeroHalf(32, 16), "ggx", kGgxParams, 24);
  const uint32_t passes[] = {16, 16, 5};  // a short last pass, as `iblx samples --count` may end with
  for (const MethodSpec& spec : methodsToRecord(*scene.brdf)) {
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    Renderer renderer(gpuContext(), gpuCompiler(), scene, method, 7);
    for (uint32_t spp : passes) renderer.runPass(spp);
    const auto image = renderer.meanRgb();
    SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, method, 7);
    bool anyContribution = false;
    for (const auto& pixel : kPixels) {
      INFO("pixel " << pixel.first << "," << pixel.second);
      const auto samples = recordPasses(recorder, pixel, passes);
      const std::size_t draws = method.drawsPerSample(), count = 37;
      REQUIRE(samples.size() == count * draws);
      glm::dvec3 product(0.0), estimate(0.0), magnitude(0.0);
      for (std::size_t i = 0; i < samples.size(); ++i) {
        const RecordedSample& s = samples[i];
        const std::size_t index = i / draws;
        CHECK(s.index == index);
        CHECK(s.pass == (index < 16 ? 0u : index < 32 ? 1u : 2u));
        // The strategy returns radiance * weight; only ris rounds differently (it scales by sum(w) / M last).
        const glm::dvec3 p = s.radiance * s.weight;
        for (int c = 0; c < 3; ++c) CHECK(std::abs(p[c] - s.estimate[c]) <= 1e-6 * std::abs(s.estimate[c]));
        product += p;
        estimate += s.estimate;
        magnitude += glm::abs(s.estimate);
        anyContribution = anyContribution || s.estimate.x > 0.0;
      }
      const std::size_t at = 3 * std::size_t(pixel.second * scene.gbuffer.width + pixel.first);
      const glm::dvec3 recorderMean = recorder.pixelMean();
      for (int c = 0; c < 3; ++c) {
        // The float running mean of 37 values is within a few ulps of their sum's magnitude.
        const double tolerance = 1e-5 * magnitude[c] / double(count) + 1e-9;
        INFO("channel " << c << ": rendered " << image[at + c] << ", mean of radiance x weight "
                        << product[c] / double(count));
        CHECK(std::abs(product[c] / double(count) - image[at + c]) <= tolerance);
        CHECK(std::abs(estimate[c] / double(count) - image[at + c]) <= tolerance);
        CHECK(std::abs(recorderMean[c] - image[at + c]) <= tolerance);
      }
    }
    CHECK(anyContribution);  // a method whose records were all 0 would pass vacuously
    CHECK(recorder.nonFiniteSamples() == 0);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("samples: each record's pdf is its technique's pdf at its direction; directions are world space") {
  // A rotated map: the records' directions are world space, the techniques work in the map's frame.
  Scene scene = sceneWith(smoothSky(32, 16), "ggx", kGgxParams, 24);
  scene.envRotationDeg = 90.0;
  const EnvImage compensated = misCompensated(scene.env);
  // (technique role, technique name, compensated, pixel) -> the records it drew
  using Key = std::tuple<bool, std::string, bool, std::size_t>;
  std::map<Key, std::vector<RecordedSample>> drawn;
  const uint32_t passes[] = {64, 64};
  for (const MethodSpec& spec : allMethodSpecs(*scene.brdf, "random")) {
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, method, 3);
    for (std::size_t p = 0; p < kPixels.size(); ++p) {
      const PixelFrame frame = pixelFrame(scene, kPixels[p]);
      for (const RecordedSample& s : recordPasses(recorder, kPixels[p], passes)) {
        if (s.technique == "none") continue;  // ris: no candidate kept
        // The product technique's pdf depends on the pixel's lobe: no probe has it. Its sampler is checked
        // against its pdf through the CPU twin (env_product_test.cpp) and the z-tests of the renders.
        if (s.technique == "product") continue;
        // World space: the map's frame turned back, and the samples that contribute lie above the surface.
        CHECK(glm::length(worldToEnv(s.direction, scene.envRotationDeg) - s.envDirection) < 1e-6);
        if (s.estimate.x > 0.0) CHECK(glm::dot(s.direction, frame.n) > -1e-5);
        CHECK(glm::length(s.uv - directionToLatLong(s.envDirection)) < 1e-9);
        const bool env = method.envTechnique && s.technique == method.envTechnique->name;
        REQUIRE((env || (method.brdfTechnique && s.technique == method.brdfTechnique->name)));
        drawn[{env, std::string(s.technique), env && method.misCompensation, p}].push_back(s);
      }
    }
  }
  CHECK(drawn.size() >= 2 * kPixels.size());
  for (const auto& [key, samples] : drawn) {
    const auto& [env, technique, isCompensated, p] = key;
    INFO(technique << (isCompensated ? " (compensated)" : "") << " at pixel " << kPixels[p].first << ","
                   << kPixels[p].second << ", " << samples.size() << " samples");
    const PixelFrame frame = pixelFrame(scene, kPixels[p]);
    std::vector<glm::dvec3> directions;
    std::vector<double> pdfs;
    if (env) {
      for (const auto& s : samples) directions.push_back(s.envDirection);
      EnvTechniqueProbe probe(technique, isCompensated ? compensated : scene.env,
                              worldToEnv(frame.n, scene.envRotationDeg));
      pdfs = probe.pdf(directions);
    } else {
      for (const auto& s : samples) directions.push_back(frame.toLocal(s.direction));
      BrdfTechniqueProbe probe(technique, "ggx", kGgxParams, frame.toLocal(frame.wo));
      pdfs = probe.pdf(directions);
    }
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < samples.size(); ++i)
      if (!(std::abs(samples[i].pdf - pdfs[i]) <= 1e-3 * std::max(samples[i].pdf, pdfs[i]) + 1e-6)) {
        if (mismatches++ < 3)
          MESSAGE("recorded pdf " << samples[i].pdf << ", technique's pdf " << pdfs[i] << " at sample "
                                  << samples[i].index);
      }
    // Env techniques' pdfs are constant per texel and brdf-tab's per table cell: a direction within float
    // rounding of an edge (the records hold float world-space directions, turned back into the technique's
    // frame here) may read the neighbour's, as in the techniques' own tests.
    CHECK(mismatches <= samples.size() / 100);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("samples: two-sample MIS records one env and one BRDF direction per sample, from distinct points") {
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", kGgxParams, 24);
  for (const char* sequence : {"random", "sobol"}) {
    MethodSpec spec;
    spec.method = "mis";
    spec.sequence = sequence;
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    REQUIRE(method.drawsPerSample() == 2);
    SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, method, 5);
    const std::vector<uint32_t> passes(8, 64);
    const auto samples = recordPasses(recorder, kPixels[0], passes);
    REQUIRE(samples.size() == 2 * 8 * 64);
    std::size_t samePoint = 0, bothWeighted = 0;
    for (std::size_t i = 0; i < samples.size(); i += 2) {
      const RecordedSample &env = samples[i], &brdf = samples[i + 1];
      CHECK(env.index == brdf.index);
      CHECK(env.technique == "env-cdf");
      CHECK(brdf.technique == "ggx-vndf");
      for (const RecordedSample* s : {&env, &brdf}) {
        CHECK(s->misWeight >= 0.0);
        CHECK(s->misWeight <= 1.0 + 1e-6);
      }
      samePoint += env.point == brdf.point;
      bothWeighted += env.misWeight > 0.0 && brdf.misWeight > 0.0;
    }
    // Each technique reads its own dimension pair: equal points would mean one pair feeds both.
    CHECK(samePoint == 0);
    CHECK(4 * bothWeighted >
          samples.size() / 2);  // on a smooth sky both directions contribute in many samples
  }
  checkNoNewValidationErrors();
}

TEST_CASE(
    "samples: product draws record the node their table chose, which holds them, with the P(node) of their "
    "pdf") {
  // 64x32: the pyramid level has 32x16 nodes of 2x2 texels, so a node's rectangle is not one texel's, and a
  // lobe of alpha 0.1 is narrower than a node, so the split nodes' children are chosen too.
  const Scene scene = sceneWith(smoothSky(64, 32), "ggx", {{"roughness", "0.1"}, {"metallic", "0.5"}}, 24);
  for (const char* name : {"product", "product-mis", "product-warp"}) {
    MethodSpec spec;
    spec.method = name;
    spec.sequence = "sobol";
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    const bool grid = std::string(name) == "product-warp";
    const EnvHierSampler hier(buildEnvHier(method.misCompensation ? misCompensated(scene.env) : scene.env));
    // The table's level and the refinement's finer ones: a record names the deepest node chosen.
    const std::vector<EnvProductLevel> levels =
        grid ? std::vector<EnvProductLevel>{buildEnvProductGrid(hier)} : buildEnvProductLevels(hier);
    std::size_t deeper = 0;
    SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, method, 7);
    const uint32_t passes[] = {256};
    for (const auto& pixel : kPixels) {
      std::map<std::pair<uint32_t, uint32_t>, double>
          probabilityOf;  // (columns, node) -> P: one table per pixel
      std::size_t productDraws = 0, mismatches = 0;
      for (const RecordedSample& s : recordPasses(recorder, pixel, passes)) {
        if (s.technique != "product") {
          CHECK(!s.productNode);
          continue;
        }
        if (!(s.pdf > 0.0)) continue;
        REQUIRE(s.productNode);
        const ProductNodeChoice& c = *s.productNode;
        const auto depth = std::size_t(std::countr_zero(c.columns / levels[0].width));
        REQUIRE(depth < levels.size());
        const EnvProductLevel& level = levels[depth];
        REQUIRE(c.columns == level.width);
        REQUIRE(c.rows == level.rows);
        REQUIRE(c.node < level.nodes());
        deeper += depth > 0;
        ++productDraws;
        const auto [known, added] = probabilityOf.emplace(std::pair{c.columns, c.node}, c.probability);
        CHECK(known->second == c.probability);
        // Blocks of texels on the map hold the direction; a grid cell of u has no rectangle there.
        CHECK(c.mapUv.has_value() == !grid);
        if (c.mapUv) {
          const double eps = 1e-6;
          CHECK((s.uv.x >= c.mapUv->x - eps && s.uv.x <= c.mapUv->z + eps));
          CHECK((s.uv.y >= c.mapUv->y - eps && s.uv.y <= c.mapUv->w + eps));
          const uint32_t texels = level.texelsPerNode;
          CHECK(c.mapUv->x == doctest::Approx(double(c.column() * texels) / scene.env.width));
          CHECK(c.mapUv->w ==
                doctest::Approx(std::min(1.0, double((c.row() + 1) * texels) / scene.env.height)));
        }
        // pdf = P(node) / E_node * p_env-hier(wi) for the deepest node chosen
        // (engine/sampling/product/env_hier_product.h).
        const glm::vec4& r = level.rects[c.node];
        const double area = double(r.z - r.x) * double(r.w - r.y);
        const double implied = s.pdf * area / hier.pdf(s.envDirection);
        if (!(std::abs(implied - c.probability) <= 1e-3 * c.probability)) ++mismatches;
      }
      CAPTURE(pixel.first);
      CAPTURE(pixel.second);
      CHECK(productDraws >= 250u);  // of 256: a draw on a float edge of the table has pdf 0
      // A direction within float rounding of a texel edge may read the neighbour's env-hier pdf.
      CHECK(mismatches <= productDraws / 100);
      double sum = 0.0;
      for (const auto& [node, p] : probabilityOf) sum += p;
      CHECK(sum <= 1.0 + 1e-5);
      CHECK(probabilityOf.size() >= 4);  // a glossy lobe over a smooth sky spreads over several nodes
    }
    // The 64x32 map has a level below the table's: the split nodes' children are chosen (not on the grid).
    CHECK((deeper > 0) == !grid);
  }
  checkNoNewValidationErrors();
}

// Whether points form a (0,m,2)-net in base 2 (2^m points): every elementary interval of area 2^-m, of every
// shape 2^-i x 2^-(m-i), holds exactly one point.
bool isZeroMTwoNet(const std::vector<glm::dvec2>& points) {
  const int m = std::countr_zero(points.size());
  if (std::size_t(1) << m != points.size()) return false;
  for (int i = 0; i <= m; ++i) {
    std::vector<int> hits(points.size(), 0);
    for (const glm::dvec2& p : points) {
      const auto x = std::size_t(p.x * double(1u << i)), y = std::size_t(p.y * double(1u << (m - i)));
      if (++hits[(y << i) + x] > 1) return false;
    }
  }
  return true;
}

TEST_CASE("samples: each dimension pair a strategy reads is its own (0,m,2)-net under sobol and cp-shared") {
  // Two-sample MIS draws the env direction from pair 0 and the BRDF direction from pair 1.
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", kGgxParams, 24);
  auto record = [&](const char* sequence) {
    MethodSpec spec;
    spec.method = "mis";
    spec.sequence = sequence;
    SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, resolveMethod(spec, *scene.brdf), 3);
    auto samples = recordPasses(recorder, kPixels[0], std::vector<uint32_t>{256});
    REQUIRE(samples.size() == 512);
    return samples;
  };
  auto pairPoints = [](const std::vector<RecordedSample>& samples, std::size_t pair, std::size_t count) {
    std::vector<glm::dvec2> points;
    for (std::size_t i = 0; i < count; ++i) points.push_back(samples[2 * i + pair].point);
    return points;
  };
  // sobol: every power-of-two prefix of each pair is a net, as padded Owen-scrambled Sobol pairs are (Burley
  // 2020); a pair fed from a hash would fail, and pair 1 equal to pair 0 would fail the mixed set.
  const auto sobol = record("sobol");
  for (std::size_t pair = 0; pair < 2; ++pair)
    for (std::size_t count : {16, 64, 256}) {
      INFO("sobol pair " << pair << ", first " << count << " points");
      CHECK(isZeroMTwoNet(pairPoints(sobol, pair, count)));
    }
  std::vector<glm::dvec2> mixed = pairPoints(sobol, 0, 8), second = pairPoints(sobol, 1, 8);
  mixed.insert(mixed.end(), second.begin(), second.end());
  CHECK_FALSE(isZeroMTwoNet(mixed));
  // cp-shared: pair 0 is the unscrambled Sobol set shifted by its first point (Sobol's point 0 is the origin,
  // and the 24-bit shift is exact); pair 1 reads the set in another order, so it is not pair 0 moved by a
  // constant.
  const auto shared = record("cp-shared");
  const std::vector<glm::dvec2> first = pairPoints(shared, 0, 256), other = pairPoints(shared, 1, 256);
  for (std::size_t count : {16, 64, 256}) {
    std::vector<glm::dvec2> unshifted;
    for (std::size_t i = 0; i < count; ++i) unshifted.push_back(glm::fract(first[i] - first[0]));
    INFO("cp-shared pair 0 unshifted, first " << count << " points");
    CHECK(isZeroMTwoNet(unshifted));
  }
  std::size_t sameOffset = 0;
  for (std::size_t i = 1; i < other.size(); ++i)
    sameOffset += glm::length(glm::fract(other[i] - first[i]) - glm::fract(other[0] - first[0])) < 1e-9;
  CHECK(sameOffset < 8);
  checkNoNewValidationErrors();
}

TEST_CASE("samples: one-sample MIS records carry both techniques in the split, with their MIS weights") {
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", kGgxParams, 24);
  for (const char* sequence : {"random", "sobol"}) {
    MethodSpec spec;
    spec.method = "mis";
    spec.sequence = sequence;
    spec.misEnvFraction = 0.3;
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, method, 5);
    const std::vector<uint32_t> passes(64, 64);
    const auto samples = recordPasses(recorder, kPixels[0], passes);
    std::map<std::string, std::size_t> counts;
    for (const auto& s : samples) {
      ++counts[std::string(s.technique)];
      CHECK(s.misWeight >= 0.0);
      CHECK(s.misWeight <= 1.0 + 1e-6);
    }
    CHECK(counts.size() == 2);
    CHECK(counts["env-cdf"] + counts["ggx-vndf"] == samples.size());
    // u.x < 0.3 picks the env technique: a binomial share within 5 standard deviations.
    const double share = double(counts["env-cdf"]) / double(samples.size());
    CHECK(std::abs(share - 0.3) < 5.0 * std::sqrt(0.3 * 0.7 / double(samples.size())));
  }
  checkNoNewValidationErrors();
}

TEST_CASE("samples: a pixel off the image or off the object is refused with the reason") {
  const Scene scene = sceneWith(smoothSky(32, 16), "lambert", {}, 24);
  MethodSpec spec;
  spec.method = "env-cdf";
  SampleRecorder recorder(gpuContext(), gpuCompiler(), scene, resolveMethod(spec, *scene.brdf));
  CHECK_THROWS_WITH_AS(recorder.start(0, 0), doctest::Contains("background"), Error);
  CHECK_THROWS_WITH_AS(recorder.start(24, 3), doctest::Contains("outside the 24x24 image"), Error);
  CHECK_THROWS_WITH_AS(recorder.start(3, -1), doctest::Contains("outside"), Error);
  CHECK_THROWS_AS(recorder.runPass(8), Error);  // never started
  CHECK_FALSE(unrecordablePixel(scene.gbuffer, 12, 12).has_value());
  checkNoNewValidationErrors();
}
