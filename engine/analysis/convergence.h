// Speed against error (docs/DESIGN.md §7): the measurements of `iblx converge` (error after each pass of each
// method, sequence and seed) and what is derived from them: the sample schedule, log-log fits and
// interpolation, the summary table (time to a target error, equal-time MSE ratio, slope, efficiency, spread
// over seeds), CSV. Plain CPU code on plain values, so every figure can be unit-tested on synthetic curves.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace iblx {

inline constexpr double kNotReached = std::numeric_limits<double>::quiet_NaN();

// The error of one image, after `spp` samples per pixel and `seconds` of rendering (cumulative).
struct ConvergencePoint {
  std::uint64_t spp = 0;
  double gpuSeconds = 0.0;   // the passes' dispatches (timestamp queries)
  double wallSeconds = 0.0;  // record + submit + wait of those passes: the time axis
  double mse = 0.0, relMse = 0.0;
};

// One method with one sequence and one seed, from its first pass to the end of its budget.
struct ConvergenceRun {
  std::string method;    // e.g. "mis(env-cdf+ggx-vndf, balance 0.5)"
  std::string sequence;  // e.g. "sobol"
  std::uint32_t seed = 0;
  double setupSeconds = 0.0;  // table builds + compile + upload, not on the time axis
  std::vector<ConvergencePoint> points;
  // The final image's checks: |z| of its mean signed error (engine/render/metrics.h) and NaN/Inf estimates.
  double finalMaxAbsZ = 0.0;
  std::uint32_t nonFiniteSamples = 0;
  bool finiteImage = true;
};

// Cumulative spp at which error is recorded: `first`, then `pointsPerOctave` points per doubling (evenly
// spaced in log spp, so log-log plots and fits weigh every scale alike), strictly increasing, up to `max`.
std::vector<std::uint64_t> sppSchedule(std::uint64_t first, std::uint64_t max, int pointsPerOctave);

// The median of `values` (the mean of the middle two for an even count); NaN when empty.
double median(std::vector<double> values);

// Least-squares slope of log y against log x over the points with x, y > 0 and finite; NaN with fewer than 3.
double fitLogLogSlope(std::span<const double> x, std::span<const double> y);

// y at `at` on the piecewise-linear curve through (log x, log y); x increasing. Before the first point the
// curve is extended with slope -1 (an unbiased estimator's MSE ~ 1/N), after the last it is NaN.
double interpolateLogLog(std::span<const double> x, std::span<const double> y, double at);

// The wall time at which a run's relMSE first falls to `target` (log-log interpolation between the
// bracketing points); kNotReached when it never does.
double timeToReach(const ConvergenceRun& run, double target);

// |z| bound for `tests` two-sided z-tests with family-wise false-alarm rate `alpha` (Sidak correction):
// erfc(z / sqrt 2) = 1 - (1 - alpha)^(1 / tests).
double familyZBound(double alpha, std::size_t tests);

struct MethodSummary {
  std::string method, sequence;
  int seeds = 0;
  std::uint64_t spp = 0;                   // final spp (median over seeds)
  double seconds = 0.0;                    // final wall time (median over seeds)
  double setupSeconds = 0.0;               // median over seeds
  double mse = 0.0, relMse = 0.0;          // final, mean over seeds
  double mseLow = 0.0, mseHigh = 0.0;      // final, min and max over seeds
  double slopeSpp = 0.0, slopeTime = 0.0;  // log-log slope of MSE against spp / time (median over seeds)
  double timeToTarget = kNotReached;       // median over seeds (unreached seeds count as infinite)
  double equalTimeMse = 0.0;               // mean over seeds of the MSE at the common time
  double equalTimeRatio = 0.0;             // equalTimeMse / the best method's
  double equalTimeRelMse = 0.0;            // the same for relMSE
  double equalTimeRelRatio = 0.0;          // equalTimeRelMse / the best method's (best in relMSE)
  double efficiency = 0.0;                 // 1 / (MSE * time) at the end, mean over seeds
  // MSE x spp and relMSE x spp at the end, mean over seeds: the variance per sample for i.i.d. samples.
  double mseTimesSpp = 0.0, relMseTimesSpp = 0.0;
  // Those over the oracle's (engine/render/oracle.h); NaN when the summary has no oracle.
  double mseOverOracle = std::numeric_limits<double>::quiet_NaN();
  double relMseOverOracle = std::numeric_limits<double>::quiet_NaN();
  double samplesPerSecond = 0.0;       // spp per second of wall time (per pixel), median over seeds
  double maxAbsZ = 0.0;                // worst final |z| over seeds
  std::uint32_t nonFiniteSamples = 0;  // summed over seeds
  bool finite = true;
};

struct ConvergenceSummary {
  double targetRelMse = 0.0;
  double equalTimeSeconds = 0.0;  // the common time: the end of the shortest run
  // A Monte Carlo reference's own expected MSE and relMSE, already subtracted from every error (0: exact).
  double referenceNoiseMse = 0.0, referenceNoiseRelMse = 0.0;
  std::vector<MethodSummary> rows;  // in the order the runs first appear
  // The oracle's variance per sample over the object pixels (engine/render/oracle.h); 0: not computed.
  double oracleMseTimesSpp = 0.0, oracleRelMseTimesSpp = 0.0;
  int oraclePixelStride = 1;  // > 1: estimated on the centre pixel of every stride x stride block
};

// Groups runs by (method, sequence). Throws iblx::Error when there is no run with a point.
ConvergenceSummary summarize(std::span<const ConvergenceRun> runs, double targetRelMse);
// Records the oracle's MSE x spp and relMSE x spp in `summary` and each method's as a multiple of them.
void addOracle(ConvergenceSummary& summary, double mseTimesSpp, double relMseTimesSpp, int pixelStride = 1);

// A table of text cells, written as Markdown (terminal, docs) or HTML (report pages) from one definition.
struct TextTable {
  std::vector<std::string> headers;
  std::vector<bool> rightAligned;  // per column: numbers
  std::vector<std::vector<std::string>> rows;
};
std::string formatMarkdownTable(const TextTable& table);

// The summary's table: one row per method and sequence.
TextTable summaryTable(const ConvergenceSummary& summary);
// The summary as a Markdown table (with the common time and the target), for the terminal and docs.
std::string formatSummaryTable(const ConvergenceSummary& summary);

// One row per (method, sequence, seed, point): method,sequence,seed,pass,spp,gpu_s,wall_s,mse,relmse.
void writeConvergenceCsv(const std::filesystem::path& path, std::span<const ConvergenceRun> runs);

// The summary rows as JSON objects, one per line (engine/core/json_output.h: figures that are NaN, such as a
// target never reached, are null and counted in nonFinite).
std::string formatSummaryJson(const ConvergenceSummary& summary, std::size_t* nonFinite = nullptr);

}  // namespace iblx
