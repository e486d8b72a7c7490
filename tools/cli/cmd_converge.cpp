// `iblx converge`: speed against error (docs/DESIGN.md §7). Runs methods x sequences x seeds on one scene,
// records MSE and relMSE against the ground truth after each point of a log-spaced sample schedule, and
// writes the CSV, the summary table and the PNG figures.
#include "engine/analysis/convergence.h"
#include "engine/core/csv.h"
#include "engine/core/error.h"
#include "engine/core/file_lock.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/io/image_write.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"
#include "tools/cli/converge_figures.h"
#include "tools/cli/converge_scene.h"
#include "engine/render/oracle.h"
#include "tools/cli/measurement.h"
#include "tools/cli/report_html.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

namespace iblx::cli {

namespace {

// The flags of `iblx converge`: those it shares with `iblx study` (the scene, the measurement and the ground
// truth; --json and the device flags land in their RenderSpec) and the outputs'.
struct ConvergeOptions {
  ConvergeSceneFlags sceneFlags;
  std::filesystem::path outDir = "converge";
  double targetRelMse = 1e-3;
  bool plots = true;
  bool oracle = false;   // --oracle
  int oracleStride = 1;  // --oracle-stride
};

// Declares the flags and parses `args`; none when --help was answered.
std::optional<ConvergeOptions> parseConvergeOptions(const Args& args) {
  ConvergeOptions options;
  RenderSpec& render = options.sceneFlags.render;
  ArgParser parser("converge");
  addConvergeSceneFlags(parser, options.sceneFlags);
  addDeviceFlags(parser, render);
  parser.value(
      "--target-relmse", "X", "the error whose time to reach is reported (default 1e-3)",
      [&](const std::string& v) { options.targetRelMse = parseDouble("--target-relmse", v, 1e-12, 1e6); });
  parser.value("--out-dir", "DIR", "where the CSV, summary and figures go (default ./converge; created)",
               [&](const std::string& v) { options.outDir = v; });
  parser.toggle("--no-plots", "write no PNG figures", [&] { options.plots = false; });
  parser.toggle(
      "--oracle",
      "also compute the oracle's variance (the limit of a luminance pdf over the map's texels; about "
      "three ground truths) and give each method's MSE·spp and relMSE·spp as a multiple of it",
      [&] { options.oracle = true; });
  parser.value(
      "--oracle-stride", "K",
      "with --oracle: compute it on the centre pixel of every K x K block only (K^2 times cheaper; "
      "its figures are then estimates over those pixels; default 1, every pixel)",
      [&](const std::string& v) { options.oracleStride = int(parseUint("--oracle-stride", v, 1, 64)); });
  parser.toggle("--json", "print the summary as one JSON object per method instead of the table",
                [&] { render.json = true; });
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (options.oracleStride != 1 && !options.oracle) throw Error("--oracle-stride: needs --oracle");
  finishConvergeSceneFlags(options.sceneFlags);
  return options;
}

std::string budgetText(const ConvergenceBudget& budget) {
  char text[64];
  if (budget.seconds)
    std::snprintf(text, sizeof text, "%g s of rendering", *budget.seconds);
  else
    std::snprintf(text, sizeof text, "%llu spp", static_cast<unsigned long long>(budget.maxSpp));
  return text;
}

// Every method with every seed, until the budget or Ctrl-C (which keeps the runs measured so far); warns of
// what was skipped and throws when nothing was measured.
ConvergenceResult measureConvergence(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, const ObtainedReference& obtained,
                                     const std::vector<ResolvedMethod>& methods,
                                     const std::vector<std::uint32_t>& seeds,
                                     const ConvergenceBudget& budget) {
  ConvergenceResult result;
  {
    InterruptGuard interrupt;
    result = runConvergence(context, compiler, scene, obtained.rgb, methods, seeds, budget, showProgress,
                            &interrupt.flag(), obtained.noise);
  }
  endProgressLine();
  if (result.interrupted)
    warn("interrupted: keeping the " + std::to_string(result.runs.size()) + " runs measured so far");
  for (const auto& skipped : result.skipped)
    warn(skipped.method + "/" + skipped.sequence + " skipped: " + skipped.reason);
  if (result.runs.empty())
    throw Error(result.interrupted ? "interrupted before any measurement"
                                   : "no method could run on this device");
  return result;
}

// The PNG figures written into --out-dir (none with --no-plots): file names.
struct ConvergeFigures {
  std::vector<std::string> plotFiles, heatMaps, finalImages;
};

// report.html: the setting, the summary table and the figures.
void writeConvergeHtml(const ConvergeOptions& options, const std::string& sceneTitle,
                       const std::string& setting, const ConvergenceSummary& summary,
                       const ConvergeFigures& figures, const ConvergenceResult& result, const Scene& scene,
                       const ConvergenceBudget& budget) {
  const std::filesystem::path& outDir = options.outDir;
  HtmlReport report("iblx converge: " + sceneTitle);
  report.paragraph(setting);
  report.heading("Summary");
  report.paragraph(
      "Equal time: the end of the shortest run. × best: MSE at equal time over the best method's. "
      "Click a column's header to sort by it.");
  report.table(summaryTable(summary));
  if (options.plots) {
    std::vector<HtmlReport::Figure> plotFigures, finalFigures, heatFigures;
    for (const auto& f : figures.plotFiles) plotFigures.push_back({f, outDir / f});
    finalFigures.push_back({"reference (ground truth)", outDir / figures.finalImages.front()});
    for (std::size_t i = 0; i < result.images.size(); ++i) {
      finalFigures.push_back({imageCaption(result.images[i]), outDir / figures.finalImages[i + 1]});
      heatFigures.push_back({imageCaption(result.images[i]), outDir / figures.heatMaps[i]});
    }
    const int imageWidth = std::max(scene.gbuffer.width, 192);
    report.heading("Error against samples and time");
    report.figures(plotFigures, 620);
    report.heading(budget.seconds ? "Final images at equal time" : "Final images at equal samples");
    report.paragraph(
        "The first seed's image of each method at the end of its run, beside the reference, all "
        "under the reference's display transform (automatic exposure, ACES), so brightness compares.");
    report.figures(finalFigures, imageWidth);
    report.heading("Per-pixel error");
    report.paragraph("Relative squared error (x - r)^2 / (r^2 + 0.01) of the same images, on one log scale.");
    report.figures(heatFigures, 0);
  }
  report.write(outDir / "report.html");
}

// oracle_pixels.csv: per method and object pixel of the oracle, where the method's MSE·spp lies
// (oraclePixelErrors, engine/render/oracle.h), from its first seed's final image.
void writeOraclePixelsCsv(const std::filesystem::path& path, const OracleVariance& oracle,
                          const GBuffer& gbuffer, const ConvergenceResult& result) {
  AtomicOutput output(path);
  std::ofstream& out = output.stream();
  out << "method,sequence,x,y,oracle_mean,oracle_variance,squared_error_spp\n";
  char line[192];
  for (const auto& image : result.images)
    for (const OraclePixelError& p : oraclePixelErrors(oracle, gbuffer, image.rgb, image.point.spp)) {
      std::snprintf(line, sizeof line, ",%s,%d,%d,%.9g,%.9g,%.9g\n", image.sequence.c_str(), p.x, p.y, p.mean,
                    p.variance, p.squaredErrorTimesSpp);
      out << csvQuoted(image.method) << line;  // a method label holds commas
    }
  output.commit();
}

// The CSV, reference.exr, the figures, summary.md and report.html, then the summary on stdout (a table, or
// JSON with --json) and a warning per method with non-finite estimates.
void writeConvergeOutputs(const ConvergeOptions& options, const std::string& deviceName, const Scene& scene,
                          const std::string& sceneTitle, const ObtainedReference& obtained,
                          const std::optional<OracleVariance>& oracle, const ConvergenceResult& result,
                          const ConvergenceBudget& budget, std::size_t seedCount) {
  const std::filesystem::path& outDir = options.outDir;
  const std::vector<float>& reference = obtained.rgb;
  writeConvergenceCsv(outDir / "converge.csv", result.runs);
  writeExr(outDir / "reference.exr", scene.gbuffer.width, scene.gbuffer.height, reference);
  ConvergenceSummary summary = summarize(result.runs, options.targetRelMse);
  summary.referenceNoiseMse = obtained.noise.mse;
  summary.referenceNoiseRelMse = obtained.noise.relMse;
  if (oracle) {
    writeOraclePixelsCsv(outDir / "oracle_pixels.csv", *oracle, scene.gbuffer, result);
    addOracle(summary, oracle->mseTimesSpp, oracle->relMseTimesSpp, oracle->pixelStride);
    // On a sample of pixels, each method is measured on the same pixels: its first seed's final image.
    if (oracle->pixelStride > 1 && oracle->mseTimesSpp > 0.0 && oracle->relMseTimesSpp > 0.0)
      for (auto& row : summary.rows)
        for (const auto& image : result.images)
          if (image.method == row.method && image.sequence == row.sequence) {
            const OraclePixelsError e =
                errorOnOraclePixels(*oracle, scene.gbuffer, image.rgb, image.point.spp);
            row.mseOverOracle = e.mseTimesSpp / oracle->mseTimesSpp;
            row.relMseOverOracle = e.relMseTimesSpp / oracle->relMseTimesSpp;
          }
  }
  ConvergeFigures figures;
  if (options.plots) {
    figures.plotFiles = writeConvergencePlots(outDir, sceneTitle, result.runs, obtained.noise);
    figures.heatMaps = writeErrorHeatMaps(outDir, scene.gbuffer, result.images, reference);
    figures.finalImages = writeFinalImages(outDir, scene.gbuffer, result.images, reference);
  }
  const std::size_t figureCount =
      figures.plotFiles.size() + figures.heatMaps.size() + figures.finalImages.size();
  const std::string table = formatSummaryTable(summary);
  const std::string setting = "Device: " + deviceName + ". Seeds: " + std::to_string(seedCount) +
                              ". Budget per run: " + budgetText(budget) +
                              (result.interrupted ? " (interrupted)" : "") +
                              ". Reference: " + obtained.description + ".";
  writeFileAtomically(outDir / "summary.md",
                      "# iblx converge: " + sceneTitle + "\n\n" + setting + "\n\n" + table);
  writeConvergeHtml(options, sceneTitle, setting, summary, figures, result, scene, budget);
  const RenderSpec& render = options.sceneFlags.render;
  if (render.json) {
    std::size_t nulls = 0;
    std::fputs(formatSummaryJson(summary, &nulls).c_str(), stdout);
    if (nulls > 0)
      warn(std::to_string(nulls) +
           " figures are null in the JSON: not measured (a target never reached, an "
           "equal time beyond a run)");
  } else
    std::printf("%s\nwrote %s: converge.csv, summary.md, report.html, reference.exr and %zu figures\n",
                table.c_str(), outDir.string().c_str(), figureCount);
  for (const auto& row : summary.rows)
    if (row.nonFiniteSamples || !row.finite)
      warn(row.method + "/" + row.sequence + ": " +
           nonFiniteEstimatesMessage(row.nonFiniteSamples, render.scene.brdf));
}

// The oracle's variance with progress; Ctrl-C abandons it between dispatches (exit 130).
OracleVariance computeOracle(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                             int pixelStride) {
  InterruptGuard interrupt;
  ReferenceOptions options;
  options.progress = interruptibleProgress(interrupt, "oracle", "the oracle");
  OracleVariance oracle = computeOracleVariance(context, compiler, scene, options, pixelStride);
  const std::string pixels = pixelStride > 1 ? " (the centre pixel of every " + std::to_string(pixelStride) +
                                                   "x" + std::to_string(pixelStride) + " block)"
                                             : "";
  std::fprintf(stderr, "oracle: MSE·spp %.4g, relMSE·spp %.4g%s, computed in %.2f s\n", oracle.mseTimesSpp,
               oracle.relMseTimesSpp, pixels.c_str(), oracle.seconds);
  return oracle;
}

int runConverge(const ConvergeOptions& options) {
  const ConvergeSceneFlags& flags = options.sceneFlags;
  const RenderSpec& render = flags.render;
  const MeasurementSpec& spec = flags.spec;

  // Everything a user can get wrong is checked before anything heavy.
  const HardCase* hardCase = flags.hardCase();
  const ConvergenceBudget budget = spec.finalBudget();
  LoadedBrdf brdf = checkConvergeScene(flags);

  VulkanContext context({render.device, render.validation ? Validation::On : Validation::Auto});
  Scene scene = loadConvergeScene(context, flags, std::move(brdf));
  const std::vector<ResolvedMethod> methods = resolveMethods(spec, *scene.brdf);
  const std::vector<std::uint32_t> seeds = seedList(spec);
  checkOutDir(options.outDir);
  ShaderCompiler compiler;
  const ObtainedReference obtained = obtainReference(context, compiler, scene, hardCase, spec);
  const std::optional<OracleVariance> oracle =
      options.oracle ? std::optional(computeOracle(context, compiler, scene, options.oracleStride))
                     : std::nullopt;
  // Created once the inputs have been checked (nothing is written for bad input), before the long part.
  const FileLock outDirLock = claimOutDir(options.outDir);

  const std::string sceneTitle = convergeSceneTitle(flags, scene);
  std::fprintf(stderr, "converge: %zu methods x %zu seeds on %s (%s)\n", methods.size(), seeds.size(),
               context.deviceName().c_str(), sceneTitle.c_str());
  const ConvergenceResult result =
      measureConvergence(context, compiler, scene, obtained, methods, seeds, budget);
  writeConvergeOutputs(options, context.deviceName(), scene, sceneTitle, obtained, oracle, result, budget,
                       seeds.size());
  return result.interrupted ? 130 : 0;
}

}  // namespace

int cmdConverge(const Args& args) {
  if (const std::optional<ConvergeOptions> options = parseConvergeOptions(args)) return runConverge(*options);
  return 0;
}

}  // namespace iblx::cli
