// The OT env techniques' tables (env_ot_maps.h).
#include "engine/sampling/env/env_ot_maps.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/io/latlong_texel.h"
#include "engine/ot/cache.h"
#include "engine/ot/map.h"
#include "engine/ot/solver.h"
#include "engine/sampling/env/env_ot_sun.h"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <string>
#include <vector>

namespace iblx {

EnvOtMaps solveEnvOtMaps(const EnvImage& image, int grid) {
  const int n = grid > 0 ? grid : otGridSize(image);
  EnvOtMaps maps{texelSamplingWeights(image, "OT density"), {}, {}};
  maps.sun = splitOtSun(maps.weights, image.width, image.height);
  const std::vector<double> density =
      otDensityFromWeights(maps.sun.smoothWeights, image.width, image.height, n);
  maps.map = solveOtMapCached(density, n, OtSolverOptions{}, defaultCacheDir());
  const OtMap& map = maps.map;
  if (map.negativeAreaQuads > 0)
    throw Error("OT map: " + std::to_string(map.negativeAreaQuads) +
                " folded quads at n = " + std::to_string(n));
  if (!map.converged)  // still an exact sampler (its pdf is the map's own), only a less efficient one
    warn("OT map at n = " + std::to_string(n) + " did not converge (L2 " + std::to_string(map.l2) + ", L1 " +
         std::to_string(map.l1) + "); sampling with the best map reached");
  return maps;
}

namespace {

// A QuadGridMap's vertex images and piece types: tables <prefix>Vertex and <prefix>Piece.
void addQuadMapGeometry(TechniqueData& data, const QuadGridMap& map, const std::string& prefix,
                        const std::string& technique) {
  if (map.invalidPieces() > 0)
    throw Error(technique + ": " + std::to_string(map.invalidPieces()) +
                " quads of the map are not injective; the sampler would not be exact");
  const std::vector<glm::vec2> vertices(map.image().begin(), map.image().end());
  std::vector<std::uint32_t> pieces(map.pieces().size());
  for (std::size_t c = 0; c < pieces.size(); ++c) pieces[c] = std::uint32_t(map.pieces()[c]);
  data.add(prefix + "Vertex", vertices);
  data.add(prefix + "Piece", pieces);
}

TechniqueData packEnvOt(const QuadGridMap& map, const OtSunSplit& sun, int densityGrid,
                        const std::string& technique) {
  TechniqueData data;
  addQuadMapGeometry(data, map, "quadMap", technique);
  data.add("quadMapNode", map.nodes());
  data.add("quadMapLeafCell", map.leafCells());
  data.add("otSunTexel", sun.texels);
  data.add("otSunCdf", sun.cdf);
  data.add("otSunRowFirst", sun.rowFirst);
  data.define("OT_GRID", std::uint32_t(map.size()));
  data.define("OT_TREE_DEPTH", std::uint32_t(map.treeDepth()));
  data.define("OT_LARGEST_LEAF", map.largestLeaf());
  data.define("OT_DENSITY_GRID", std::uint32_t(densityGrid));
  data.define("OT_SUN_TEXELS", std::to_string(sun.texels.size()));
  data.define("OT_SUN_SHARE_BITS", std::bit_cast<std::uint32_t>(sun.sunShare));
  return data;
}

}  // namespace

int otGridSize(const EnvImage& image) {
  if (const char* forced = std::getenv("IBLX_OT_SIZE")) {
    const int n = std::atoi(forced);
    if (n < 8 || n > 2048)
      throw Error("IBLX_OT_SIZE: expected a grid size in [8, 2048], got '" + std::string(forced) + "'");
    return n;
  }
  return std::clamp(image.height, 32, 256);
}

int envOtGridSize(const EnvImage& image) {
  if (std::getenv("IBLX_OT_SIZE") || image.texelCount() > kEnvOtFineGridTexels) return otGridSize(image);
  return std::clamp(image.height, 32, 512);
}

TechniqueData envOtFwdTechniqueData(const EnvImage& image) {
  const EnvOtMaps maps = solveEnvOtMaps(image);
  return packEnvOt(forwardMap(maps.map), maps.sun, maps.map.n, "env-ot-fwd");
}

TechniqueData envOtInvTechniqueData(const EnvImage& image) {
  const EnvOtMaps maps = solveEnvOtMaps(image);
  const QuadGridMap forward = forwardMap(maps.map);
  TechniqueData data = packEnvOt(tabulatedInverse(forward, maps.map.n), maps.sun, maps.map.n, "env-ot-inv");
  // The forward map, whose image of a point guesses the point's preimage under the inverse.
  addQuadMapGeometry(data, forward, "otForward", "env-ot-inv");
  return data;
}

}  // namespace iblx
