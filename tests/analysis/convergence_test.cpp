// The figures of `iblx converge` on synthetic curves whose answers are known in closed form.
#include "engine/analysis/convergence.h"
#include "engine/core/error.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <fstream>
#include <unistd.h>

namespace iblx {
namespace {

// A run whose MSE is c / spp and whose time is `secondsPerSpp` * spp, at the points of `schedule`.
ConvergenceRun powerLawRun(const std::string& method, uint32_t seed, double c, double secondsPerSpp,
                           const std::vector<uint64_t>& schedule) {
  ConvergenceRun run{method, "random", seed};
  for (uint64_t spp : schedule) {
    const double mse = c / double(spp);
    run.points.push_back({spp, 0.9 * secondsPerSpp * double(spp), secondsPerSpp * double(spp), mse, 2 * mse});
  }
  return run;
}

}  // namespace

TEST_CASE("sppSchedule: evenly spaced in log spp, strictly increasing, ending at the budget") {
  const auto s = sppSchedule(4, 64, 4);
  REQUIRE(s.size() == 17);
  CHECK(s.front() == 4);
  CHECK(s.back() == 64);
  for (std::size_t i = 1; i < s.size(); ++i) {
    CHECK(s[i] > s[i - 1]);
    CHECK(double(s[i]) / double(s[i - 1]) == doctest::Approx(std::exp2(0.25)).epsilon(0.12));
  }
  // Small counts cannot be spaced by 2^(1/4): every point is still a new spp.
  CHECK(sppSchedule(1, 3, 4) == std::vector<uint64_t>{1, 2, 3});
  // A budget between two points ends the schedule at the budget itself.
  CHECK(sppSchedule(16, 100, 1) == std::vector<uint64_t>{16, 32, 64, 100});
  CHECK_THROWS_AS(sppSchedule(8, 4, 4), Error);
  CHECK_THROWS_AS(sppSchedule(0, 4, 4), Error);
}

TEST_CASE("fitLogLogSlope and interpolateLogLog on power laws") {
  const std::vector<double> x = {1, 2, 4, 8, 16}, y = {5, 2.5, 1.25, 0.625, 0.3125};
  CHECK(fitLogLogSlope(x, y) == doctest::Approx(-1.0));
  const std::vector<double> y2 = {1, 4, 16, 64, 256};
  CHECK(fitLogLogSlope(x, y2) == doctest::Approx(2.0));
  CHECK(std::isnan(fitLogLogSlope(std::vector<double>{1, 2}, std::vector<double>{1, 2})));
  // Non-positive and non-finite points are left out, not fitted as log(0).
  const std::vector<double> withBad = {5, 0.0, 1.25, NAN, 0.3125};
  CHECK(fitLogLogSlope(x, withBad) == doctest::Approx(-1.0));

  CHECK(interpolateLogLog(x, y, 2.0) == doctest::Approx(2.5));
  CHECK(interpolateLogLog(x, y, std::sqrt(2.0)) == doctest::Approx(5.0 / std::sqrt(2.0)));
  CHECK(interpolateLogLog(x, y, 0.5) == doctest::Approx(10.0));  // extended with slope -1
  CHECK(std::isnan(interpolateLogLog(x, y, 32.0)));
}

TEST_CASE("timeToReach interpolates the crossing in log-log") {
  ConvergenceRun run{"m", "random", 1};
  for (double t : {1.0, 2.0, 4.0, 8.0}) run.points.push_back({uint64_t(t), t, t, 1.0 / t, 1.0 / t});
  CHECK(timeToReach(run, 0.3) == doctest::Approx(1.0 / 0.3));
  CHECK(timeToReach(run, 2.0) == doctest::Approx(1.0));  // reached at the first point
  CHECK(std::isnan(timeToReach(run, 0.01)));
}

TEST_CASE("summarize: relMSE at equal time has its own best method") {
  const auto schedule = sppSchedule(4, 1024, 4);
  // As below, B has 2x A's MSE at equal time; its relMSE is 0.1 of its MSE against A's 2, so in relMSE B is
  // best and A is 2 / (0.1 * 2) = 10x behind.
  ConvergenceRun a = powerLawRun("A", 1, 1.0, 0.001, schedule);
  ConvergenceRun b = powerLawRun("B", 1, 0.5, 0.004, schedule);
  for (auto& p : b.points) p.relMse = 0.1 * p.mse;
  const ConvergenceSummary s = summarize(std::vector<ConvergenceRun>{a, b}, 1e-3);
  REQUIRE(s.rows.size() == 2);
  CHECK(s.rows[0].equalTimeRatio == doctest::Approx(1.0));
  CHECK(s.rows[1].equalTimeRatio == doctest::Approx(2.0));
  CHECK(s.rows[0].equalTimeRelMse == doctest::Approx(2.0 / 1024));
  CHECK(s.rows[0].equalTimeRelRatio == doctest::Approx(10.0));
  CHECK(s.rows[1].equalTimeRelRatio == doctest::Approx(1.0));
  CHECK(formatSummaryJson(s).find("\"equal_time_relmse_ratio\": 10") != std::string::npos);
  CHECK(formatSummaryTable(s).find("| 10.00 |") != std::string::npos);
}

TEST_CASE("summarize: equal-time ratio, slope, efficiency and time to target of two power laws") {
  const auto schedule = sppSchedule(4, 1024, 4);
  std::vector<ConvergenceRun> runs;
  // A: MSE 1/spp at 1 ms per spp; B: half the MSE per sample at 4x the time per sample, so at equal time B's
  // MSE is 0.5 * 4 = 2x A's. The seeds differ by a constant factor, to check mean and spread.
  for (uint32_t seed : {1u, 2u}) {
    runs.push_back(powerLawRun("A", seed, seed == 1 ? 1.0 : 1.2, 0.001, schedule));
    runs.push_back(powerLawRun("B", seed, seed == 1 ? 0.5 : 0.6, 0.004, schedule));
  }
  const ConvergenceSummary s = summarize(runs, 1e-3);
  REQUIRE(s.rows.size() == 2);
  const MethodSummary &a = s.rows[0], &b = s.rows[1];
  CHECK(a.method == "A");
  CHECK(a.seeds == 2);
  CHECK(a.spp == 1024);
  CHECK(s.equalTimeSeconds == doctest::Approx(1.024));  // A's final time, the shorter
  CHECK(a.equalTimeRatio == doctest::Approx(1.0));
  CHECK(b.equalTimeRatio == doctest::Approx(2.0));
  CHECK(a.slopeSpp == doctest::Approx(-1.0));
  CHECK(b.slopeTime == doctest::Approx(-1.0));
  CHECK(a.mse == doctest::Approx(1.1 / 1024));
  CHECK(a.mseLow == doctest::Approx(1.0 / 1024));
  CHECK(a.mseHigh == doctest::Approx(1.2 / 1024));
  // Efficiency 1/(MSE t) = 1/(c 0.001) for A: mean over seeds of 1000 and 833.3.
  CHECK(a.efficiency == doctest::Approx(0.5 * (1000.0 + 1000.0 / 1.2)));
  // relMSE = 2c/spp reaches 1e-3 at spp = 2000 c: beyond A's budget for both seeds.
  CHECK(std::isnan(a.timeToTarget));
  const ConvergenceSummary loose = summarize(runs, 4e-3);  // spp = 500 c: t = 0.5 and 0.6 s, median 0.55
  CHECK(loose.rows[0].timeToTarget == doctest::Approx(0.55).epsilon(0.02));

  const std::string table = formatSummaryTable(s);
  CHECK(table.find("| A | random | 2 | 1024 |") != std::string::npos);
  CHECK(formatSummaryJson(s).find("\"equal_time_ratio\": 2") != std::string::npos);
  CHECK(table.find("reference's own noise") == std::string::npos);  // an exact reference: nothing to say
  ConvergenceSummary noisy = s;
  noisy.referenceNoiseMse = 2e-6, noisy.referenceNoiseRelMse = 3e-7;
  CHECK(formatSummaryTable(noisy).find("net of the reference's own noise (MSE 2e-06, relMSE 3e-07)") !=
        std::string::npos);
  CHECK(formatSummaryJson(noisy).find("\"reference_noise_mse\": 2e-06") != std::string::npos);
  // Labels are escaped, and a figure that was never measured (NaN) is null and counted.
  ConvergenceSummary odd = s;
  odd.rows[0].method = "a \"quoted\" label";
  odd.rows[0].timeToTarget = std::numeric_limits<double>::quiet_NaN();
  std::size_t nulls = 0;
  const std::string json = formatSummaryJson(odd, &nulls);
  CHECK(json.find("\"method\": \"a \\\"quoted\\\" label\"") != std::string::npos);
  CHECK(json.find("\"time_to_target_s\": null") != std::string::npos);
  CHECK(nulls >= 1);
  CHECK_THROWS_AS(summarize(std::vector<ConvergenceRun>{{"empty", "random", 1}}, 1e-3), Error);
}

TEST_CASE("summarize: variance per sample, and as a multiple of the oracle's") {
  const auto schedule = sppSchedule(4, 256, 4);
  // MSE c / spp: MSE x spp is c (relMSE x spp 2c), mean over the seeds 1.0 and 1.2.
  const std::vector<ConvergenceRun> runs = {powerLawRun("A", 1, 1.0, 0.001, schedule),
                                            powerLawRun("A", 2, 1.2, 0.001, schedule)};
  ConvergenceSummary s = summarize(runs, 1e-3);
  CHECK(s.rows[0].mseTimesSpp == doctest::Approx(1.1));
  CHECK(s.rows[0].relMseTimesSpp == doctest::Approx(2.2));
  CHECK(std::isnan(s.rows[0].mseOverOracle));
  CHECK(formatSummaryTable(s).find("oracle") == std::string::npos);
  CHECK(formatSummaryJson(s).find("oracle") == std::string::npos);
  addOracle(s, 0.55, 0.2);
  CHECK(s.rows[0].mseOverOracle == doctest::Approx(2.0));
  CHECK(s.rows[0].relMseOverOracle == doctest::Approx(11.0));
  const std::string table = formatSummaryTable(s);
  CHECK(table.find("The oracle (the limit of a luminance pdf over the map's texels): MSE·spp 0.55") !=
        std::string::npos);
  CHECK(table.find("| MSE·spp ÷ oracle | relMSE·spp ÷ oracle |") != std::string::npos);
  CHECK(table.find("| 2 | 11 |") != std::string::npos);
  CHECK(formatSummaryJson(s).find("\"mse_spp_over_oracle\": 2.0") != std::string::npos);
  CHECK(table.find("estimated on") == std::string::npos);
  addOracle(s, 0.55, 0.2, 4);
  CHECK(formatSummaryTable(s).find("relMSE·spp 0.2, estimated on the centre pixel of every 4×4 block, where "
                                   "each method's is its first seed's final image's.") != std::string::npos);
}

TEST_CASE("familyZBound: the normal quantiles, Sidak-corrected") {
  CHECK(familyZBound(0.05, 1) == doctest::Approx(1.959964).epsilon(1e-5));
  CHECK(familyZBound(1e-3, 1) == doctest::Approx(3.290527).epsilon(1e-5));
  // 100 tests at a family rate of 0.05: each at 1 - 0.95^(1/100) = 5.128e-4, z = 3.4767.
  CHECK(familyZBound(0.05, 100) == doctest::Approx(3.4767).epsilon(1e-3));
  CHECK(familyZBound(1e-3, 1000) > familyZBound(1e-3, 10));
}

TEST_CASE("writeConvergenceCsv: one row per point, method labels quoted") {
  const auto path =
      std::filesystem::temp_directory_path() / ("iblx-csv-" + std::to_string(::getpid()) + ".csv");
  std::vector<ConvergenceRun> runs = {
      powerLawRun("mis(env-cdf+ggx-vndf, balance 0.5)", 3, 1.0, 0.01, {4, 8})};
  writeConvergenceCsv(path, runs);
  std::ifstream in(path);
  std::string header, first, second, extra;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  CHECK_FALSE(std::getline(in, extra));
  CHECK(header == "method,sequence,seed,pass,spp,gpu_s,wall_s,mse,relmse");
  CHECK(first.rfind("\"mis(env-cdf+ggx-vndf, balance 0.5)\",random,3,1,4,", 0) == 0);
  CHECK(second.find(",2,8,") != std::string::npos);
  std::filesystem::remove(path);
  CHECK_THROWS_AS(writeConvergenceCsv("/nonexistent-dir/x.csv", runs), Error);
}

}  // namespace iblx
