// The measured scene of `converge` and `study` (tools/cli/converge_scene.h).
#include "tools/cli/converge_scene.h"

#include "tools/cli/command_support.h"

#include "engine/core/file_io.h"
#include "engine/render/scene_gpu.h"
#include "engine/scene/brdf_params.h"

namespace iblx::cli {

void addConvergeSceneFlags(ArgParser& parser, ConvergeSceneFlags& flags) {
  addSceneFlags(parser, flags.render);
  parser.value("--case", "NAME",
               "a scene of the hard-case suite instead of --env/--brdf/... (see `iblx hardcases --list`)",
               [&](const std::string& v) { flags.caseName = findHardCase(v).name; });
  addMeasurementFlags(parser, flags.spec);
  addReferenceFlags(parser, flags.spec);
  // Whether --size was given, in whatever spelling the parser accepts: no size until it sets one.
  flags.render.scene.width = flags.render.scene.height = 0;
}

void finishConvergeSceneFlags(ConvergeSceneFlags& flags) {
  flags.sizeGiven = flags.render.scene.width != 0;
  if (!flags.sizeGiven)
    flags.render.scene.width = SceneSpec{}.width, flags.render.scene.height = SceneSpec{}.height;
}

LoadedBrdf checkConvergeScene(const ConvergeSceneFlags& flags) {
  const HardCase* hardCase = flags.hardCase();
  flags.spec.finalBudget();  // --spp beyond --max-spp
  const DeviceTableLimit tableLimit = deviceTableLimit(flags.render.device);
  LoadedBrdf brdf = loadBrdfArgument(hardCase ? hardCase->scene.brdf : flags.render.scene.brdf);
  resolveParams(*brdf.info, hardCase ? hardCase->scene.params : flags.render.scene.params);
  resolveMethods(flags.spec, *brdf.info);  // an asked-for method that does not apply to the BRDF
  return brdf;
}

Scene loadConvergeScene(const VulkanContext& context, const ConvergeSceneFlags& flags, LoadedBrdf brdf) {
  const HardCase* hardCase = flags.hardCase();
  if (!hardCase) return loadSceneFor(context, flags.render.scene, std::move(brdf));
  HardCase sized = *hardCase;
  if (flags.sizeGiven) {  // a hard case's own size fits every device
    checkImageFitsDevice(context, flags.render.scene.width, flags.render.scene.height);
    sized.scene.width = flags.render.scene.width, sized.scene.height = flags.render.scene.height;
  }
  return makeHardCaseScene(sized);
}

std::string convergeSceneTitle(const ConvergeSceneFlags& flags, const Scene& scene) {
  return (flags.caseName.empty() ? std::string() : "case " + flags.caseName + ", ") + scene.brdf->name +
         ", env " + std::to_string(scene.env.width) + "x" + std::to_string(scene.env.height) + ", " +
         std::to_string(scene.gbuffer.width) + "x" + std::to_string(scene.gbuffer.height);
}

}  // namespace iblx::cli
