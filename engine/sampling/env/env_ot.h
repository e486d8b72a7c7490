// env-ot: the texel-exact optimal-transport sampler (builder + CPU twin of
// shaders/env_technique/env_ot.glsl).
//
// The optimal-transport map (engine/ot/solver.h, with suns split off by env_ot_sun.h) sends the cells of
// a regular n x n grid over the uniform square to quads of the lat-long parameter square that hold about
// 1/n^2 of the environment's weight each: neighbouring cells go to neighbouring quads of similar shape, with
// no row shear. Its pdf, though, is the map's Jacobian, not the texel pdf: sub-cell texel detail (and the
// map's residual) stays in the estimator. env-ot keeps the map's cell layout and makes the pdf exactly the
// texel pdf:
//
// - every quad of the tabulated inverse map is split into two triangles (a piecewise-affine map, injective
//   because every triangle has positive area) and each triangle is clipped against the texel grid into
//   pieces that lie inside one texel (and one row of the OT density grid, where the parameter square is
//   linear in cos(theta), so a piece is a triangle in the texel's own equal-area coordinates as well);
// - a piece gets the probability of its texel's smooth weight times its share of the texel's area, so the
//   pieces of a texel hold exactly its weight, and a direction is uniform in solid angle inside its piece;
// - the uniform square is partitioned like the map's grid but with exact masses: a CDF over the grid's rows,
//   then one over each row's pieces ordered by cell (the same warp as a CDF over the row's cells followed by
//   one over each cell's pieces, with one search less). The cells' masses are within the solver's residual of
//   1/n^2, so the partition is the map's grid moved by that residual;
// - the sun's excess weight (the part split off before solving) is one more row of the same CDFs, of the sun
//   texels as whole pieces: the sun takes its share as a strip of u.y of the same 2D sample,
//   and every sample takes the same code path (no divergent sun branch on SIMD hardware).
//
// The sampled density is the texel pdf of env-cdf (texel weight = mean RGB x exact texel solid angle), up to
// the float rounding of the CDFs (the pdf is the probability the float tables give the texel, as env-cdf's
// is) and of the piece corners. Across cells the warp is the OT map's (continuous up to the residual shift);
// inside a cell it chooses among the cell's pieces, so it is texel-exact and, where a cell holds several
// texels, discontinuous there.
#pragma once

#include "engine/io/env_image.h"
#include "engine/io/latlong_texel.h"
#include "engine/ot/map.h"
#include "engine/sampling/env/env_ot_sun.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace iblx {

// A piece's GPU record (std430 uvec4): x = texel index y*W + x, with bit 31 set for a triangle; for a
// triangle y, z, w are its corners a, b, c in the texel's coordinates t in [0,1]^2 (texelToDirection's: phi
// and cos(theta) linear), each packed as unorm16 x | y << 16 (GLSL unpackUnorm2x16). A piece without bit 31
// is the whole texel.
inline constexpr std::uint32_t kEnvOtTrianglePiece = 0x80000000u;

struct EnvOtData {
  int width = 0, height = 0;
  int grid = 0;  // n: the uniform square's grid (the OT map's)
  // n, or n + 1 when the sun is split: row n holds the sun texels as whole pieces (their excess weight).
  int rows = 0;
  int sunTexels = 0;                    // the sun row's texels (0: no split)
  std::vector<float> rowCdf;            // rows + 1 entries, [0] = 0, [rows] = 1
  int rowGuideCells = 0;                // envCdfGuideCells(rows, 2)
  std::vector<std::uint32_t> rowGuide;  // float_cdf.h writeGuide of rowCdf
  // rows + 1 records: row j's pieces start at x (the last record's x is the piece count), its guide at y with
  // z cells (a power of two, about one per piece); w unused.
  std::vector<glm::uvec4> rowPieces;
  // Per row j, at rowPieces[j].x + j: the CDF over its pieces (count + 1 entries, [0] = 0, last = 1). The
  // pieces of a row are ordered by cell, so this one CDF is the cells' CDF followed by each cell's pieces'
  // CDF.
  std::vector<float> pieceCdf;
  std::vector<std::uint32_t> pieceGuide;  // the rows' guides, row j's at rowPieces[j].y
  std::vector<glm::uvec4> pieces;         // per piece, as above
  // W*H: the pdf w.r.t. solid angle, the texel's probability as these float tables give it (the sum over its
  // pieces) over its solid angle: its weight's share up to the CDFs' rounding.
  std::vector<float> texelPdf;
};

// Builds the mesh from a tabulated inverse map over the density square (domain = the uniform square's grid,
// image = the lat-long parameter square whose OT_DENSITY_GRID rows, densityGrid of them, are each linear in
// cos(theta): shaders/lib/quad_grid_map.glsl otParameterToDirection). weights: W*H texel sampling weights;
// sun: their split (its smoothWeights are what the mesh carries). Throws iblx::Error when the map has a quad
// that is not injective or the sizes disagree.
EnvOtData buildEnvOtMesh(std::span<const double> weights, int width, int height, const OtSunSplit& sun,
                         const QuadGridMap& inverse, int densityGrid);
// Solves (or reads from the cache) the environment's OT map and builds the mesh. Throws iblx::Error as the
// env-ot-inv builder does (invalid image, folded map).
EnvOtData buildEnvOt(const EnvImage& image);

// CPU twin of the env-ot GLSL part: the same float steps on the same tables.
//
// sample(u), u the float the GPU receives (toGpuU): u.y picks the row j (the largest k with rowCdf[k] <= u.y,
// searched in its guide cell), u.x the piece in row j's CDF (likewise); the piece is placed with (rescaled
// u.x, rescaled u.y): a whole texel takes them as t, a triangle maps them uniformly (Osada et al. 2002,
// "Shape distributions", eq. 1: (1 - sqrt r1) a + sqrt r1 (1 - r2) b + sqrt r1 r2 c). pdfSolidAngle =
// texelPdf of the texel sampled.
//
// Trade-offs:
// - Cost: two guided searches (a step or none each), one table read for the row, one for the piece and one
//   for the pdf; pdf() is one read. No point location, no Jacobian.
// - Memory: about 24 B per piece (record, CDF entry, guide cell) and 4 B per texel for the pdf. A 1024 x 512
//   map has 1.9 M pieces (45 MB) under a 256 grid and 3.2-3.4 M (74-80 MB) under its default 512
//   (envOtGridSize): the map's cell edges cut most texels. The tables do not fit a 32 MB cache, so at about
//   env-hier's instruction count a sample still costs more than env-hier's: its piece and CDF reads miss
//   (docs/BENCHMARKS.md, "Where the OT samplers lose, in factors").
class EnvOtSampler {
 public:
  // Keeps a copy. Throws iblx::Error when the tables are mis-sized.
  explicit EnvOtSampler(EnvOtData data);

  EnvSample sample(glm::dvec2 u) const;
  // The texel pdf of the texel that contains wi.
  double pdf(glm::dvec3 wi) const;
  // A u with sample(u).direction == wi (up to float rounding), through the map's pieces when wi's texel has
  // any, else through the sun row; empty when wi's texel has probability 0.
  std::optional<glm::dvec2> invert(glm::dvec3 wi) const;

  // The probability of texel (x, y) as the tables give it: the sum over its pieces (the sun row's included)
  // of float CDF differences, what sampling draws (as opposed to texelPdf * Omega).
  double texelProbability(int x, int y) const;
  // The sum of the map's pieces' areas in texel (x, y), in units of the texel (1 when they tile it).
  double texelCoverage(int x, int y) const;
  const EnvOtData& data() const { return data_; }

 private:
  // Probability (float) of a piece: rowProb * pieceProb, and the piece's row.
  double pieceProbability(std::uint32_t piece) const;
  std::uint32_t pieceRow(std::uint32_t piece) const;

  EnvOtData data_;
  std::vector<std::uint32_t> texelPieceFirst_, texelPieces_;  // per texel, its pieces (for invert)
};

// env-ot's tables for shaders/env_technique/env_ot.glsl (envOtRowCdf, envOtRowGuide, envOtRow, envOtPieceCdf,
// envOtPieceGuide, envOtPiece, envOtTexelPdf), with the row guide's size as a definition.
TechniqueData envOtTechniqueData(const EnvOtData& data);
TechniqueData envOtTechniqueData(const EnvImage& image);

}  // namespace iblx
