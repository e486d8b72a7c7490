// `iblx bench`: samples per second of every method (and sequence) on one scene, medians over timed passes.
#include "engine/render/renderer.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"

#include <algorithm>
#include <cstdio>

namespace iblx::cli {
namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

int cmdBench(const Args& args) {
  RenderSpec spec;
  spec.samplesPerPass = 64;
  spec.passes = 7;
  ArgParser parser("bench");
  bool help = false;
  std::vector<std::string> sequences, methods;
  addSceneFlags(parser, spec);
  addDeviceFlags(parser, spec);
  parser.value("--spp", "N", "samples per pixel per pass (default 64)",
               [&](const std::string& v) { spec.samplesPerPass = parseUint("--spp", v, 1, 4096); });
  parser.value("--passes", "N", "timed passes per method, after one warm-up pass (default 7)",
               [&](const std::string& v) { spec.passes = parseUint("--passes", v, 1, 10000); });
  parser.value("--seq", "NAME", "only this sequence (default: every sequence)",
               [&](const std::string& v) { sequences.push_back(v); });
  parser.value("--method", "NAME", "only this method (repeatable; default: every method)",
               [&](const std::string& v) { methods.push_back(findMethod(v).name); });
  parser.toggle("--json", "one JSON object per line instead of the table", [&] { spec.json = true; });
  parser.toggle("--help", "show this help", [&] { help = true; });
  parser.parse(args);
  if (help) {
    std::fputs(parser.usage().c_str(), stdout);
    return 0;
  }
  if (sequences.empty())
    for (const auto& s : sequenceRegistry()) sequences.push_back(s.name);
  const Scene scene = loadScene(spec.scene);
  VulkanContext context({spec.device, spec.validation ? Validation::On : Validation::Auto});
  ShaderCompiler compiler;
  const double objectPixels = double(scene.gbuffer.objectPixelCount());
  if (!spec.json)
    std::printf("iblx bench: %s, %dx%d (%.0f object pixels), env %dx%d, BRDF %s, %u spp/pass, median of %u passes\n"
                "%-44s %14s %14s %10s\n",
                context.deviceName().c_str(), scene.gbuffer.width, scene.gbuffer.height, objectPixels, scene.env.width,
                scene.env.height, scene.brdf->name.c_str(), spec.samplesPerPass, spec.passes, "method", "Msamples/s GPU",
                "Msamples/s wall", "vs uniform");
  for (const auto& sequence : sequences) {
    double uniformRate = 0.0;
    for (const auto& m : methodRegistry()) {
      if (!methods.empty() && std::find(methods.begin(), methods.end(), m.name) == methods.end()) continue;
      MethodSpec methodSpec;
      methodSpec.method = m.name;
      methodSpec.sequence = sequence;
      const ResolvedMethod method = resolveMethod(methodSpec, *scene.brdf);
      Renderer renderer(context, compiler, scene, method, 1);
      renderer.runPass(spec.samplesPerPass);  // warm-up: first-use costs stay out of the figures
      std::vector<double> gpuRates, wallRates;
      const double samples = objectPixels * spec.samplesPerPass;
      for (uint32_t i = 0; i < spec.passes; ++i) {
        const PassTiming t = renderer.runPass(spec.samplesPerPass);
        if (t.gpuSeconds > 0) gpuRates.push_back(samples / t.gpuSeconds);
        wallRates.push_back(samples / t.wallSeconds);
      }
      const double gpuRate = median(gpuRates), wallRate = median(wallRates);
      const double rate = gpuRate > 0 ? gpuRate : wallRate;
      if (m.name == "uniform") uniformRate = rate;
      const double ratio = uniformRate > 0 ? uniformRate / rate : 0.0;
      if (spec.json)
        std::printf("{\"method\": \"%s\", \"gpu_samples_per_s\": %.1f, \"samples_per_s\": %.1f, "
                    "\"slowdown_vs_uniform\": %.3f}\n",
                    method.label().c_str(), gpuRate, wallRate, ratio);
      else
        std::printf("%-44s %14.2f %14.2f %9.2fx\n", method.label().c_str(), gpuRate * 1e-6, wallRate * 1e-6, ratio);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace iblx::cli
