// Speed-against-error figures (engine/analysis/convergence.h).
#include "engine/analysis/convergence.h"

#include "engine/core/csv.h"
#include "engine/core/error.h"
#include "engine/core/json_output.h"
#include "engine/core/file_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace iblx {
namespace {

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? kNotReached : sum / double(v.size());
}

std::vector<double> column(const ConvergenceRun& run, double ConvergencePoint::*field) {
  std::vector<double> values;
  for (const auto& p : run.points) values.push_back(p.*field);
  return values;
}

std::vector<double> sppColumn(const ConvergenceRun& run) {
  std::vector<double> values;
  for (const auto& p : run.points) values.push_back(double(p.spp));
  return values;
}

// Fits skip the first points: with few samples the error of a heavy-tailed estimator is not yet in its
// asymptotic 1/N regime.
template <typename T>
std::span<const T> tail(const std::vector<T>& v) {
  const std::size_t skip = v.size() >= 6 ? 2 : 0;
  return std::span<const T>(v).subspan(skip);
}

std::string formatSeconds(double s) {
  if (!std::isfinite(s)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, s < 10 ? "%.3g s" : "%.1f s", s);
  return b;
}

std::string formatNumber(double v, const char* format = "%.3g") {
  if (!std::isfinite(v)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return kNotReached;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<std::uint64_t> sppSchedule(std::uint64_t first, std::uint64_t max, int pointsPerOctave) {
  if (first == 0 || pointsPerOctave < 1)
    throw Error("spp schedule: first spp and points per octave must be >= 1");
  if (first > max)
    throw Error("spp schedule: the first point (" + std::to_string(first) + " spp) exceeds the budget (" +
                std::to_string(max) + " spp)");
  std::vector<std::uint64_t> schedule;
  for (int k = 0;; ++k) {
    const double target = double(first) * std::exp2(double(k) / pointsPerOctave);
    auto spp = std::uint64_t(std::llround(target));
    if (!schedule.empty()) spp = std::max(spp, schedule.back() + 1);
    if (spp > max) break;
    schedule.push_back(spp);
  }
  if (schedule.back() < max) schedule.push_back(max);
  return schedule;
}

double fitLogLogSlope(std::span<const double> x, std::span<const double> y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    if (!(x[i] > 0 && y[i] > 0 && std::isfinite(x[i]) && std::isfinite(y[i]))) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, ++n;
  }
  const double denominator = n * sxx - sx * sx;
  if (n < 3 || !(std::abs(denominator) > 1e-12)) return kNotReached;
  return (n * sxy - sx * sy) / denominator;
}

double interpolateLogLog(std::span<const double> x, std::span<const double> y, double at) {
  if (x.empty() || x.size() != y.size() || !(at > 0)) return kNotReached;
  if (at <= x[0]) return y[0] * x[0] / at;
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (at > x[i]) continue;
    if (!(x[i - 1] > 0 && y[i - 1] > 0 && y[i] > 0)) return y[i];
    const double t = std::log(at / x[i - 1]) / std::log(x[i] / x[i - 1]);
    return std::exp(std::log(y[i - 1]) + t * std::log(y[i] / y[i - 1]));
  }
  return kNotReached;
}

double timeToReach(const ConvergenceRun& run, double target) {
  for (std::size_t i = 0; i < run.points.size(); ++i) {
    const auto& p = run.points[i];
    if (p.relMse > target) continue;
    if (i == 0 || !(p.relMse > 0)) return p.wallSeconds;
    const auto& q = run.points[i - 1];
    // Linear in log-log between the bracketing points.
    const double t = std::log(target / q.relMse) / std::log(p.relMse / q.relMse);
    return std::exp(std::log(q.wallSeconds) + t * std::log(p.wallSeconds / q.wallSeconds));
  }
  return kNotReached;
}

double familyZBound(double alpha, std::size_t tests) {
  const double perTest = -std::expm1(std::log1p(-alpha) / double(std::max<std::size_t>(tests, 1)));
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {  // bisection: erfc is decreasing
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > perTest ? lo : hi) = mid;
  }
  return hi;
}

ConvergenceSummary summarize(std::span<const ConvergenceRun> runs, double targetRelMse) {
  std::vector<std::pair<std::string, std::string>> order;
  std::map<std::pair<std::string, std::string>, std::vector<const ConvergenceRun*>> groups;
  for (const auto& run : runs) {
    if (run.points.empty()) continue;
    const auto key = std::pair{run.method, run.sequence};
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&run);
  }
  if (order.empty()) throw Error("no measurements to summarize (every run was empty)");

  ConvergenceSummary summary;
  summary.targetRelMse = targetRelMse;
  summary.equalTimeSeconds = std::numeric_limits<double>::infinity();
  for (const auto& key : order) {
    const auto& group = groups[key];
    MethodSummary row;
    row.method = key.first;
    row.sequence = key.second;
    row.seeds = int(group.size());
    std::vector<double> spp, seconds, setup, mse, relMse, slopeSpp, slopeTime, toTarget, efficiency, rate;
    std::vector<double> msePerSample, relMsePerSample;
    for (const ConvergenceRun* run : group) {
      const auto& last = run->points.back();
      spp.push_back(double(last.spp));
      seconds.push_back(last.wallSeconds);
      setup.push_back(run->setupSeconds);
      mse.push_back(last.mse);
      relMse.push_back(last.relMse);
      const auto errors = column(*run, &ConvergencePoint::mse);
      slopeSpp.push_back(fitLogLogSlope(tail(sppColumn(*run)), tail(errors)));
      slopeTime.push_back(fitLogLogSlope(tail(column(*run, &ConvergencePoint::wallSeconds)), tail(errors)));
      const double t = timeToReach(*run, targetRelMse);
      toTarget.push_back(std::isnan(t) ? std::numeric_limits<double>::infinity() : t);
      efficiency.push_back(last.mse > 0 && last.wallSeconds > 0 ? 1.0 / (last.mse * last.wallSeconds)
                                                                : std::numeric_limits<double>::infinity());
      rate.push_back(last.wallSeconds > 0 ? double(last.spp) / last.wallSeconds : 0.0);
      msePerSample.push_back(last.mse * double(last.spp));
      relMsePerSample.push_back(last.relMse * double(last.spp));
      row.maxAbsZ = std::max(row.maxAbsZ, run->finalMaxAbsZ);
      row.nonFiniteSamples += run->nonFiniteSamples;
      row.finite = row.finite && run->finiteImage;
    }
    row.spp = std::uint64_t(median(spp));
    row.seconds = median(seconds);
    row.setupSeconds = median(setup);
    row.mse = mean(mse);
    row.relMse = mean(relMse);
    row.mseLow = *std::min_element(mse.begin(), mse.end());
    row.mseHigh = *std::max_element(mse.begin(), mse.end());
    row.slopeSpp = median(slopeSpp);
    row.slopeTime = median(slopeTime);
    row.timeToTarget = median(toTarget);
    if (std::isinf(row.timeToTarget)) row.timeToTarget = kNotReached;
    row.efficiency = mean(efficiency);
    row.samplesPerSecond = median(rate);
    row.mseTimesSpp = mean(msePerSample);
    row.relMseTimesSpp = mean(relMsePerSample);
    // The common time is the shortest run's end, so every run has a measurement on both sides of it.
    for (double s : seconds) summary.equalTimeSeconds = std::min(summary.equalTimeSeconds, s);
    summary.rows.push_back(row);
  }
  // MSE and relMSE of every method at the common time, and their ratios to the best there.
  double best = std::numeric_limits<double>::infinity(), bestRel = best;
  for (std::size_t r = 0; r < order.size(); ++r) {
    std::vector<double> mseAt, relMseAt;
    for (const ConvergenceRun* run : groups[order[r]]) {
      const auto seconds = column(*run, &ConvergencePoint::wallSeconds);
      mseAt.push_back(
          interpolateLogLog(seconds, column(*run, &ConvergencePoint::mse), summary.equalTimeSeconds));
      relMseAt.push_back(
          interpolateLogLog(seconds, column(*run, &ConvergencePoint::relMse), summary.equalTimeSeconds));
    }
    MethodSummary& row = summary.rows[r];
    row.equalTimeMse = mean(mseAt);
    row.equalTimeRelMse = mean(relMseAt);
    if (row.equalTimeMse > 0) best = std::min(best, row.equalTimeMse);
    if (row.equalTimeRelMse > 0) bestRel = std::min(bestRel, row.equalTimeRelMse);
  }
  for (auto& row : summary.rows) {
    row.equalTimeRatio = row.equalTimeMse / best;
    row.equalTimeRelRatio = row.equalTimeRelMse / bestRel;
  }
  return summary;
}

void addOracle(ConvergenceSummary& summary, double mseTimesSpp, double relMseTimesSpp, int pixelStride) {
  summary.oracleMseTimesSpp = mseTimesSpp;
  summary.oracleRelMseTimesSpp = relMseTimesSpp;
  summary.oraclePixelStride = pixelStride;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  for (auto& row : summary.rows) {
    row.mseOverOracle = mseTimesSpp > 0.0 ? row.mseTimesSpp / mseTimesSpp : kNaN;
    row.relMseOverOracle = relMseTimesSpp > 0.0 ? row.relMseTimesSpp / relMseTimesSpp : kNaN;
  }
}

std::string formatMarkdownTable(const TextTable& table) {
  std::ostringstream s;
  s << "|";
  for (const auto& h : table.headers) s << " " << h << " |";
  s << "\n|";
  for (std::size_t c = 0; c < table.headers.size(); ++c)
    s << (c < table.rightAligned.size() && table.rightAligned[c] ? "---:|" : "---|");
  s << "\n";
  for (const auto& row : table.rows) {
    s << "|";
    for (const auto& cell : row) s << " " << cell << " |";
    s << "\n";
  }
  return s.str();
}

TextTable summaryTable(const ConvergenceSummary& summary) {
  TextTable t;
  t.headers = {"method",
               "seq",
               "seeds",
               "spp",
               "time",
               "setup",
               "MSE (min–max over seeds)",
               "relMSE",
               "slope vs spp",
               "time to target",
               "MSE at equal time",
               "× best",
               "efficiency 1/(MSE·s)",
               "relMSE at equal time × best"};
  t.rightAligned = {false, false, true, true, true, true, false, true, true, true, true, true, true, true};
  for (const auto& r : summary.rows)
    t.rows.push_back({r.method, r.sequence, std::to_string(r.seeds), std::to_string(r.spp),
                      formatSeconds(r.seconds), formatSeconds(r.setupSeconds),
                      formatNumber(r.mse) + " (" + formatNumber(r.mseLow, "%.2g") + "–" +
                          formatNumber(r.mseHigh, "%.2g") + ")",
                      formatNumber(r.relMse), formatNumber(r.slopeSpp, "%.2f"), formatSeconds(r.timeToTarget),
                      formatNumber(r.equalTimeMse), formatNumber(r.equalTimeRatio, "%.2f"),
                      formatNumber(r.efficiency), formatNumber(r.equalTimeRelRatio, "%.2f")});
  if (summary.oracleMseTimesSpp > 0.0) {
    t.headers.insert(t.headers.end(), {"MSE·spp ÷ oracle", "relMSE·spp ÷ oracle"});
    t.rightAligned.insert(t.rightAligned.end(), {true, true});
    for (std::size_t i = 0; i < summary.rows.size(); ++i)
      t.rows[i].insert(t.rows[i].end(), {formatNumber(summary.rows[i].mseOverOracle, "%.3g"),
                                         formatNumber(summary.rows[i].relMseOverOracle, "%.3g")});
  }
  return t;
}

std::string formatSummaryTable(const ConvergenceSummary& summary) {
  const std::string noise = summary.referenceNoiseMse > 0.0
                                ? " Errors are net of the reference's own noise (MSE " +
                                      formatNumber(summary.referenceNoiseMse) + ", relMSE " +
                                      formatNumber(summary.referenceNoiseRelMse) + "), subtracted."
                                : "";
  const std::string oracle =
      summary.oracleMseTimesSpp > 0.0
          ? " The oracle (the limit of a luminance pdf over the map's texels): MSE·spp " +
                formatNumber(summary.oracleMseTimesSpp) + ", relMSE·spp " +
                formatNumber(summary.oracleRelMseTimesSpp) +
                (summary.oraclePixelStride > 1
                     ? ", estimated on the centre pixel of every " +
                           std::to_string(summary.oraclePixelStride) + "×" +
                           std::to_string(summary.oraclePixelStride) +
                           " block, where each method's is its first seed's final image's."
                     : ".")
          : "";
  return "Equal time: " + formatSeconds(summary.equalTimeSeconds) +
         " of rendering (the shortest run); target relMSE " + formatNumber(summary.targetRelMse) + "." +
         noise + oracle + "\n\n" + formatMarkdownTable(summaryTable(summary));
}

std::string formatSummaryJson(const ConvergenceSummary& summary, std::size_t* nonFinite) {
  std::string lines;
  for (const auto& r : summary.rows) {
    JsonObject row = {{"method", r.method},
                      {"sequence", r.sequence},
                      {"seeds", r.seeds},
                      {"spp", r.spp},
                      {"wall_s", r.seconds},
                      {"setup_s", r.setupSeconds},
                      {"mse", r.mse},
                      {"mse_min", r.mseLow},
                      {"mse_max", r.mseHigh},
                      {"relmse", r.relMse},
                      {"slope_spp", r.slopeSpp},
                      {"slope_time", r.slopeTime},
                      {"target_relmse", summary.targetRelMse},
                      {"time_to_target_s", r.timeToTarget},
                      {"equal_time_s", summary.equalTimeSeconds},
                      {"equal_time_mse", r.equalTimeMse},
                      {"equal_time_ratio", r.equalTimeRatio},
                      {"equal_time_relmse", r.equalTimeRelMse},
                      {"equal_time_relmse_ratio", r.equalTimeRelRatio},
                      {"efficiency", r.efficiency},
                      {"max_abs_z", r.maxAbsZ},
                      {"reference_noise_mse", summary.referenceNoiseMse},
                      {"reference_noise_relmse", summary.referenceNoiseRelMse},
                      {"non_finite", r.nonFiniteSamples},
                      {"mse_spp", r.mseTimesSpp},
                      {"relmse_spp", r.relMseTimesSpp}};
    if (summary.oracleMseTimesSpp > 0.0) {
      row["oracle_mse_spp"] = summary.oracleMseTimesSpp;
      row["oracle_relmse_spp"] = summary.oracleRelMseTimesSpp;
      row["mse_spp_over_oracle"] = r.mseOverOracle;
      row["relmse_spp_over_oracle"] = r.relMseOverOracle;
    }
    lines += formatJson(row, nonFinite) + "\n";
  }
  return lines;
}

void writeConvergenceCsv(const std::filesystem::path& path, std::span<const ConvergenceRun> runs) {
  AtomicOutput output(path);
  std::ofstream& out = output.stream();
  out << "method,sequence,seed,pass,spp,gpu_s,wall_s,mse,relmse\n";
  char line[160];
  for (const auto& run : runs)
    for (std::size_t i = 0; i < run.points.size(); ++i) {
      const auto& p = run.points[i];
      std::snprintf(line, sizeof line, ",%s,%u,%zu,%llu,%.6f,%.6f,%.9g,%.9g\n", run.sequence.c_str(),
                    run.seed, i + 1, static_cast<unsigned long long>(p.spp), p.gpuSeconds, p.wallSeconds,
                    p.mse, p.relMse);
      out << csvQuoted(run.method) << line;  // a method label holds commas
    }
  output.commit();
}

}  // namespace iblx
