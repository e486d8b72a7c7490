// The measuring loop of `iblx converge` (engine/render/convergence_runner.h).
#include "engine/render/convergence_runner.h"

#include "engine/core/error.h"
#include "engine/render/metrics.h"
#include "engine/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

namespace iblx {
namespace {

// One dispatch renders at most this many samples per pixel (the renderer's --spp cap): far from GPU
// watchdog limits at any image size.
constexpr std::uint64_t kMaxSppPerDispatch = 4096;

}  // namespace

ConvergenceResult runConvergence(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                 std::span<const float> reference, std::span<const ResolvedMethod> methods,
                                 std::span<const std::uint32_t> seeds, const ConvergenceBudget& budget,
                                 const std::function<void(const ConvergenceProgress&)>& progress,
                                 const std::atomic<bool>* stop, const ReferenceNoise& noise) {
  const std::vector<std::uint64_t> schedule =
      sppSchedule(budget.firstSpp, budget.maxSpp, budget.pointsPerOctave);
  ConvergenceResult result;
  const std::size_t runs = methods.size() * seeds.size();
  for (const ResolvedMethod& method : methods) {
    const std::string name = method.techniqueLabel(), sequence = method.sequence->name;
    for (std::uint32_t seed : seeds) {
      if (stop && stop->load()) return result.interrupted = true, result;
      ConvergenceRun run{name, sequence, seed};
      std::optional<Renderer> made;
      try {
        made.emplace(context, compiler, scene, method, seed);
      } catch (const DeviceLimitError& e) {
        result.skipped.push_back({name, sequence, e.what()});
        break;  // the other seeds would need the same tables
      }
      Renderer& renderer = *made;
      run.setupSeconds = renderer.setupSeconds();
      // A warm-up pass, then a fresh start: first-use costs (the driver compiling the pipeline on its first
      // dispatch) stay off the time axis.
      renderer.runPass(1);
      renderer.restart(seed);
      ConvergencePoint point;
      for (std::uint64_t target : schedule) {
        while (renderer.samplesPerPixel() < target) {
          const auto spp = std::uint32_t(std::min(kMaxSppPerDispatch, target - renderer.samplesPerPixel()));
          const PassTiming t = renderer.runPass(spp);
          point.gpuSeconds += t.gpuSeconds;
          point.wallSeconds += t.wallSeconds;
        }
        point.spp = renderer.samplesPerPixel();
        const ErrorMetrics e = compareToReference(scene.gbuffer, renderer.meanRgb(), reference);
        // Below the noise of a Monte Carlo reference an error is not resolved: NaN (not drawn, null in JSON,
        // "—" in the tables), not a number near or below zero.
        const double nan = std::numeric_limits<double>::quiet_NaN();
        point.mse = noise.mse > 0.0 && e.mse <= noise.mse ? nan : e.mse - noise.mse;
        point.relMse = noise.relMse > 0.0 && e.relMse <= noise.relMse ? nan : e.relMse - noise.relMse;
        run.points.push_back(point);
        if (progress) progress({result.runs.size(), runs, name + "/" + sequence, seed, point});
        if (budget.seconds && point.wallSeconds >= *budget.seconds) break;
        if (stop && stop->load()) {
          result.interrupted = true;
          break;
        }
      }
      const auto mean = renderer.meanRgb();
      run.finalMaxAbsZ = zTestMeanError(scene.gbuffer, mean, renderer.varianceRgb(),
                                        double(renderer.samplesPerPixel()), reference)
                             .maxAbsZ();
      run.nonFiniteSamples = renderer.nonFiniteSamples();
      run.finiteImage = std::all_of(mean.begin(), mean.end(), [](float v) { return std::isfinite(v); });
      if (seed == seeds.front()) result.images.push_back({name, sequence, mean, point});
      result.runs.push_back(std::move(run));
      if (result.interrupted) return result;
    }
  }
  return result;
}

}  // namespace iblx
