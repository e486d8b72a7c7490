// The equal-time loss in factors (engine/analysis/loss_decomposition.h) on power-law curves whose factors are
// known in closed form.
#include "engine/analysis/loss_decomposition.h"
#include "engine/core/error.h"

#include <doctest/doctest.h>

#include <cmath>

namespace iblx {
namespace {

// MSE = c * spp^slope, GPU time = secondsPerSpp * spp, at spp 4 .. 4096 (4 points per octave).
ConvergenceRun powerLaw(const std::string& sequence, std::uint32_t seed, double c, double slope,
                        double secondsPerSpp) {
  ConvergenceRun run{"m", sequence, seed};
  for (std::uint64_t spp : sppSchedule(4, 4096, 4))
    run.points.push_back({spp, secondsPerSpp * double(spp), secondsPerSpp * double(spp),
                          c * std::pow(double(spp), slope), 0.0});
  return run;
}

// A sampler with variance per sample c (random: MSE = c / spp), sobol MSE = c * q0 * spp^(slope + 1) / spp,
// and cost secondsPerSpp.
SamplerRuns sampler(const std::string& name, double c, double q0, double sobolSlope, double secondsPerSpp) {
  SamplerRuns s{name, {}, {}};
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    s.random.push_back(powerLaw("random", seed, c, -1.0, secondsPerSpp));
    s.sobol.push_back(powerLaw("sobol", seed, c * q0, sobolSlope, secondsPerSpp));
  }
  return s;
}

}  // namespace

TEST_CASE("decomposeLoss: each factor of a power-law sampler against a power-law baseline") {
  // The baseline: C = 0.2, sobol MSE = 0.2 * 0.5 * N^-1.5, 1 ms per spp. The other: C = 0.6 (pdf 3x),
  // sobol MSE = 0.6 * 2 * N^-1.5 (a QMC factor 4x the baseline's at every N), 4 ms per spp (cost).
  const std::vector<SamplerRuns> samplers = {sampler("baseline", 0.2, 0.5, -1.5, 1e-3),
                                             sampler("other", 0.6, 2.0, -1.5, 4e-3)};
  const LossDecomposition d = decomposeLoss(samplers, 0, 1000);
  // Equal time: the end of the shortest sobol run, the baseline's (4096 spp x 1 ms); the other reaches a
  // quarter of its spp there.
  CHECK(d.equalTimeSeconds == doctest::Approx(4096 * 1e-3));
  CHECK(d.baselineSpp == doctest::Approx(4096));
  CHECK(d.baselineSlope == doctest::Approx(-1.5));
  const LossFactors& h = d.rows[0];
  const LossFactors& o = d.rows[1];
  CHECK(h.c == doctest::Approx(0.2));
  CHECK(h.ratio == doctest::Approx(1.0));
  CHECK(o.c == doctest::Approx(0.6));
  CHECK(o.pdf == doctest::Approx(3.0));
  CHECK(o.qmc == doctest::Approx(4.0));
  // Cost: the baseline's MSE with 4x fewer samples, (1/4)^-1.5 = 8.
  CHECK(o.cost == doctest::Approx(8.0));
  CHECK(o.residual == doctest::Approx(1.0));
  CHECK(o.ratio == doctest::Approx(3.0 * 4.0 * 8.0));
  CHECK(o.slopeRandom == doctest::Approx(-1.0));
  CHECK(o.slopeSobol == doctest::Approx(-1.5));
  CHECK(o.nsPerSample == doctest::Approx(4e-3 / 1000 * 1e9));
  CHECK(o.spp == doctest::Approx(1024));
  // Q: the sobol MSE at equal time over C / N, at N = 1024.
  CHECK(o.q == doctest::Approx(2.0 * std::pow(1024.0, -0.5)));
}

TEST_CASE("decomposeLoss: the residual measures the baseline's curve off its power law") {
  // A baseline whose sobol curve wiggles about a power law: the residual, 1 for a straight curve (above), is
  // not 1 here, and the pdf factor, from the random runs, does not see the wiggle.
  std::vector<SamplerRuns> samplers = {sampler("baseline", 0.2, 0.5, -1.2, 1e-3),
                                       sampler("other", 0.3, 1.0, -1.6, 2e-3)};
  for (auto& run : samplers[0].sobol)
    for (auto& p : run.points) p.mse *= 1.0 + 0.3 * std::sin(std::log(double(p.spp)));
  const LossDecomposition d = decomposeLoss(samplers, 0, 500);
  const LossFactors& o = d.rows[1];
  CHECK(o.residual != doctest::Approx(1.0).epsilon(0.01));
  CHECK(o.pdf == doctest::Approx(1.5));
}

TEST_CASE("medianCurve: the median over seeds point by point, NaN points left out, too few points refused") {
  std::vector<ConvergenceRun> seeds = {powerLaw("random", 1, 1.0, -1.0, 1e-3),
                                       powerLaw("random", 2, 3.0, -1.0, 1e-3),
                                       powerLaw("random", 3, 2.0, -1.0, 1e-3)};
  seeds[2].points.pop_back();  // the points every seed reached
  seeds[0].points[0].mse = std::nan("");
  const MedianCurve c = medianCurve(seeds, "m");
  CHECK(c.spp.size() == seeds[2].points.size());
  CHECK(c.mse[1] == doctest::Approx(2.0 / double(seeds[0].points[1].spp)));
  // Point 0: the median of the two finite values, 3/4 and 2/4.
  CHECK(c.mse[0] == doctest::Approx(0.5 * (3.0 + 2.0) / 4.0));
  std::vector<ConvergenceRun> shortRuns = {powerLaw("random", 1, 1.0, -1.0, 1e-3)};
  shortRuns[0].points.resize(2);
  CHECK_THROWS_AS(medianCurve(shortRuns, "m"), Error);
}

}  // namespace iblx
