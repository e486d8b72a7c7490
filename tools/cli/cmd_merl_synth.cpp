// `iblx merl-synth`: tabulates a BRDF into MERL's .binary layout (engine/io/merl.h), evaluating its GLSL part
// on the GPU at the centre of every bin, so tests and benchmarks have measured-layout materials with known
// answers (real MERL files are 35 MB each and cannot ship with the project).
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/io/merl.h"
#include "engine/render/brdf_tabulation.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <chrono>
#include <cstdio>

namespace iblx::cli {

int cmdMerlSynth(const Args& args) {
  RenderSpec spec;
  std::string out = "material.binary";
  MerlSynthOptions options;
  bool seedGiven = false;
  ArgParser parser("merl-synth");
  parser.value("--brdf", "NAME", "BRDF to tabulate: any built-in (default ggx)",
               [&](const std::string& v) { spec.scene.brdf = v; });
  addParamFlag(parser, spec.scene.params);
  parser.value("--out", "FILE", "output .binary (default material.binary)",
               [&](const std::string& v) { out = v; });
  parser.toggle(
      "--invalid-below-horizon",
      "write -1 (MERL's 'no data') into bins whose centre lies below the horizon, as measured files do",
      [&] { options.invalidBelowHorizon = true; });
  parser.value("--invalid-fraction", "F", "also write -1 into this fraction of random bins (default 0)",
               [&](const std::string& v) {
                 options.invalidFraction = parseDouble("--invalid-fraction", v, 0.0, 1.0);
               });
  parser.value("--seed", "N", "seed of --invalid-fraction (default 1)", [&](const std::string& v) {
    options.seed = parseUint("--seed", v, 0, 0xffffffffu);
    seedGiven = true;
  });
  addDeviceFlags(parser, spec);
  if (parser.parseOrShowHelp(args)) return 0;
  if (seedGiven && options.invalidFraction == 0.0) warn("--seed is ignored without --invalid-fraction");
  checkTableOutput(out, ".binary", "MERL");
  const DeviceTableLimit tableLimit = deviceTableLimit(spec.device);
  LoadedBrdf loaded = loadBrdfArgument(spec.scene.brdf);
  if (loaded.measured)
    throw Error("--brdf " + spec.scene.brdf +
                ": merl-synth tabulates a built-in BRDF or a .brdf file, not a MERL file");
  const std::string brdfName = loaded.info->name;

  const auto start = std::chrono::steady_clock::now();
  const Scene scene = tabulationScene(spec.scene, std::move(loaded));
  VulkanContext context({spec.device, spec.validation ? Validation::On : Validation::Auto});
  ShaderCompiler compiler;
  const MerlSynthResult table = tabulateMerl(context, compiler, scene, options);
  writeMerl(out, table.values);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("wrote %s: %s tabulated at %zu bin centres, %zu bins marked invalid (-1), %.2f s\n",
              out.c_str(), brdfName.c_str(), kMerlBins, table.invalidBins, seconds);
  return 0;
}

}  // namespace iblx::cli
