// The optimal-transport env techniques' GPU tables: env-ot-fwd (the forward quad mesh, inverted per sample by
// quadtree point location) and env-ot-inv (the tabulated inverse, with the forward map as its guess). The map
// is solved (engine/sampling/ot_solver.h) for the environment with its sun texels split off
// (engine/sampling/ot_sun.h); both parts read the sun's tables too.
#pragma once

#include "engine/io/env_image.h"
#include "engine/sampling/ot_solver.h"
#include "engine/sampling/ot_sun.h"
#include "engine/sampling/technique_data.h"

#include <vector>

namespace iblx {

// Grid of the OT map: 256 or, for smaller maps, the map's height (no finer than its rows), at least 32;
// IBLX_OT_SIZE overrides it (benchmarks). Throws iblx::Error for an IBLX_OT_SIZE outside [8, 2048].
int otGridSize(const EnvImage& image);

// The OT techniques' map: the sun texels' excess split off (ot_sun.h) and the map solved (or read from the
// cache) for the rest at otGridSize, before untangling. The samplers build their tables from it; so do the
// offline diagnostics of their pdfs (engine/sampling/env_ot_diagnostics.h). Throws iblx::Error when the map
// has a folded quad; warns when it did not converge (the samplers stay exact, only less efficient).
struct EnvOtMaps {
  std::vector<double> weights;  // the texel sampling weights (texelSamplingWeights)
  OtSunSplit sun;
  OtMap map;
};
EnvOtMaps solveEnvOtMaps(const EnvImage& image);

// Tables of shaders/lib/quad_grid_map.glsl (quadMapVertex, quadMapPiece, quadMapNode, quadMapLeafCell) and
// shaders/lib/ot_sun.glsl (otSunTexel, otSunCdf, otSunRowFirst); env-ot-inv adds otForwardVertex and
// otForwardPiece. Throws iblx::Error when the solved map folds (it would not be an exact sampler).
TechniqueData envOtFwdTechniqueData(const EnvImage& image);
TechniqueData envOtInvTechniqueData(const EnvImage& image);

}  // namespace iblx
