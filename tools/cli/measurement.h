// What `iblx converge` and `iblx hardcases` share: the method / sequence / seed / budget flags, the ground
// truth (computed and cached, closed-form for hard cases that have one, or read from a file), the progress
// line and Ctrl-C handling.
#pragma once

#include "engine/render/convergence_runner.h"
#include "engine/render/hard_cases.h"
#include "engine/render/mc_reference.h"
#include "tools/cli/cli_options.h"

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>
#include <functional>
#include <vector>

namespace iblx::cli {

struct MeasurementSpec {
  std::vector<std::string>
      methods;  // NAME[:OPTION]... (parseMethodVariant); empty: every method that applies
  std::vector<std::string> sequences;  // empty: every sequence
  std::uint32_t seeds = 3, firstSeed = 1;
  ConvergenceBudget budget;             // maxSpp: see finalBudget
  std::optional<std::uint64_t> maxSpp;  // --max-spp
  std::uint64_t defaultMaxSpp = 1024;   // without --max-spp and --time
  std::filesystem::path referenceFile;
  bool noCache = false;
  bool monteCarloReference = false;  // --reference mc
  McReferenceOptions mc;             // --reference-time, --reference-method
  // The budget with --max-spp's default: defaultMaxSpp, or unlimited with --time.
  ConvergenceBudget finalBudget() const;
};

// The help texts give the defaults held in `spec` when it is registered.
void addMeasurementFlags(ArgParser& parser, MeasurementSpec& spec);

// Every requested (method, sequence), resolved against the BRDF (an explicit method that does not apply is an
// error; defaults that do not apply are skipped).
std::vector<ResolvedMethod> resolveMethods(const MeasurementSpec& spec, const BrdfInfo& brdf);
std::vector<std::uint32_t> seedList(const MeasurementSpec& spec);

// --reference exact|mc, --reference-time and --reference-method (converge).
void addReferenceFlags(ArgParser& parser, MeasurementSpec& spec);

struct ObtainedReference {
  std::vector<float> rgb;
  ReferenceNoise noise;     // 0 unless Monte Carlo
  std::string description;  // where it came from, for reports
};
// The ground truth of `scene`: --reference-file, else the hard case's closed form, else the convolution (or
// with --reference mc the Monte Carlo reference) through the on-disk cache (unless --no-cache). Prints where
// it came from.
ObtainedReference obtainReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const HardCase* hardCase, const MeasurementSpec& spec);

// While alive, Ctrl-C or SIGTERM sets flag() instead of ending the process (a second one ends it). Guards
// nest: an inner one (the ground truth's, inside a measurement's) shares the outer one's flag.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  const std::atomic<bool>& flag() const;
};

// The progress of a long computation as "LABEL N%" (progressLine); once Ctrl-C or SIGTERM set `guard`'s flag
// it throws Interrupted ("SUBJECT was N% done; nothing was written"), abandoning the computation between
// dispatches.
std::function<void(double)> interruptibleProgress(const InterruptGuard& guard, std::string label,
                                                  std::string subject);

// The progress line of a measurement (stderr, terminals only).
void showProgress(const ConvergenceProgress& p);

}  // namespace iblx::cli
