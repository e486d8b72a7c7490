// What `iblx converge` and `iblx study` share: the flags that define one measured scene (the scene, or a hard
// case, with the method, sequence, seed, budget and ground-truth flags), checked before anything heavy, and
// the scene they load.
#pragma once

#include "engine/render/hard_cases.h"
#include "engine/scene/scene.h"
#include "engine/vk/context.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/measurement.h"

#include <string>

namespace iblx::cli {

struct ConvergeSceneFlags {
  RenderSpec render;
  MeasurementSpec spec;
  std::string caseName;  // --case: a scene of the hard-case suite
  bool sizeGiven = false;

  const HardCase* hardCase() const { return caseName.empty() ? nullptr : &findHardCase(caseName); }
};

// Registers the scene flags, --case, the measurement flags and the reference flags into `flags`.
void addConvergeSceneFlags(ArgParser& parser, ConvergeSceneFlags& flags);
// After parsing: the default size when --size was not given (a hard case keeps its own then).
void finishConvergeSceneFlags(ConvergeSceneFlags& flags);

// Loads the BRDF and checks its parameters and the methods asked for against it (an asked-for method that
// does not apply is an error), without a device: everything a user can get wrong, before anything heavy.
LoadedBrdf checkConvergeScene(const ConvergeSceneFlags& flags);

// The scene on `context`, from the BRDF checkConvergeScene loaded.
Scene loadConvergeScene(const VulkanContext& context, const ConvergeSceneFlags& flags, LoadedBrdf brdf);

// "case NAME, BRDF, env WxH, WxH": the title of the scene's reports.
std::string convergeSceneTitle(const ConvergeSceneFlags& flags, const Scene& scene);

}  // namespace iblx::cli
