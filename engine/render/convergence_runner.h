// Runs methods on one scene and records their error after each pass (docs/DESIGN.md §7): the measuring loop of
// `iblx converge` and `iblx hardcases`. The figures derived from the records are
// engine/analysis/convergence.h.
#pragma once

#include "engine/analysis/convergence.h"
#include "engine/render/reference.h"
#include "engine/scene/scene.h"
#include "engine/vk/context.h"
#include "engine/vk/shader_compiler.h"

#include <atomic>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace iblx {

struct ConvergenceBudget {
  std::uint64_t firstSpp = 4;     // the first recorded point
  std::uint64_t maxSpp = 1024;    // stop after this many samples per pixel ...
  std::optional<double> seconds;  // ... or once this much wall time of rendering has passed
  int pointsPerOctave = 4;        // recorded points per doubling of spp (engine/analysis sppSchedule)
};

struct ConvergenceProgress {
  std::size_t run = 0, runs = 0;  // this run's index and the number of runs
  std::string label;              // method/sequence
  std::uint32_t seed = 0;
  ConvergencePoint point;
};

struct ConvergenceImage {
  std::string method, sequence;
  std::vector<float> rgb;  // the first seed's final image
  ConvergencePoint point;  // where it was taken
};

struct SkippedMethod {
  std::string method, sequence;
  std::string reason;  // the DeviceLimitError's message
};

struct ConvergenceResult {
  std::vector<ConvergenceRun> runs;  // method-major, then seed
  std::vector<ConvergenceImage> images;
  std::vector<SkippedMethod> skipped;  // methods whose data exceed the device's limits
  bool interrupted = false;
};

// Every method with every seed, each from an empty accumulation to the end of the budget, recording error
// against `reference` (object pixels) at the budget's schedule. A method whose tables exceed the device's
// limits (DeviceLimitError) is listed in `skipped` and the others go on. `stop` (e.g. set by Ctrl-C) ends the
// measurement after the current point; what was recorded is kept. `noise`, the reference's own expected error
// (a Monte Carlo reference), is subtracted from every MSE and relMSE recorded, so that they estimate the
// error against the truth; an error at or below the reference's noise is not resolved and recorded as NaN.
ConvergenceResult runConvergence(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                 std::span<const float> reference, std::span<const ResolvedMethod> methods,
                                 std::span<const std::uint32_t> seeds, const ConvergenceBudget& budget,
                                 const std::function<void(const ConvergenceProgress&)>& progress = {},
                                 const std::atomic<bool>* stop = nullptr, const ReferenceNoise& noise = {});

}  // namespace iblx
