// `iblx bench`: samples per second of every method (and sequence) on one scene, medians over timed passes.
#include "engine/analysis/convergence.h"
#include "engine/core/json_output.h"
#include "engine/render/renderer.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <algorithm>
#include <map>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace iblx::cli {

namespace {

// The flags of `iblx bench`.
struct BenchOptions {
  RenderSpec render;                            // the scene, --spp, --passes, --json and the device flags
  std::vector<std::string> sequences, methods;  // empty methods: every method
  uint32_t repeat = 1;
};

// Declares the flags and parses `args`; none when --help was answered.
std::optional<BenchOptions> parseBenchOptions(const Args& args) {
  BenchOptions options;
  RenderSpec& spec = options.render;
  spec.samplesPerPass = 64;
  spec.passes = 7;
  ArgParser parser("bench");
  addSceneFlags(parser, spec);
  addDeviceFlags(parser, spec);
  parser.value("--spp", "N", "samples per pixel per pass (default 64)",
               [&](const std::string& v) { spec.samplesPerPass = parseUint("--spp", v, 1, 4096); });
  parser.value("--passes", "N", "timed passes per method, after one warm-up pass (default 7)",
               [&](const std::string& v) { spec.passes = parseUint("--passes", v, 1, 10000); });
  parser.value("--seq", "NAME", "only this sequence (default: every sequence)",
               [&](const std::string& v) { options.sequences.push_back(v); });
  parser.value("--method", "NAME", "only this method (repeatable; default: every method)",
               [&](const std::string& v) { options.methods.push_back(findMethod(v).name); });
  parser.value("--repeat", "N",
               "measure every method N times, in rounds, and report medians (of rates, and of the per-round "
               "ratio to uniform; default 1)",
               [&](const std::string& v) { options.repeat = parseUint("--repeat", v, 1, 1000); });
  parser.toggle("--json", "one JSON object per line instead of the table", [&] { spec.json = true; });
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (options.sequences.empty())
    for (const auto& s : sequenceRegistry()) options.sequences.push_back(s.name);
  return options;
}

// One (sequence, method): its median rate of each round.
struct BenchRow {
  std::string label;
  std::vector<double> gpu, wall;
};

// Every (sequence, method) asked for, resolved against the scene's BRDF (warning of flags a method ignores).
std::vector<ResolvedMethod> resolveBenchMethods(const BenchOptions& options, const BrdfInfo& brdf) {
  std::vector<ResolvedMethod> resolved;
  for (const auto& sequence : options.sequences)
    for (const auto& m : methodRegistry()) {
      if (!options.methods.empty() &&
          std::find(options.methods.begin(), options.methods.end(), m.name) == options.methods.end())
        continue;
      MethodSpec methodSpec;
      methodSpec.method = m.name;
      methodSpec.sequence = sequence;
      resolved.push_back(resolveMethodAndWarn(methodSpec, brdf));
    }
  return resolved;
}

// Every (sequence, method) is measured `repeat` times in rounds, so slow phases of a noisy machine spread
// over all methods; each measurement is the median over timed passes, and the figure is the median over
// rounds (of the rate, and of the ratio to uniform within a round).
std::vector<BenchRow> measureRows(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const std::vector<ResolvedMethod>& resolved, const BenchOptions& options) {
  const RenderSpec& spec = options.render;
  const uint32_t repeat = options.repeat;
  std::vector<BenchRow> rows;
  for (const ResolvedMethod& method : resolved) rows.push_back({method.label(), {}, {}});
  const double samples = double(scene.gbuffer.objectPixelCount()) * spec.samplesPerPass;
  for (uint32_t round = 0; round < repeat; ++round)
    for (size_t r = 0; r < rows.size(); ++r) {
      Renderer renderer(context, compiler, scene, resolved[r], 1);
      renderer.runPass(
          spec.samplesPerPass);  // warm-up: first-use costs (pipeline JIT) stay out of the figures
      std::vector<double> gpuRates, wallRates;
      for (uint32_t i = 0; i < spec.passes; ++i) {
        const PassTiming t = renderer.runPass(spec.samplesPerPass);
        if (t.gpuSeconds > 0) gpuRates.push_back(samples / t.gpuSeconds);
        wallRates.push_back(samples / t.wallSeconds);
      }
      rows[r].gpu.push_back(gpuRates.empty() ? 0.0 : median(gpuRates));  // 0: no timestamps
      rows[r].wall.push_back(median(wallRates));
      if (repeat > 1)
        progressLine("round " + std::to_string(round + 1) + "/" + std::to_string(repeat) + ": " +
                     rows[r].label);
    }
  endProgressLine();
  return rows;
}

// One line per row: the rates and the slowdown against uniform (a JSON object with --json).
void printRows(const std::vector<BenchRow>& rows, const std::vector<ResolvedMethod>& resolved,
               const BenchOptions& options) {
  const uint32_t repeat = options.repeat;
  // "vs uniform" is the median over rounds of the ratio within each round: uniform and the method ran close
  // together, so a slow phase of the machine cancels out of the ratio instead of landing on one of them.
  std::map<std::string, std::size_t> uniformRow;  // per sequence
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (resolved[r].method->name == "uniform") uniformRow[resolved[r].sequence->name] = r;
  const auto roundRates = [](const BenchRow& row) { return row.gpu.front() > 0 ? row.gpu : row.wall; };
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const BenchRow& row = rows[r];
    const double gpuRate = median(row.gpu), wallRate = median(row.wall);
    double ratio = 0.0;
    if (const auto u = uniformRow.find(resolved[r].sequence->name); u != uniformRow.end()) {
      const std::vector<double> uniformRates = roundRates(rows[u->second]), rates = roundRates(row);
      std::vector<double> ratios;
      for (std::size_t k = 0; k < rates.size(); ++k)
        if (rates[k] > 0) ratios.push_back(uniformRates[k] / rates[k]);
      if (!ratios.empty()) ratio = median(ratios);
    }
    const auto [lo, hi] = std::minmax_element(row.gpu.begin(), row.gpu.end());
    if (options.render.json)
      printJsonLine({{"method", row.label},
                     {"gpu_samples_per_s", gpuRate},
                     {"samples_per_s", wallRate},
                     {"gpu_min", *lo},
                     {"gpu_max", *hi},
                     {"rounds", repeat},
                     {"slowdown_vs_uniform", ratio}});
    else
      std::printf("%-44s %14.2f %14.2f %9.2fx   (GPU %.2f-%.2f over %u rounds)\n", row.label.c_str(),
                  gpuRate * 1e-6, wallRate * 1e-6, ratio, *lo * 1e-6, *hi * 1e-6, repeat);
  }
}

int runBench(const BenchOptions& options) {
  const RenderSpec& spec = options.render;
  VulkanContext context({spec.device, spec.validation ? Validation::On : Validation::Auto});
  const Scene scene = loadSceneFor(context, spec.scene);
  ShaderCompiler compiler;
  const double objectPixels = double(scene.gbuffer.objectPixelCount());
  if (!spec.json)
    std::printf(
        "iblx bench: %s, %dx%d (%.0f object pixels), env %dx%d, BRDF %s, %u spp/pass, median of %u passes\n"
        "%-44s %14s %14s %10s\n",
        context.deviceName().c_str(), scene.gbuffer.width, scene.gbuffer.height, objectPixels,
        scene.env.width, scene.env.height, scene.brdf->name.c_str(), spec.samplesPerPass, spec.passes,
        "method", "Msamples/s GPU", "Msamples/s wall", "vs uniform");
  const std::vector<ResolvedMethod> resolved = resolveBenchMethods(options, *scene.brdf);
  const std::vector<BenchRow> rows = measureRows(context, compiler, scene, resolved, options);
  printRows(rows, resolved, options);
  return 0;
}

}  // namespace

int cmdBench(const Args& args) {
  if (const std::optional<BenchOptions> options = parseBenchOptions(args)) return runBench(*options);
  return 0;
}

}  // namespace iblx::cli
