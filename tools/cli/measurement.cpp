// Flags, ground truth, progress and Ctrl-C of the measuring commands (tools/cli/measurement.h).
#include "tools/cli/measurement.h"

#include "tools/cli/command_support.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/render/reference.h"

#include <csignal>
#include <cmath>
#include <cstdio>

namespace iblx::cli {
namespace {

std::atomic<bool> gInterrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

int gGuardDepth = 0;  // guards alive (they nest: a measurement holds one around the ground truth's)

extern "C" void onInterrupt(int signal) {
  gInterrupted.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C (or SIGTERM) ends the process
}

}  // namespace

void addMeasurementFlags(ArgParser& p, MeasurementSpec& s) {
  p.value("--method", "NAME[:OPTION]...",
          "a method, repeatable (default: every method that applies). Options: an env or BRDF technique, "
          "balance|power, compensated, M=N, split=F; e.g. mis:env-hier:power, ris:M=32, brdf:brdf-tab",
          [&](const std::string& v) {
            parseMethodVariant(v);  // reports a bad word now, with the flag
            s.methods.push_back(v);
          });
  p.value("--seq", "NAME", "a sequence, repeatable (default: every sequence)",
          [&](const std::string& v) { s.sequences.push_back(findSequence(v).name); });
  p.value("--seeds", "K",
          "independent runs per method, seeds N..N+K-1 (default " + std::to_string(s.seeds) + ")",
          [&](const std::string& v) { s.seeds = parseUint("--seeds", v, 1, 1000); });
  p.value("--seed", "N", "first seed (default 1)",
          [&](const std::string& v) { s.firstSeed = parseUint("--seed", v, 0, 0xffffffffu - 1000); });
  p.value("--spp", "N",
          "samples per pixel at the first recorded point (default " + std::to_string(s.budget.firstSpp) + ")",
          [&](const std::string& v) { s.budget.firstSpp = parseUint("--spp", v, 1, 1u << 20); });
  p.value("--max-spp", "N",
          "budget: samples per pixel per run (default " + std::to_string(s.defaultMaxSpp) +
              "; with --time, unlimited)",
          [&](const std::string& v) { s.maxSpp = parseUint("--max-spp", v, 1, 1u << 30); });
  p.value("--time", "S", "budget: seconds of rendering per run (the run ends at the first point past S)",
          [&](const std::string& v) { s.budget.seconds = parseDouble("--time", v, 1e-3, 1e6); });
  p.value("--points-per-octave", "P", "recorded points per doubling of spp (default 4)",
          [&](const std::string& v) {
            s.budget.pointsPerOctave = int(parseUint("--points-per-octave", v, 1, 64));
          });
  p.value("--reference-file", "FILE",
          "the ground truth as an EXR of `iblx reference` (default: computed, cached)",
          [&](const std::string& v) { s.referenceFile = v; });
  p.toggle("--no-cache", "compute the ground truth even when the cache holds it, and do not store it",
           [&] { s.noCache = true; });
}

std::vector<ResolvedMethod> resolveMethods(const MeasurementSpec& spec, const BrdfInfo& brdf) {
  std::vector<MethodSpec> methods;
  if (spec.methods.empty())
    methods = defaultMethodSpecs(brdf);
  else
    for (const auto& m : spec.methods) methods.push_back(parseMethodVariant(m));
  std::vector<std::string> sequences = spec.sequences;
  if (sequences.empty())
    for (const auto& s : sequenceRegistry()) sequences.push_back(s.name);
  std::vector<ResolvedMethod> resolved;
  for (const auto& sequence : sequences)
    for (MethodSpec m : methods) {
      m.sequence = sequence;
      resolved.push_back(resolveMethodAndWarn(m, brdf));
    }
  return resolved;
}

ConvergenceBudget MeasurementSpec::finalBudget() const {
  ConvergenceBudget b = budget;
  // With --time alone, the limit is the 32-bit sample index.
  b.maxSpp = maxSpp ? *maxSpp : budget.seconds ? (std::uint64_t(1) << 32) - 4096 : defaultMaxSpp;
  if (b.firstSpp > b.maxSpp)
    throw Error("--spp " + std::to_string(b.firstSpp) + " exceeds --max-spp " + std::to_string(b.maxSpp));
  return b;
}

std::vector<std::uint32_t> seedList(const MeasurementSpec& spec) {
  std::vector<std::uint32_t> seeds;
  for (std::uint32_t i = 0; i < spec.seeds; ++i) seeds.push_back(spec.firstSeed + i);
  return seeds;
}

void addReferenceFlags(ArgParser& p, MeasurementSpec& s) {
  p.value(
      "--reference", "exact|mc",
      "exact (default): the convolution; mc: the mean of two runs of --reference-method, with its own error "
      "estimated from their difference and subtracted from every error",
      [&](const std::string& v) {
        if (v != "exact" && v != "mc") throw Error("--reference " + v + ": expected exact or mc");
        s.monteCarloReference = v == "mc";
      });
  p.value("--reference-time", "S", "--reference mc: seconds of rendering for both runs together (default 20)",
          [&](const std::string& v) { s.mc.seconds = parseDouble("--reference-time", v, 0.01, 1e6); });
  p.value("--reference-method", "NAME[:OPTION]...",
          "--reference mc: the method, as --method (default mis, with the sobol sequence)",
          [&](const std::string& v) {
            const std::string sequence = s.mc.method.sequence;
            s.mc.method = parseMethodVariant(v);
            s.mc.method.sequence = sequence;
          });
}

std::function<void(double)> interruptibleProgress(const InterruptGuard& guard, std::string label,
                                                  std::string subject) {
  return [&guard, label = std::move(label), subject = std::move(subject)](double f) {
    const std::string percent = std::to_string(int(100 * f)) + "%";
    if (guard.flag().load()) throw Interrupted(subject + " was " + percent + " done; nothing was written");
    progressLine(label + " " + percent);
  };
}

ObtainedReference obtainReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const HardCase* hardCase, const MeasurementSpec& spec) {
  if (!spec.referenceFile.empty())
    return {readReferenceFile(spec.referenceFile, scene.gbuffer.width, scene.gbuffer.height, "the scene's"),
            {},
            "read from " + spec.referenceFile.string()};
  if (hardCase && hardCase->exactReference) {
    std::fprintf(stderr, "reference: closed form of hard case %s\n", hardCase->name.c_str());
    return {hardCase->exactReference(scene), {}, "closed form of hard case " + hardCase->name};
  }
  // Ctrl-C abandons the ground truth between dispatches (exit 130); nothing partial is cached or written.
  InterruptGuard interrupt;
  const auto progress = interruptibleProgress(interrupt, "reference", "the ground truth");
  const std::filesystem::path cacheDir = spec.noCache ? std::filesystem::path() : defaultCacheDir();
  bool fromCache = false;
  ReferenceImage ref;
  std::string kind = "the exact convolution";
  if (spec.monteCarloReference) {
    McReferenceOptions options = spec.mc;
    options.progress = progress;
    ref = cachedMcReference(context, compiler, scene, cacheDir, options, &fromCache);
    char text[200];
    std::snprintf(text, sizeof text,
                  "Monte Carlo: 2 runs of %s, %g s in all; its own MSE %.3g, relMSE %.3g "
                  "(subtracted from every error)",
                  resolveMethod(options.method, *scene.brdf).label().c_str(), options.seconds, ref.noise.mse,
                  ref.noise.relMse);
    kind = text;
  } else {
    ReferenceOptions options;
    options.progress = progress;
    ref = cachedReference(context, compiler, scene, cacheDir, options, &fromCache);
  }
  endProgressLine();
  if (fromCache)
    std::fprintf(stderr, "reference: %s, from the cache (%s)\n", kind.c_str(),
                 defaultCacheDir().string().c_str());
  else
    std::fprintf(stderr, "reference: %s, computed in %.2f s\n", kind.c_str(), ref.seconds);
  return {std::move(ref.rgb), ref.noise, kind};
}

InterruptGuard::InterruptGuard() {
  if (gGuardDepth++ > 0) return;  // the outer guard's flag and handlers stay
  gInterrupted.store(false);
  std::signal(SIGINT, onInterrupt);
  // A job scheduler (Slurm's scancel, a time limit, a preemption) stops work with SIGTERM: the same as
  // Ctrl-C.
  std::signal(SIGTERM, onInterrupt);
}

InterruptGuard::~InterruptGuard() {
  if (--gGuardDepth > 0) return;
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

const std::atomic<bool>& InterruptGuard::flag() const {
  return gInterrupted;
}

void showProgress(const ConvergenceProgress& p) {
  char line[256];
  std::snprintf(line, sizeof line, "[%zu/%zu] %s seed %u: %llu spp, %.2f s, relMSE %.3g", p.run + 1, p.runs,
                p.label.c_str(), p.seed, static_cast<unsigned long long>(p.point.spp), p.point.wallSeconds,
                p.point.relMse);
  progressLine(line);
}

}  // namespace iblx::cli
