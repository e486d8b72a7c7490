// `iblx render`: progressive render of one scene with one method; writes the image, prints speed (and error).
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json_output.h"
#include "engine/core/log.h"
#include "engine/io/brdf_file.h"
#include "engine/io/image_write.h"
#include "engine/render/metrics.h"
#include "engine/render/reference.h"
#include "engine/render/renderer.h"
#include "engine/scene/brdf_params.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"
#include "tools/cli/measurement.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace iblx::cli {

namespace {

// Declares the flags and parses `args`; none when --help or --list-methods was answered.
std::optional<RenderSpec> parseRenderOptions(const Args& args) {
  RenderSpec spec;
  spec.out = "render.png";
  ArgParser parser("render");
  addSceneFlags(parser, spec);
  addMethodFlags(parser, spec);
  addRunFlags(parser, spec);
  addDeviceFlags(parser, spec);
  parser.value(
      "--save-bparam", "FILE",
      "also write the BRDF's parameter values (defaults, .bparam and --param) as a BRDF Explorer .bparam "
      "file; the BRDF must come from a file",
      [&](const std::string& v) { spec.saveBparam = v; });
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (spec.listMethods) {
    printRegistry(spec);
    return std::nullopt;
  }
  return spec;
}

// Checks the parameters, the method and the output against `brdf` (writing --save-bparam once its values are
// known) and returns the method.
ResolvedMethod checkRenderInputs(const RenderSpec& spec, const LoadedBrdf& brdf) {
  const ParamValues params = resolveParams(*brdf.info, spec.scene.params);
  if (!spec.saveBparam.empty()) {
    if (brdf.file.empty())
      throw Error("--save-bparam: BRDF '" + brdf.info->name +
                  "' is built in; a .bparam names a .brdf or .binary file");
    if (spec.saveBparam.extension() != ".bparam")
      throw Error("--save-bparam " + spec.saveBparam.string() + ": the file name must end in .bparam");
    writeBparam(spec.saveBparam, std::filesystem::weakly_canonical(brdf.file), brdf.info->params, params);
    std::printf("wrote %s\n", spec.saveBparam.string().c_str());
  }
  ResolvedMethod method = resolveMethodAndWarn(spec.method, *brdf.info);
  checkImagePath("--out", spec.out);
  if (!spec.timeBudgetSeconds && uint64_t(spec.passes) * spec.samplesPerPass > 0xffffffffull)
    throw Error("--passes x --spp exceeds 2^32 samples per pixel (the sample index would wrap)");
  return method;
}

// What the passes took.
struct PassTotals {
  double gpuSeconds = 0.0, renderWallSeconds = 0.0;
  uint32_t passes = 0;
};

// Runs passes until --passes (or --time) is reached or Ctrl-C sets `interrupt`, with a progress line.
PassTotals runPasses(Renderer& renderer, const RenderSpec& spec, const InterruptGuard& interrupt) {
  PassTotals totals;
  for (;;) {
    if (interrupt.flag().load()) break;
    const bool done = spec.timeBudgetSeconds ? totals.renderWallSeconds >= *spec.timeBudgetSeconds
                                             : totals.passes >= spec.passes;
    if (done) break;
    if (renderer.samplesPerPixel() + spec.samplesPerPass > 0xffffffffull) {
      warn("--time stopped at 2^32 samples per pixel (the sample index would wrap)");
      break;
    }
    const PassTiming t = renderer.runPass(spec.samplesPerPass);
    totals.gpuSeconds += t.gpuSeconds;
    totals.renderWallSeconds += t.wallSeconds;
    ++totals.passes;
    char line[160];
    std::snprintf(line, sizeof line, "pass %u, %llu spp, %.2f s", totals.passes,
                  static_cast<unsigned long long>(renderer.samplesPerPixel()), totals.renderWallSeconds);
    progressLine(line);
  }
  endProgressLine();
  return totals;
}

// The error against the ground truth, when there is one: --reference-file's, or the one --reference computes.
struct ReferenceError {
  std::optional<ErrorMetrics> metrics;
  bool fromFile = false;          // --reference-file
  double referenceSeconds = 0.0;  // computing the ground truth (0 for a file)
};

// The speed (and error) line, or with --json one JSON object.
void printRenderResult(const RenderSpec& spec, const ResolvedMethod& method, const VulkanContext& context,
                       const Scene& scene, const Renderer& renderer, const PassTotals& totals,
                       const ReferenceError& error, double totalWall) {
  const double samples = double(scene.gbuffer.objectPixelCount()) * double(renderer.samplesPerPixel());
  const double samplesPerSecond = totals.renderWallSeconds > 0 ? samples / totals.renderWallSeconds : 0.0;
  const double gpuSamplesPerSecond = totals.gpuSeconds > 0 ? samples / totals.gpuSeconds : 0.0;
  if (spec.json) {
    JsonObject line = {{"method", method.label()},
                       {"device", context.deviceName()},
                       {"width", scene.gbuffer.width},
                       {"height", scene.gbuffer.height},
                       {"object_pixels", scene.gbuffer.objectPixelCount()},
                       {"spp", renderer.samplesPerPixel()},
                       {"passes", totals.passes},
                       {"gpu_s", totals.gpuSeconds},
                       {"wall_s", totals.renderWallSeconds},
                       {"setup_s", renderer.setupSeconds()},
                       {"total_wall_s", totalWall},
                       {"samples_per_s", samplesPerSecond},
                       {"gpu_samples_per_s", gpuSamplesPerSecond},
                       {"non_finite", renderer.nonFiniteSamples()}};
    if (error.metrics) {
      line["mse"] = error.metrics->mse;
      line["relmse"] = error.metrics->relMse;
      line["mean_signed_error"] = error.metrics->meanSignedError;
    }
    if (error.metrics && !error.fromFile) line["reference_s"] = error.referenceSeconds;
    line["out"] = spec.out;
    printJsonLine(line);
  } else {
    std::printf(
        "%s on %s: %llu spp in %u passes, %.3f s wall (%.3f s GPU), %.2f M samples/s (%.2f M/s GPU)\n",
        method.label().c_str(), context.deviceName().c_str(),
        static_cast<unsigned long long>(renderer.samplesPerPixel()), totals.passes, totals.renderWallSeconds,
        totals.gpuSeconds, samplesPerSecond * 1e-6, gpuSamplesPerSecond * 1e-6);
    if (error.metrics) {
      char computed[48];
      std::snprintf(computed, sizeof computed, "computed in %.2f s", error.referenceSeconds);
      const std::string source = error.fromFile ? spec.referenceFile.string() : computed;
      std::printf("error vs reference (%s): MSE %.4g, relMSE %.4g, mean signed error %.3g\n", source.c_str(),
                  error.metrics->mse, error.metrics->relMse, error.metrics->meanSignedError);
    }
    std::printf("wrote %s (total %.2f s)\n", spec.out.c_str(), totalWall);
  }
}

int runRender(const RenderSpec& spec) {
  // Everything a user can get wrong is checked before the map is loaded and anything is rendered.
  const DeviceTableLimit tableLimit = deviceTableLimit(spec.device);
  LoadedBrdf brdf = loadBrdfArgument(spec.scene.brdf);
  const ResolvedMethod method = checkRenderInputs(spec, brdf);

  const auto start = std::chrono::steady_clock::now();
  // A stored ground truth is read before anything heavy: its errors must not wait for the map and the render.
  std::optional<std::vector<float>> referenceImage;
  if (!spec.referenceFile.empty()) {
    if (spec.reference) warn("--reference is ignored: --reference-file gives the ground truth");
    referenceImage = readReferenceFile(spec.referenceFile, spec.scene.width, spec.scene.height, "--size");
  }
  VulkanContext context({spec.device, spec.validation ? Validation::On : Validation::Auto});
  const Scene scene = loadSceneFor(context, spec.scene, std::move(brdf));
  ShaderCompiler compiler;
  Renderer renderer(context, compiler, scene, method, spec.seed);

  // Ctrl-C ends the passes; the image accumulated so far is still written, and the exit status is 130.
  InterruptGuard interrupt;
  const PassTotals totals = runPasses(renderer, spec, interrupt);
  const bool interrupted = interrupt.flag().load();
  if (interrupted && totals.passes == 0) throw Interrupted("before the first pass; nothing was written");
  if (interrupted)
    warn("interrupted after " + std::to_string(totals.passes) +
         " passes: writing the image accumulated so far");
  const auto rgb = renderer.meanRgb();
  if (const uint32_t bad = renderer.nonFiniteSamples()) warn(nonFiniteEstimatesMessage(bad, spec.scene.brdf));

  ReferenceError error;
  if (referenceImage) {
    error.metrics = compareToReference(scene.gbuffer, rgb, *referenceImage);
    error.fromFile = true;
  } else if (spec.reference && !interrupted) {
    ReferenceOptions options;
    options.progress = [&interrupt](double f) {
      if (interrupt.flag().load())
        throw Interrupted("the ground truth was not finished; nothing was written");
      progressLine("reference " + std::to_string(int(100 * f)) + "%");
    };
    const ReferenceImage ref = computeReference(context, compiler, scene, options);
    endProgressLine();
    error.referenceSeconds = ref.seconds;
    error.metrics = compareToReference(scene.gbuffer, rgb, ref.rgb);
  }
  writeImage(spec.out, scene.gbuffer.width, scene.gbuffer.height, rgb,
             resolveDisplay(spec.display, rgb, scene.gbuffer.objectMask()));

  const double totalWall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  printRenderResult(spec, method, context, scene, renderer, totals, error, totalWall);
  return interrupted ? 130 : 0;
}

}  // namespace

int cmdRender(const Args& args) {
  if (const std::optional<RenderSpec> spec = parseRenderOptions(args)) return runRender(*spec);
  return 0;
}

}  // namespace iblx::cli
