// The optimal-transport env techniques' GPU tables: env-ot-fwd (the forward quad mesh, inverted per sample by
// quadtree point location) and env-ot-inv (the tabulated inverse, with the forward map as its guess). The map
// is solved (engine/ot/solver.h) for the environment with its sun texels split off
// (engine/sampling/env/env_ot_sun.h); both parts read the sun's tables too.
#pragma once

#include "engine/io/env_image.h"
#include "engine/ot/solver.h"
#include "engine/sampling/env/env_ot_sun.h"
#include "engine/sampling/technique_data.h"

#include <vector>

namespace iblx {

// Grid of the OT map: 256 or, for smaller maps, the map's height (no finer than its rows), at least 32;
// IBLX_OT_SIZE overrides it (benchmarks). Throws iblx::Error for an IBLX_OT_SIZE outside [8, 2048].
int otGridSize(const EnvImage& image);
// Grid of env-ot's map: the map's height, between 32 and 512, for maps of at most kEnvOtFineGridTexels texels
// (a 2:1 map's cells then hold two texels), otGridSize for larger ones; IBLX_OT_SIZE overrides both. Finer
// cells keep the map's layout further down towards the texels (docs/RESULTS.md); larger maps keep 256 so that
// the pieces stay within lavapipe's 128 MiB buffers (a 1024 x 512 map at 512 has 3.2-3.4 M pieces, 51-54 MB
// of piece records).
inline constexpr std::size_t kEnvOtFineGridTexels = std::size_t(1) << 20;
int envOtGridSize(const EnvImage& image);

// The OT techniques' map: the sun texels' excess split off (env_ot_sun.h) and the map solved (or read from
// the cache) for the rest at otGridSize, before untangling. The samplers build their tables from it; so do
// the offline diagnostics of their pdfs (engine/sampling/env/env_ot_diagnostics.h). Throws iblx::Error when
// the map has a folded quad; warns when it did not converge (the samplers stay exact, only less efficient).
struct EnvOtMaps {
  std::vector<double> weights;  // the texel sampling weights (texelSamplingWeights)
  OtSunSplit sun;
  OtMap map;
};
// grid: the map's n, 0 for otGridSize(image).
EnvOtMaps solveEnvOtMaps(const EnvImage& image, int grid = 0);

// Tables of shaders/lib/quad_grid_map.glsl (quadMapVertex, quadMapPiece, quadMapNode, quadMapLeafCell) and
// shaders/lib/ot_sun.glsl (otSunTexel, otSunCdf, otSunRowFirst); env-ot-inv adds otForwardVertex and
// otForwardPiece. Throws iblx::Error when the solved map folds (it would not be an exact sampler).
TechniqueData envOtFwdTechniqueData(const EnvImage& image);
TechniqueData envOtInvTechniqueData(const EnvImage& image);

}  // namespace iblx
