// The equal-time loss in factors (engine/analysis/loss_decomposition.h).
#include "engine/analysis/loss_decomposition.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>

namespace iblx {

MedianCurve medianCurve(std::span<const ConvergenceRun> seeds, const std::string& what) {
  MedianCurve curve;
  if (seeds.empty()) throw Error(what + ": no runs");
  std::size_t passes = seeds.front().points.size();
  for (const auto& run : seeds) passes = std::min(passes, run.points.size());
  for (std::size_t p = 0; p < passes; ++p) {
    std::vector<double> mse, gpu;
    for (const auto& run : seeds) {
      const ConvergencePoint& point = run.points[p];
      if (std::isfinite(point.mse) && point.mse > 0) mse.push_back(point.mse);
      gpu.push_back(point.gpuSeconds);
    }
    if (mse.empty()) continue;
    curve.spp.push_back(double(seeds.front().points[p].spp));
    curve.mse.push_back(median(mse));
    curve.gpuSeconds.push_back(median(gpu));
  }
  if (curve.spp.size() < 3)
    throw Error(what + ": " + std::to_string(curve.spp.size()) + " points with an error, 3 needed");
  const std::size_t start = fitStart(curve);
  curve.slope = fitLogLogSlope(std::span(curve.spp).subspan(start), std::span(curve.mse).subspan(start));
  return curve;
}

std::size_t fitStart(const MedianCurve& curve) {
  return curve.spp.size() >= 6 ? 2 : 0;
}

double varianceConstant(const MedianCurve& curve) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = fitStart(curve); i < curve.spp.size(); ++i, ++count)
    sum += std::log(curve.mse[i] * curve.spp[i]);
  return std::exp(sum / double(count));
}

double mseAtSpp(const MedianCurve& c, double n) {
  const std::size_t last = c.spp.size() - 1;
  if (n <= c.spp[0]) return c.mse[0] * std::exp(c.slope * std::log(n / c.spp[0]));
  for (std::size_t i = 1; i <= last; ++i)
    if (n <= c.spp[i]) {
      const double t = std::log(n / c.spp[i - 1]) / std::log(c.spp[i] / c.spp[i - 1]);
      return std::exp(std::log(c.mse[i - 1]) + t * std::log(c.mse[i] / c.mse[i - 1]));
    }
  return c.mse[last] * std::exp(c.slope * std::log(n / c.spp[last]));
}

double sppAtTime(const MedianCurve& c, double t) {
  const std::size_t last = c.spp.size() - 1;
  if (t <= c.gpuSeconds[0]) return c.spp[0] * t / c.gpuSeconds[0];
  for (std::size_t i = 1; i <= last; ++i)
    if (t <= c.gpuSeconds[i])
      return c.spp[i - 1] +
             (c.spp[i] - c.spp[i - 1]) * (t - c.gpuSeconds[i - 1]) / (c.gpuSeconds[i] - c.gpuSeconds[i - 1]);
  return c.spp[last] * t / c.gpuSeconds[last];
}

LossDecomposition decomposeLoss(std::span<const SamplerRuns> samplers, std::size_t baseline,
                                std::size_t objectPixels) {
  std::vector<MedianCurve> random, sobol;
  for (const auto& s : samplers) {
    random.push_back(medianCurve(s.random, s.name + "/random"));
    sobol.push_back(medianCurve(s.sobol, s.name + "/sobol"));
  }
  LossDecomposition d;
  d.equalTimeSeconds = sobol.front().gpuSeconds.back();
  for (const auto& c : sobol) d.equalTimeSeconds = std::min(d.equalTimeSeconds, c.gpuSeconds.back());
  const MedianCurve& hs = sobol[baseline];
  const double ch = varianceConstant(random[baseline]);
  d.baselineSpp = sppAtTime(hs, d.equalTimeSeconds);
  d.baselineSlope = hs.slope;
  const double mh = mseAtSpp(hs, d.baselineSpp);
  for (std::size_t s = 0; s < samplers.size(); ++s) {
    LossFactors f;
    f.name = samplers[s].name;
    f.c = varianceConstant(random[s]);
    f.cRatio = f.c / ch;
    f.spp = sppAtTime(sobol[s], d.equalTimeSeconds);
    const double m = mseAtSpp(sobol[s], f.spp);
    f.q = m * f.spp / f.c;
    f.slopeRandom = random[s].slope;
    f.slopeSobol = sobol[s].slope;
    f.nsPerSample = sobol[s].gpuSeconds.back() /
                    (sobol[s].spp.back() * double(std::max<std::size_t>(objectPixels, 1))) * 1e9;
    f.ratio = m / mh;
    // R = pdf x QMC x cost x residual; pdf x QMC = M_s(N_s) / M_h(N_s) whatever the fits.
    f.pdf = f.cRatio;
    f.qmc = f.q / (mseAtSpp(hs, f.spp) * f.spp / ch);
    f.cost = std::exp(-d.baselineSlope * std::log(d.baselineSpp / f.spp));
    f.residual = f.ratio / (f.pdf * f.qmc * f.cost);
    d.rows.push_back(f);
  }
  return d;
}

}  // namespace iblx
