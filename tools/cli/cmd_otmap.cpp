// `iblx otmap`: solves (or reads from the cache) the optimal-transport map of an environment
// (engine/ot/solver.h, engine/ot/cache.h), prints how well it converged and draws it: the environment's
// lat-long map as grey log sampling weight, with the pre-images of a uniform grid over the unit square drawn
// on top. A sampler maps uniform points through the inverse map, so where those lines crowd, samples crowd.
// With --diagnose it draws nothing and reports, per env sampler, how far its pdf is from the texel pdf
// (engine/sampling/env/env_ot_diagnostics.h): the offline part of the OT decomposition (docs/BENCHMARKS.md).
#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/file_names.h"
#include "engine/core/json_output.h"
#include "engine/core/log.h"
#include "engine/io/env_image.h"
#include "engine/io/image_write.h"
#include "engine/scene/scene.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/sampling/env/env_hier.h"
#include "engine/sampling/env/env_ot_maps.h"
#include "engine/sampling/env/env_ot_diagnostics.h"
#include "engine/sampling/env/env_ot.h"
#include "engine/io/latlong_texel.h"
#include "engine/ot/cache.h"
#include "engine/ot/map.h"
#include "engine/ot/solver.h"
#include "engine/sampling/env/env_ot_sun.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace iblx::cli {

namespace {

constexpr int kGridLines = 32;  // grid cells per axis of the uniform square whose lines are drawn

// An 8-bit RGB raster with alpha blending of single pixels.
struct Figure {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  void blend(int x, int y, const std::array<std::uint8_t, 3>& colour, double alpha) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
    for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(std::lround(p[c] + alpha * (colour[c] - p[c])));
  }
};

// The environment's sampling weight (mean RGB, docs/DESIGN.md §3) box-filtered to width x height, as grey on
// a log scale: the brightest pixel near white, the dimmest non-zero ones dark grey, exact zeros black.
Figure logWeightBackground(const EnvImage& env, int width, int height) {
  std::vector<double> weight(std::size_t(width) * height, 0.0);
  for (int py = 0; py < height; ++py) {
    const int y0 = int(std::int64_t(py) * env.height / height);
    const int y1 = std::max(y0 + 1, int(std::int64_t(py + 1) * env.height / height));
    for (int px = 0; px < width; ++px) {
      const int x0 = int(std::int64_t(px) * env.width / width);
      const int x1 = std::max(x0 + 1, int(std::int64_t(px + 1) * env.width / width));
      double sum = 0.0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += env.weight(x, y);
      weight[std::size_t(py) * width + px] = sum / (double(y1 - y0) * (x1 - x0));
    }
  }
  // White at the brightest pixel, dark grey at the 1st percentile of the non-zero ones (at least 10^3 below
  // it).
  std::vector<double> positive;
  for (double w : weight)
    if (w > 0.0) positive.push_back(w);
  double hi = 0.0, lo = 0.0;
  if (!positive.empty()) {
    hi = *std::max_element(positive.begin(), positive.end());
    const auto percentile = positive.begin() + std::ptrdiff_t(positive.size() / 100);
    std::nth_element(positive.begin(), percentile, positive.end());
    lo = std::min(*percentile, 1e-3 * hi);
  }
  Figure figure{width, height, std::vector<std::uint8_t>(weight.size() * 3, 0)};
  for (std::size_t i = 0; i < weight.size(); ++i) {
    if (!(weight[i] > 0.0)) continue;
    const double t = std::clamp(std::log(weight[i] / lo) / std::log(hi / lo), 0.0, 1.0);
    const auto grey = std::uint8_t(std::lround(40 + 190 * t));
    for (int c = 0; c < 3; ++c) figure.rgb[3 * i + c] = grey;
  }
  return figure;
}

// Draws the pre-image under `forward` (lat-long square -> uniform square) of the uniform square's line
// {axis coordinate = value}, as a chain of points no more than half a pixel apart (bisected where the map
// stretches the line).
void drawPreimage(Figure& figure, const QuadGridMap& forward, int axis, double value,
                  const std::array<std::uint8_t, 3>& colour) {
  const double inset = 1e-9;  // points on the square's sides may fall just outside every piece by rounding
  const double fixed = std::clamp(value, inset, 1.0 - inset);
  const auto locate = [&](double t) -> std::optional<glm::dvec2> {
    t = std::clamp(t, inset, 1.0 - inset);
    const glm::dvec2 y = axis == 0 ? glm::dvec2(fixed, t) : glm::dvec2(t, fixed);
    const auto x = forward.invert(y);
    if (!x) return std::nullopt;
    return glm::dvec2(x->p.x * figure.width, x->p.y * figure.height);  // pixels; v (row) down the image
  };
  const auto plot = [&](glm::dvec2 p) {
    figure.blend(int(std::floor(p.x)), int(std::floor(p.y)), colour, 0.85);
  };
  // Bisects [t0, t1] until consecutive points are within half a pixel (or the interval is tiny).
  const auto refine = [&](auto&& self, double t0, glm::dvec2 p0, double t1, glm::dvec2 p1,
                          int depth) -> void {
    const glm::dvec2 d = p1 - p0;
    if (d.x * d.x + d.y * d.y <= 0.25 || depth == 0) {
      plot(p1);
      return;
    }
    const double tm = 0.5 * (t0 + t1);
    const auto pm = locate(tm);
    if (!pm) {
      plot(p1);
      return;
    }
    self(self, t0, p0, tm, *pm, depth - 1);
    self(self, tm, *pm, t1, p1, depth - 1);
  };
  const int steps = 2 * std::max(figure.width, figure.height);
  std::optional<glm::dvec2> previous;
  double previousT = 0.0;
  for (int s = 0; s <= steps; ++s) {
    const double t = double(s) / steps;
    const auto p = locate(t);
    if (p && previous)
      refine(refine, previousT, *previous, t, *p, 24);
    else if (p)
      plot(*p);
    previous = p;
    previousT = t;
  }
}

std::string yesNo(bool b) {
  return b ? "yes" : "no";
}

// Round trips over 512 x 512 points: a quarter and three quarters of the way across each cell of a 256 grid.
constexpr int kRoundTripPoints = 512;

// `iblx otmap --diagnose`: per env sampler, chi^2 of the texel pdf against the sampler's texel probabilities
// (its pdf integrated over each texel on a subgrid x subgrid grid), and for the OT samplers the share of
// non-convex quads of the map they evaluate and its round trip. The OT samplers use their own map (grid,
// floor, sun split: engine/sampling/env/env_ot_maps.h), read from the cache or solved.
int diagnoseSamplers(const EnvImage& env, const std::filesystem::path& envPath, int subgrid, bool json) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<double> texelPdf = texelProbabilities(env);
  progressLine("otmap --diagnose: the OT samplers' map (" + std::to_string(otGridSize(env)) + "^2)");
  const EnvOtSamplerMaps ot = envOtSamplerMaps(env);
  endProgressLine();

  // Every env technique of the registry with a CPU twin; the two that evaluate the OT map per sample also
  // report the map's quality (env-ot only takes its cells).
  struct Sampler {
    std::string name;
    std::function<double(glm::dvec3)> pdf;
    const QuadGridMap* map;  // the map it evaluates per sample; none for the others
  };
  std::vector<Sampler> samplers;
  for (const EnvTechniqueInfo& technique : envTechniqueRegistry()) {
    if (!technique.cpuPdf) continue;
    const QuadGridMap* map = technique.otMap == EvaluatedOtMap::Inverse   ? &ot.inverse
                             : technique.otMap == EvaluatedOtMap::Forward ? &ot.forward
                                                                          : nullptr;
    samplers.push_back({technique.name, technique.cpuPdf(env), map});
  }
  if (!json) {
    std::printf(
        "sampler diagnostics of %s (%dx%d): OT grid %d, sun share %.3g, texel pdf integrated on "
        "%dx%d points per texel\n",
        envPath.string().c_str(), env.width, env.height, ot.densityGrid, double(ot.sun.sunShare), subgrid,
        subgrid);
    std::printf("%-11s %12s %12s %12s %11s %15s %15s\n", "sampler", "chi2", "unreachable", "sampler mass",
                "non-convex", "round trip max", "round trip mean");
  }
  for (const Sampler& sampler : samplers) {
    progressLine("otmap --diagnose: " + sampler.name);
    const auto began = std::chrono::steady_clock::now();
    const std::vector<double> q = integrateTexelProbabilities(sampler.pdf, env.width, env.height, subgrid);
    const TexelChi2 chi2 = texelChi2(texelPdf, q);
    std::optional<MapRoundTrip> roundTrip;
    if (sampler.map == &ot.inverse) roundTrip = inverseRoundTrip(ot.forward, ot.inverse, kRoundTripPoints);
    if (sampler.map == &ot.forward) roundTrip = forwardRoundTrip(ot.forward, kRoundTripPoints);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    endProgressLine();
    const double nonConvex = sampler.map ? nonConvexShare(*sampler.map) : 0.0;
    if (json) {
      // null where a figure does not apply (the texel samplers have no map).
      const auto orNull = [](bool applies, double value) {
        return applies ? JsonObject(value) : JsonObject();
      };
      printJsonLine(
          {{"env", envPath.string()},
           {"env_width", env.width},
           {"env_height", env.height},
           {"sampler", sampler.name},
           {"subgrid", subgrid},
           {"chi2", chi2.chi2},
           {"unreachable_mass", chi2.unreachableMass},
           {"sampler_mass", chi2.qMass},
           {"non_convex_share", orNull(sampler.map != nullptr, nonConvex)},
           {"round_trip_max", orNull(roundTrip.has_value(), roundTrip ? roundTrip->max : 0.0)},
           {"round_trip_mean", orNull(roundTrip.has_value(), roundTrip ? roundTrip->mean : 0.0)},
           {"round_trip_missed", orNull(roundTrip.has_value(), roundTrip ? double(roundTrip->missed) : 0.0)},
           {"ot_grid", ot.densityGrid},
           {"sun_share", double(ot.sun.sunShare)},
           {"seconds", seconds}});
    } else {
      char convex[32] = "-", tripMax[32] = "-", tripMean[32] = "-";
      if (sampler.map) std::snprintf(convex, sizeof convex, "%.2f %%", 100.0 * nonConvex);
      if (roundTrip) {
        std::snprintf(tripMax, sizeof tripMax, "%.3g", roundTrip->max);
        std::snprintf(tripMean, sizeof tripMean, "%.3g", roundTrip->mean);
      }
      std::printf("%-11s %12.4g %12.4g %12.6f %11s %15s %15s\n", sampler.name.c_str(), chi2.chi2,
                  chi2.unreachableMass, chi2.qMass, convex, tripMax, tripMean);
    }
  }
  if (!json) {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "chi2 = sum p_texel^2 / p_sampler - 1 over reachable texels (0: the texel pdf); unreachable: "
        "the texel pdf's mass where the sampler's is 0; round trip: |F(G(u)) - u| (env-ot-inv), "
        "|F(F^-1(u)) - u| (env-ot-fwd) over %dx%d points; total %.2f s\n",
        kRoundTripPoints, kRoundTripPoints, wall);
  }
  return 0;
}

// The flags of `iblx otmap`.
struct OtMapOptions {
  std::filesystem::path envPath;  // empty: the default map
  int n = 256;
  OtSolverOptions solver;
  bool json = false, noCache = false;
  double sunClip = 0.0;
  std::string out = "otmap.png";
  bool diagnose = false;
  int subgrid = 0;  // 0: not given
};

// Declares the flags and parses `args`; none when --help was answered.
std::optional<OtMapOptions> parseOtMapOptions(const Args& args) {
  OtMapOptions options;
  std::vector<std::string> mapFlags;  // given flags that --diagnose does not take (it uses the samplers' map)
  ArgParser parser("otmap");
  parser.value("--env", "FILE", ".exr or .hdr lat-long map (default: assets/default_sky.exr)",
               [&](const std::string& v) { options.envPath = v; });
  parser.value("--size", "N", "grid size n of the map, 64-1024 (default 256)", [&](const std::string& v) {
    options.n = int(parseUint("--size", v, 64, 1024));
    mapFlags.push_back("--size");
  });
  parser.value("--floor", "EPS", "density floor as a fraction of the mean, in [1e-12, 1] (default 1e-2)",
               [&](const std::string& v) {
                 options.solver.floorFraction = parseDouble("--floor", v, 1e-12, 1.0);
                 mapFlags.push_back("--floor");
               });
  parser.value("--max-iter", "N", "iteration cap at each grid level (default 2000)",
               [&](const std::string& v) {
                 options.solver.maxIterations = int(parseUint("--max-iter", v, 1, 1000000));
                 mapFlags.push_back("--max-iter");
               });
  parser.value("--sun-clip", "F",
               "solve for the map with texels above F x the median radiance capped, as the env-ot samplers "
               "do (they use " +
                   std::to_string(int(kOtSunClip)) + "); 0 = the whole map (default)",
               [&](const std::string& v) {
                 options.sunClip = v == "0" ? 0.0 : parseDouble("--sun-clip", v, 1.0, 1e12);
                 mapFlags.push_back("--sun-clip");
               });
  parser.toggle("--json", "print one JSON object instead of text", [&] { options.json = true; });
  parser.value("--out", "FILE", "the figure, a .png (default otmap.png)", [&](const std::string& v) {
    options.out = v;
    mapFlags.push_back("--out");
  });
  parser.toggle("--no-cache", "solve even when the cache holds the map, and do not store it", [&] {
    options.noCache = true;
    mapFlags.push_back("--no-cache");
  });
  parser.toggle(
      "--diagnose",
      "draw nothing; report per env sampler (env-cdf, env-hier, env-ot, env-ot-inv, env-ot-fwd) chi^2 of "
      "the texel pdf against its pdf, and for the OT samplers the share of non-convex quads and the "
      "map's round trip (the samplers' own map; docs/BENCHMARKS.md)",
      [&] { options.diagnose = true; });
  parser.value("--subgrid", "K",
               "with --diagnose: integrate each sampler's pdf over a texel on K x K points, 1-16 (default 4)",
               [&](const std::string& v) { options.subgrid = int(parseUint("--subgrid", v, 1, 16)); });
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (options.subgrid != 0 && !options.diagnose) throw Error("--subgrid: only with --diagnose");
  if (options.diagnose && !mapFlags.empty())
    throw Error("--diagnose uses the samplers' own map and draws nothing; " + mapFlags.front() +
                " does not apply to it");
  return options;
}

// Solves the map of `density` on the n x n grid (or reads it from the cache, unless --no-cache), with a
// progress line.
OtMap solveMap(const OtMapOptions& options, const std::vector<double>& density,
               std::chrono::steady_clock::time_point start, bool& fromCache) {
  const int n = options.n;
  OtSolverOptions solverOptions = options.solver;
  auto lastReport = start;
  solverOptions.progress = [&](int iteration, double l2) {
    const auto now = std::chrono::steady_clock::now();
    if (now - lastReport < std::chrono::milliseconds(500)) return;
    lastReport = now;
    char line[96];
    std::snprintf(line, sizeof line, "otmap %dx%d: iteration %d, L2 %.3g", n, n, iteration, l2);
    progressLine(line);
  };
  // The solver reports the finest level only; until then the line says that the coarse levels run.
  progressLine("otmap " + std::to_string(n) + "x" + std::to_string(n) + ": solving (coarse levels first)");
  const std::filesystem::path cacheDir = options.noCache ? std::filesystem::path() : defaultCacheDir();
  OtMap map = solveOtMapCached(density, n, solverOptions, cacheDir, &fromCache);
  endProgressLine();
  return map;
}

// The figure: the environment's log sampling weight under the pre-images of a kGridLines x kGridLines uniform
// grid.
Figure drawMapFigure(const EnvImage& env, const QuadGridMap& forward, int n) {
  // At least 512 wide so the grid stays legible, at most 1024, else the map's own width.
  const int width = std::min(1024, std::max({512, 2 * n, env.width})) & ~1;
  Figure figure = logWeightBackground(env, width, width / 2);
  const std::array<std::uint8_t, 3> uColour{255, 140, 0}, vColour{0, 200, 255};
  for (int k = 0; k <= kGridLines; ++k) {
    drawPreimage(figure, forward, 0, double(k) / kGridLines, uColour);
    drawPreimage(figure, forward, 1, double(k) / kGridLines, vColour);
  }
  return figure;
}

// The untangled map's own mass error: L1 of its quads' areas against the density.
double samplerMassError(const QuadGridMap& forward, const OtMap& map, int n) {
  double samplerL1 = 0.0;
  const std::vector<double> samplerAreas = otQuadAreas(forward.image(), n);
  for (std::size_t c = 0; c < samplerAreas.size(); ++c)
    samplerL1 += std::abs(samplerAreas[c] - map.density[c] / (double(n) * n));
  return samplerL1;
}

// What the report of a drawn map prints besides the flags, the sun split and the map.
struct DrawnMapReport {
  std::filesystem::path envPath;
  int envWidth = 0, envHeight = 0;
  bool fromCache = false;
  double samplerL1 = 0.0;  // samplerMassError
  int figureWidth = 0, figureHeight = 0;
  double wall = 0.0;  // loading, solving and drawing
};

void printOtMapJson(const OtMapOptions& options, const DrawnMapReport& report, const OtSunSplit& sun,
                    const OtMap& map, const QuadGridMap& forward) {
  // One object per coarse-to-fine level, coarsest first (none when the map came from the cache); their keys
  // differ from the top-level ones so that a flat reader of the top level is not misled.
  JsonObject levels = JsonObject::array();
  for (const OtLevelStats& l : map.levels)
    levels.push_back({{"grid", l.n},
                      {"newton_iterations", l.iterations},
                      {"stages", l.stages},
                      {"undone_stages", l.undoneStages},
                      {"lu_factorisations", l.factorisations},
                      {"krylov_steps", l.krylovSteps},
                      {"curved_steps", l.curvedSteps},
                      {"level_seconds", l.seconds},
                      {"level_l2", l.l2},
                      {"folded_start", l.foldedStart()},
                      {"start_folded_quads", l.startFoldedQuads},
                      {"smoothing_passes", l.smoothingPasses},
                      {"restart_scale", l.restartScale}});
  printJsonLine({{"env", report.envPath.string()},
                 {"env_width", report.envWidth},
                 {"env_height", report.envHeight},
                 {"n", options.n},
                 {"floor", options.solver.floorFraction},
                 {"iterations", map.iterations},
                 {"coarse_iterations", map.coarseIterations},
                 {"seconds", map.seconds},
                 {"wall_s", report.wall},
                 {"l2", map.l2},
                 {"l1", map.l1},
                 {"linf", map.linf},
                 {"folded", map.negativeAreaQuads},
                 {"non_convex", map.foldedQuads},
                 {"invalid_pieces", forward.invalidPieces()},
                 {"sampler_l1", report.samplerL1},
                 {"tree_depth", forward.treeDepth()},
                 {"largest_leaf", forward.largestLeaf()},
                 {"sun_clip", options.sunClip},
                 {"sun_share", double(sun.sunShare)},
                 {"sun_texels", sun.sunShare > 0.0f ? sun.texels.size() : std::size_t(0)},
                 {"converged", map.converged},
                 {"from_cache", report.fromCache},
                 {"out", options.out},
                 {"out_width", report.figureWidth},
                 {"out_height", report.figureHeight},
                 {"levels", levels}});
}

void printOtMapText(const OtMapOptions& options, const DrawnMapReport& report, const OtSunSplit& sun,
                    const OtMap& map, const QuadGridMap& forward) {
  const int n = options.n;
  const double sunClip = options.sunClip;
  std::printf("otmap of %s (%dx%d) on a %dx%d grid, floor %g x mean\n", report.envPath.string().c_str(),
              report.envWidth, report.envHeight, n, n, options.solver.floorFraction);
  if (sunClip > 0.0 && sun.sunShare > 0.0f)
    std::printf("suns: %zu texels above %g x the median radiance, %.1f %% of the weight, sampled apart\n",
                sun.texels.size(), sunClip, 100.0 * sun.sunShare);
  else if (sunClip > 0.0)
    std::printf(
        "suns: none split off (the texels above %g x the median radiance hold less than %g %% of the "
        "weight)\n",
        sunClip, 100.0 * kOtSunMinShare);
  std::printf("iterations: %d (+%d on coarser grids), solved in %.3f s%s\n", map.iterations,
              map.coarseIterations, map.seconds,
              report.fromCache ? " (when it was stored in the cache)" : "");
  for (const OtLevelStats& l : map.levels) {
    const std::string startNote = otLevelStartNote(l);
    std::printf(
        "  level %4d: %3d Newton iterations (%d curved), %2d stages (%d undone), %2d LU "
        "factorisations, %4d Krylov steps, %.3f s, L2 %.3g%s\n",
        l.n, l.iterations, l.curvedSteps, l.stages, l.undoneStages, l.factorisations, l.krylovSteps,
        l.seconds, l.l2, startNote.empty() ? "" : (", " + startNote).c_str());
  }
  std::printf("mass error: L2 %.3g, L1 %.3g, Linf %.3g\n", map.l2, map.l1, map.linf);
  std::printf("quads: %d folded (area <= 0), %d not strictly convex, %d without a valid piece\n",
              map.negativeAreaQuads, map.foldedQuads, forward.invalidPieces());
  std::printf(
      "sampler map (untangled): L1 %.3g; env-ot-fwd's quadtree: depth %d, at most %u quads per leaf\n",
      report.samplerL1, forward.treeDepth(), forward.largestLeaf());
  std::printf("converged: %s (L2 <= %g and L1 <= %g); from the cache: %s\n", yesNo(map.converged).c_str(),
              options.solver.targetL2, options.solver.targetL1, yesNo(report.fromCache).c_str());
  std::printf("wrote %s (%dx%d: log sampling weight, pre-images of a %dx%d uniform grid; total %.2f s)\n",
              options.out.c_str(), report.figureWidth, report.figureHeight, kGridLines, kGridLines,
              report.wall);
}

// Solves (or reads) the map, draws it into --out and reports it.
int drawOtMap(const OtMapOptions& options) {
  if (lowerExtension(options.out) != ".png")
    throw Error("--out " + options.out + ": the figure is a PNG; use a .png file name");
  checkImagePath("--out", options.out);

  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path envPath = options.envPath.empty() ? defaultEnvPath() : options.envPath;
  const EnvImage env = loadEnvImage(envPath);
  const OtSunSplit sun =
      splitOtSun(texelSamplingWeights(env, "OT density"), env.width, env.height, options.sunClip);
  const std::vector<double> density =
      otDensityFromWeights(sun.smoothWeights, env.width, env.height, options.n);

  bool fromCache = false;
  const OtMap map = solveMap(options, density, start, fromCache);
  if (!map.converged)
    warn("the OT map of " + envPath.string() + " did not converge (L2 " + std::to_string(map.l2) + ", L1 " +
         std::to_string(map.l1) + "); the figure shows the best map reached");

  const QuadGridMap forward = forwardMap(map);
  const Figure figure = drawMapFigure(env, forward, options.n);
  writePngRgb8(options.out, figure.width, figure.height, figure.rgb);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // What the samplers evaluate: the untangled map's own mass error, and the bound on env-ot-fwd's search.
  const DrawnMapReport report{.envPath = envPath,
                              .envWidth = env.width,
                              .envHeight = env.height,
                              .fromCache = fromCache,
                              .samplerL1 = samplerMassError(forward, map, options.n),
                              .figureWidth = figure.width,
                              .figureHeight = figure.height,
                              .wall = wall};
  if (options.json)
    printOtMapJson(options, report, sun, map, forward);
  else
    printOtMapText(options, report, sun, map, forward);
  return 0;
}

int runOtMap(const OtMapOptions& options) {
  if (options.diagnose) {
    const std::filesystem::path envPath = options.envPath.empty() ? defaultEnvPath() : options.envPath;
    return diagnoseSamplers(loadEnvImage(envPath), envPath, options.subgrid == 0 ? 4 : options.subgrid,
                            options.json);
  }
  return drawOtMap(options);
}

}  // namespace

int cmdOtMap(const Args& args) {
  if (const std::optional<OtMapOptions> options = parseOtMapOptions(args)) return runOtMap(*options);
  return 0;
}

}  // namespace iblx::cli
