// `iblx reference`: the ground truth of a scene (docs/DESIGN.md §4) written as a linear EXR.
#include "engine/core/file_io.h"
#include "engine/io/image_write.h"
#include "engine/render/reference.h"
#include "engine/render/scene_gpu.h"
#include "engine/scene/brdf_params.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <cstdio>

namespace iblx::cli {

int cmdReference(const Args& args) {
  RenderSpec spec;
  spec.out = "reference.exr";
  ArgParser parser("reference");
  addSceneFlags(parser, spec);
  addDeviceFlags(parser, spec);
  parser.value("--out", "FILE", "output .exr (default reference.exr)",
               [&](const std::string& v) { spec.out = v; });
  if (parser.parseOrShowHelp(args)) return 0;
  const DeviceTableLimit tableLimit = deviceTableLimit(spec.device);
  LoadedBrdf brdf = loadBrdfArgument(spec.scene.brdf);
  resolveParams(*brdf.info, spec.scene.params);
  checkImagePath("--out", spec.out, true);
  VulkanContext context({spec.device, spec.validation ? Validation::On : Validation::Auto});
  const Scene scene = loadSceneFor(context, spec.scene, std::move(brdf));
  ShaderCompiler compiler;
  ReferenceOptions options;
  options.progress = [](double f) { progressLine("reference " + std::to_string(int(100 * f)) + "%"); };
  const ReferenceImage ref = computeReference(context, compiler, scene, options);
  endProgressLine();
  writeImage(spec.out, ref.width, ref.height, ref.rgb);
  std::printf("reference of %dx%d (env %dx%d, fine quadrature %d) in %.2f s on %s; wrote %s\n", ref.width,
              ref.height, scene.env.width, scene.env.height, ref.fineSubdivisions, ref.seconds,
              context.deviceName().c_str(), spec.out.c_str());
  return 0;
}

}  // namespace iblx::cli
