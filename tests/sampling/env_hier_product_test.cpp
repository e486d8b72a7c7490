// Tests of the env-hier product level and the product sampler's CPU twin
// (engine/sampling/product/env_hier_product.h): the level's node rectangles, the node probabilities,
// chi-square of the samples against the pdf on hard maps.
#include "engine/sampling/product/env_hier_product.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "tests/sampling/env_technique_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace iblx {
namespace {

// A lobe around `axis` with exponent k, and exactly zero on the half-space below `horizon`: F_j at the nodes'
// centres, as a shading point's f cos would be.
std::vector<double> lobeAtCentres(const EnvProductLevel& level, glm::dvec3 axis, double k,
                                  glm::dvec3 horizon) {
  std::vector<double> f;
  for (const glm::vec4& c : level.centers) {
    const glm::dvec3 d(c.x, c.y, c.z);
    f.push_back(glm::dot(d, horizon) > 0.0 ? std::pow(std::max(glm::dot(d, axis), 0.0), k) + 1e-3 : 0.0);
  }
  return f;
}

// Draws 5000 samples: each has a positive pdf and lies on a texel of positive weight, and its pdf is pdf() of
// its direction; onSample sees every sample but those on a texel or cell border, which may be located in the
// neighbour (their count is returned).
template <typename OnSample>
int checkSamplesAgainstPdf(const EnvProductSampler& sampler, const EnvImage& image, uint64_t seed,
                           OnSample onSample) {
  int boundary = 0;
  for (const glm::dvec2 u : test::uniformPoints(5000, seed)) {
    const EnvSample s = sampler.sample(u);
    REQUIRE(s.pdfSolidAngle > 0.0);
    CHECK(image.weight(s.texel.x, s.texel.y) > 0.0);
    if (directionToTexel(s.direction, image.width, image.height) != s.texel ||
        !(std::abs(s.pdfSolidAngle - sampler.pdf(s.direction)) <= 1e-9 * s.pdfSolidAngle)) {
      ++boundary;
      continue;
    }
    onSample(s);
  }
  return boundary;
}

}  // namespace

TEST_CASE("env product level: the finest level within the node budget, rectangles tiling u") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvHierSampler hier(buildEnvHier(env.image));
    const EnvProductLevel level = buildEnvProductLevel(hier, 512);
    // 64x32 and 50x25 pad to 64^2: 32 nodes across (2 texels each) fit 512 with 16 and 13 rows; 64 do not.
    CHECK(level.width == 32);
    CHECK(level.texelsPerNode == 2);
    CHECK(level.rows == uint32_t((env.image.height + 1) / 2));
    REQUIRE(level.nodes() == level.width * level.rows);
    double total = 0.0;
    for (uint32_t y = 0; y < level.rows; ++y)
      for (uint32_t x = 0; x < level.width; ++x) {
        const glm::vec4& r = level.rects[y * level.width + x];
        const double area = double(r.z - r.x) * double(r.w - r.y);
        total += area;
        // A node's env-hier probability is the sum of its texels' (their rectangles partition it).
        double texels = 0.0;
        for (int ty = int(2 * y); ty < std::min(int(2 * y + 2), env.image.height); ++ty)
          for (int tx = int(2 * x); tx < std::min(int(2 * x + 2), env.image.width); ++tx)
            texels += double(hier.texelProbability(tx, ty));
        CHECK(area == doctest::Approx(texels).epsilon(1e-5).scale(1e-7));
      }
    CHECK(total == doctest::Approx(1.0).epsilon(1e-5));
    // u inside a node's rectangle descends to one of its texels.
    for (const glm::dvec2 u : test::uniformPoints(2000, 3)) {
      const glm::vec4& r =
          level.rects[std::size_t(u.y * level.rows) * level.width + std::size_t(u.x * level.width)];
      if (!(r.z > r.x && r.w > r.y)) continue;
      const glm::dvec2 inside(r.x + 0.5 * (r.z - r.x), r.y + 0.5 * (r.w - r.y));
      const EnvSample s = hier.sample(inside);
      CHECK(uint32_t(s.texel.x) / level.texelsPerNode == std::size_t(u.x * level.width));
      CHECK(uint32_t(s.texel.y) / level.texelsPerNode == std::size_t(u.y * level.rows));
    }
  }
  const EnvHierSampler hier(buildEnvHier(smoothSky(64, 32)));
  CHECK(buildEnvProductLevel(hier, 4).nodes() <= 4);
  CHECK(buildEnvProductLevel(hier, 1).nodes() == 1);  // the root
  // Every map's level and its refinement's block fit a pixel's stored table (kEnvProductMaxTableWords): wide,
  // square, tall and tiny.
  for (const auto& [w, h] : {std::pair{64, 32}, {256, 16}, {32, 32}, {16, 64}, {3, 200}, {1, 1}, {1000, 7}}) {
    CAPTURE(w);
    CAPTURE(h);
    const EnvProductLevel l = buildEnvProductLevel(EnvHierSampler(buildEnvHier(smoothSky(w, h))));
    CHECK(l.nodes() <= kEnvProductMaxNodes);
    CHECK(productTableWords(l.width, l.rows) + productRefineWords(uint32_t(l.nodes())) <=
          kEnvProductMaxTableWords);
  }
  CHECK_THROWS_AS(buildEnvProductLevel(hier, 0), Error);
}

TEST_CASE("env product sampler: node probabilities mix the product with env-hier's, defensively") {
  const EnvHierSampler hier(buildEnvHier(sunAndZeroHalf(64, 32)));
  const EnvProductLevel level = buildEnvProductLevel(hier);
  const std::vector<double> f = lobeAtCentres(level, glm::normalize(glm::dvec3(1, 1, 0)), 8.0, {0, 1, 0});
  const EnvProductSampler sampler(hier, level, f);
  double sumEF = 0.0, sumE = 0.0, total = 0.0;
  for (std::size_t j = 0; j < level.nodes(); ++j) {
    const glm::vec4& r = level.rects[j];
    sumEF += double((r.z - r.x) * (r.w - r.y)) * f[j];
    sumE += double((r.z - r.x) * (r.w - r.y));  // 1 to float rounding
    total += sampler.nodeProbability(j);
  }
  CHECK(total == doctest::Approx(1.0).epsilon(1e-9));
  const double normalize = 1.0 - kEnvProductDefensive + kEnvProductDefensive * sumE;
  const auto area = [&](std::size_t j) {
    const glm::vec4& r = level.rects[j];
    return double((r.z - r.x) * (r.w - r.y));
  };
  // P(j) of `sampler` against `expected` (normalized): the 16-bit table moves a row's share by at most
  // (0.5 + rows) steps plus its rescaling by at most rows / 65535, and a node's share within its row likewise
  // (quantizedRunningSums); a node of positive area stays reachable however small its share.
  const auto checkProbabilities = [&](const EnvProductSampler& tested, const auto& expected) {
    for (uint32_t y = 0; y < level.rows; ++y) {
      double row = 0.0;
      for (uint32_t x = 0; x < level.width; ++x) row += expected(y * level.width + x);
      for (uint32_t x = 0; x < level.width; ++x) {
        const std::size_t j = y * level.width + x;
        const double conditional = row > 0.0 ? expected(j) / row : 0.0;
        const double tolerance = (0.5 + 2.0 * level.rows) / kProductFullScale * conditional +
                                 (0.5 + 2.0 * level.width) / kProductFullScale * row + 1e-12;
        CHECK(std::abs(tested.nodeProbability(j) - expected(j)) <= tolerance);
        if (area(j) > 0.0)
          CHECK(tested.nodeProbability(j) > 0.0);
        else
          CHECK(tested.nodeProbability(j) == 0.0);  // a black node is never chosen
      }
    }
  };
  checkProbabilities(sampler, [&](std::size_t j) {
    return ((1.0 - kEnvProductDefensive) * area(j) * f[j] / sumEF + kEnvProductDefensive * area(j)) /
           normalize;
  });
  // With no lobe anywhere (a shading point facing away from every centre), the nodes follow env-hier's
  // masses, and the pdf is env-hier's times the quantized over the exact node probability.
  const EnvProductSampler flat(hier, level, std::vector<double>(level.nodes(), 0.0));
  checkProbabilities(flat, [&](std::size_t j) { return area(j) / sumE; });
  for (const glm::dvec2 u : test::uniformPoints(500, 4)) {
    const glm::dvec3 w = latLongToDirection(u);
    const std::size_t j = flat.nodeOf(w);
    if (!(area(j) > 0.0)) continue;
    CHECK(flat.pdf(w) == doctest::Approx(hier.pdf(w) * flat.nodeProbability(j) / area(j)).epsilon(1e-5));
  }
  CHECK_THROWS_AS(EnvProductSampler(hier, level, std::vector<double>(3, 1.0)), Error);
}

TEST_CASE("product table: 16-bit running sums keep every positive weight reachable and end at the scale") {
  // A weight far below a float's step of the running sum (1 + 1e-12 == 1 in float): it keeps one step.
  const std::vector<double> weights{1.0, 1e-12, 0.0, 2.0, 0.0, 1.0};
  const std::vector<uint32_t> q = quantizedRunningSums(weights);
  REQUIRE(q.size() == weights.size());
  CHECK(q.back() == kProductFullScale);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const uint32_t step = q[i] - (i == 0 ? 0 : q[i - 1]);
    CAPTURE(i);
    CHECK(q[i] >= (i == 0 ? 0 : q[i - 1]));
    if (weights[i] > 0.0) {
      CHECK(step >= 1);
      // Within a step or two of its share of the 65535 - 4 steps left after one per positive weight.
      CHECK(std::abs(double(step) - 1.0 - weights[i] / 4.0 * (kProductFullScale - 4)) <= 1.0);
    } else {
      CHECK(step == 0);  // a zero weight is never chosen
    }
  }
  CHECK(quantizedRunningSums(std::vector<double>(5, 0.0)) == std::vector<uint32_t>(5, 0));
  CHECK(quantizedRunningSums(std::vector<double>{3.0}) == std::vector<uint32_t>{kProductFullScale});
  CHECK_THROWS_AS(quantizedRunningSums(std::vector<double>{1.0, -1.0}), Error);
  CHECK_THROWS_AS(quantizedRunningSums(std::vector<double>{std::nan("")}), Error);

  // Over a level: P(node) is the row's step times the node's step in its row, over 65535 each; they sum to 1.
  const EnvHierSampler hier(buildEnvHier(smoothSky(64, 32)));
  const EnvProductLevel level = buildEnvProductLevel(hier);
  std::vector<double> w(level.nodes());
  for (std::size_t j = 0; j < w.size(); ++j) w[j] = j % 7 == 0 ? 1e-9 : double(j % 5);
  const std::vector<double> p = quantizedNodeProbabilities(level, w);
  double sum = 0.0;
  for (std::size_t j = 0; j < p.size(); ++j) {
    sum += p[j];
    CHECK((p[j] > 0.0) == (w[j] > 0.0));
  }
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-12));
  for (uint32_t y = 0; y < level.rows; ++y) {
    double row = 0.0;
    for (uint32_t x = 0; x < level.width; ++x) row += p[y * level.width + x];
    const double rowSteps = row * kProductFullScale;
    CHECK(std::abs(rowSteps - std::round(rowSteps)) < 1e-6);
    for (uint32_t x = 0; x < level.width && row > 0.0; ++x) {
      const double steps = p[y * level.width + x] / row * kProductFullScale;
      CHECK(std::abs(steps - std::round(steps)) < 1e-6);
    }
  }
  CHECK(quantizedNodeProbabilities(level, std::vector<double>(level.nodes(), 0.0)) ==
        std::vector<double>(level.nodes(), 0.0));
  CHECK_THROWS_AS(quantizedNodeProbabilities(level, std::vector<double>(3, 1.0)), Error);
}

TEST_CASE("env product sampler: chi2 against its own pdf on hard maps, the pdf integrating to 1") {
  const auto envs = test::samplerTestEnvs();
  uint64_t seed = 300;
  for (const auto& env : envs)
    for (const bool grid : {false, true}) {
      CAPTURE(env.name);
      CAPTURE(grid);
      const EnvHierSampler hier(buildEnvHier(env.image));
      const EnvProductLevel level = grid ? buildEnvProductGrid(hier) : buildEnvProductLevel(hier);
      // A glossy lobe towards the horizon with a shading hemisphere (a view that leaves many nodes at 0).
      const std::vector<double> f = lobeAtCentres(level, glm::normalize(glm::dvec3(0.3, 0.2, 1.0)), 30.0,
                                                  glm::normalize(glm::dvec3(0, 0.3, 1)));
      const EnvProductSampler sampler(hier, level, f);
      const test::Chi2Result r =
          test::runChi2(sampler, std::string(grid ? "env-product-grid-" : "env-product-") + env.name,
                        int(2 * envs.size()), seed++);
      INFO(r.message);
      CHECK(r.passed);
      CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
      // Each sample's pdf (from the node chosen) is pdf() of its direction (from the node located), and a
      // sample never lands on a black texel.
      CHECK(checkSamplesAgainstPdf(sampler, env.image, seed, [](const EnvSample&) {}) < 50);
    }
}

namespace {

// A narrow lobe pow(cos, k) around `axis`, zero below `horizon`, at the direction of a cap closest to the
// axis: what the GPU evaluates for a mirror-like lobe.
ProductCapLobe narrowLobe(glm::dvec3 axis, double k, glm::dvec3 horizon) {
  return [=](const glm::vec4& cap) {
    const glm::dvec3 d = closestDirectionInCap(glm::dvec3(cap.x, cap.y, cap.z), double(cap.w), axis);
    return glm::dot(d, horizon) > 0.0 ? std::pow(std::max(glm::dot(d, axis), 0.0), k) : 0.0;
  };
}

double nodeArea(const EnvProductLevel& level, std::size_t j) {
  const glm::vec4& r = level.rects[j];
  return double((r.z - r.x) * (r.w - r.y));
}

}  // namespace

TEST_CASE("env product sampler, refined: the largest nodes split twice, chi2 against its own pdf") {
  auto envs = test::samplerTestEnvs();
  envs.push_back({"sun-zero-256x128", sunAndZeroHalf(256, 128)});  // two levels below the table's
  envs.push_back({"smooth-256x128", smoothSky(256, 128)});
  uint64_t seed = 700;
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.4, 0.5, 1.0)), horizon(0, 0.3, 1);
  for (const auto& env : envs) {
    CAPTURE(env.name);
    const EnvHierSampler hier(buildEnvHier(env.image));
    const std::vector<EnvProductLevel> levels = buildEnvProductLevels(hier);
    const uint32_t depth = env.image.width >= 256 ? 2 : 1;  // 64x32 and 50x25: nodes of 2x2 texels
    REQUIRE(levels.size() == depth + 1);
    for (uint32_t k = 1; k < levels.size(); ++k) {
      CHECK(levels[k].width == levels[0].width << k);
      CHECK(levels[k].texelsPerNode == levels[0].texelsPerNode >> k);
    }
    const ProductCapLobe lobe = narrowLobe(axis, 3000.0, horizon);
    const EnvProductSampler sampler(hier, levels, lobe);
    // The split nodes are those of largest E F, none of the others larger; the children split again are
    // children of split nodes.
    const auto& split = sampler.refinedNodes();
    REQUIRE(split.size() == kProductRefinedNodes);
    double smallestSplit = 1e300, largestKept = 0.0;
    for (std::size_t j = 0; j < levels[0].nodes(); ++j) {
      const double ef = nodeArea(levels[0], j) * lobe(levels[0].centers[j]);
      if (std::find(split.begin(), split.end(), j) != split.end())
        smallestSplit = std::min(smallestSplit, ef);
      else
        largestKept = std::max(largestKept, ef);
    }
    CHECK(smallestSplit >= largestKept);
    CHECK(sampler.refinedChildren().size() == (depth > 1 ? kProductRefinedChildren : 0u));
    for (const std::size_t child : sampler.refinedChildren()) {
      const std::size_t parent =
          (child / levels[1].width / 2) * levels[0].width + (child % levels[1].width) / 2;
      CHECK(std::find(split.begin(), split.end(), parent) != split.end());
    }
    const test::Chi2Result r =
        test::runChi2(sampler, "env-product-refined-" + env.name, int(envs.size()), seed++);
    INFO(r.message);
    CHECK(r.passed);
    CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
    // Each sample's pdf is pdf() of its direction, whose deepest node is the split one's child (or
    // grandchild) where it lies in a split node; none lands on a black texel.
    int deep = 0;
    const int boundary = checkSamplesAgainstPdf(sampler, env.image, seed, [&](const EnvSample& s) {
      const ProductLeaf leaf = sampler.leafOf(s.direction);
      const bool inSplit = std::find(split.begin(), split.end(), sampler.nodeOf(s.direction)) != split.end();
      CHECK((leaf.depth > 0) == inSplit);
      deep += leaf.depth == depth;
    });
    CHECK(boundary < 50);
    CHECK(deep > 2500);  // a narrow lobe: most samples end at the deepest level
  }
}

TEST_CASE("env product sampler, refined: more samples inside a lobe narrower than a node than one level") {
  // A lobe of about 2 degrees (pow(cos, 3000)) on a smooth 512x256 sky: nodes of 16x16 texels, about 11
  // degrees. The one-level sampler spreads a node's share over the node by env-hier; the refined one puts it
  // on the quarter and sixteenth of the node nearest the lobe.
  const EnvHierSampler hier(buildEnvHier(smoothSky(512, 256)));
  const std::vector<EnvProductLevel> levels = buildEnvProductLevels(hier);
  REQUIRE(levels.size() == 3);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.4, 0.5, 1.0)), horizon(0, 0.3, 1);
  const ProductCapLobe lobe = narrowLobe(axis, 3000.0, horizon);
  std::vector<double> f;
  for (const glm::vec4& c : levels[0].centers) f.push_back(lobe(c));
  const EnvProductSampler oneLevel(hier, levels[0], f), refined(hier, levels, lobe);
  const auto inLobe = [&](const EnvProductSampler& sampler) {
    int hits = 0;
    for (const glm::dvec2 u : test::uniformPoints(20000, 5))
      hits += glm::dot(sampler.sample(u).direction, axis) > std::cos(0.05);  // within about 3 degrees
    return hits;
  };
  const int before = inLobe(oneLevel), after = inLobe(refined);
  MESSAGE("samples within 3 degrees of the lobe's axis: one level " << before << ", refined " << after);
  CHECK(after > 4 * before);
  // With F = 0 everywhere nothing is split and the table is the one-level sampler's.
  const EnvProductSampler flat(hier, levels, [](const glm::vec4&) { return 0.0; });
  CHECK(flat.refinedNodes().empty());
  const EnvProductSampler flatOneLevel(hier, levels[0], std::vector<double>(levels[0].nodes(), 0.0));
  for (std::size_t j = 0; j < levels[0].nodes(); ++j)
    CHECK(flat.nodeProbability(j) == flatOneLevel.nodeProbability(j));
}

TEST_CASE("env product grid: uniform cells over u, each holding the directions its u maps to") {
  const EnvHierSampler hier(buildEnvHier(sunAndZeroHalf(64, 32)));
  const EnvProductLevel grid = buildEnvProductGrid(hier, 8, 4);
  REQUIRE(grid.nodes() == 32);
  CHECK(grid.uniformGrid);
  const std::vector<double> flat(grid.nodes(), 1.0);
  const EnvProductSampler sampler(hier, grid, flat);
  for (std::size_t j = 0; j < grid.nodes(); ++j) {
    const glm::vec4& r = grid.rects[j];
    CHECK(double((r.z - r.x) * (r.w - r.y)) == doctest::Approx(1.0 / 32.0));
    CHECK(sampler.nodeProbability(j) == doctest::Approx(1.0 / 32.0));  // equal F: env-hier itself
  }
  int tested = 0, outsideCap = 0;
  for (const glm::dvec2 u : test::uniformPoints(2000, 11)) {
    const std::size_t cell = std::size_t(u.y * 4) * 8 + std::size_t(u.x * 8);
    const EnvSample s = hier.sample(u);
    // Away from cell edges, env-hier's inverse puts the direction back in the cell of u.
    const glm::dvec2 inCell(u.x * 8 - std::floor(u.x * 8), u.y * 4 - std::floor(u.y * 4));
    if (glm::min(inCell, 1.0 - inCell).x < 1e-3 || glm::min(inCell, 1.0 - inCell).y < 1e-3) continue;
    CHECK(sampler.nodeOf(s.direction) == cell);
    const glm::vec4& c = grid.centers[cell];
    ++tested;
    outsideCap += glm::dot(glm::dvec3(c.x, c.y, c.z), s.direction) < double(c.w) - 1e-6;
  }
  // The caps are estimated from a grid of u per cell: a dim block thinner in u than the grid's step can fall
  // outside (it only lowers that block's weight; the pdf stays exact).
  CHECK(tested > 1500);
  CHECK(outsideCap * 100 <= tested);
  CHECK_THROWS_AS(buildEnvProductGrid(hier, 0, 4), Error);
}

}  // namespace iblx

namespace iblx {

TEST_CASE("env product level: each node's cap holds its block; the closest direction in a cap") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvHierSampler hier(buildEnvHier(env.image));
    const EnvProductLevel level = buildEnvProductLevel(hier);
    // Random directions of each node's texels lie within its angular radius of its centre.
    for (const glm::dvec2 u : test::uniformPoints(20000, 7)) {
      const glm::dvec3 w = latLongToDirection(u);
      const glm::ivec2 t = directionToTexel(w, env.image.width, env.image.height);
      const glm::vec4& c = level.centers[std::size_t(uint32_t(t.y) / level.texelsPerNode) * level.width +
                                         uint32_t(t.x) / level.texelsPerNode];
      CHECK(glm::dot(glm::dvec3(c.x, c.y, c.z), w) >= double(c.w) - 1e-6);
    }
  }
  const glm::dvec3 centre(0, 0, 1);
  const double cosRadius = std::cos(0.3);
  const glm::dvec3 inside = glm::normalize(glm::dvec3(0.1, 0.1, 1.0));
  CHECK(glm::length(closestDirectionInCap(centre, cosRadius, inside) - inside) < 1e-12);
  const glm::dvec3 outside = glm::normalize(glm::dvec3(1.0, 0.5, 0.2));
  const glm::dvec3 d = closestDirectionInCap(centre, cosRadius, outside);
  CHECK(glm::length(d) == doctest::Approx(1.0));
  CHECK(glm::dot(d, centre) == doctest::Approx(cosRadius));                 // on the cap's edge
  CHECK(glm::dot(glm::cross(centre, outside), d) == doctest::Approx(0.0));  // towards `outside`
  CHECK(glm::dot(d, outside) > glm::dot(centre, outside));
}

}  // namespace iblx
