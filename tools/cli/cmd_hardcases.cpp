// `iblx hardcases`: the hard-case suite (docs/DESIGN.md §5). Runs every method on each case and checks that
// the output is finite and converges to the reference (z-test of the image-mean error, family-wise
// false-alarm rate 1e-3), then ranks the methods by MSE at equal time. Exit status 1 when any check fails.
#include "engine/analysis/convergence.h"
#include "engine/core/error.h"
#include "engine/core/json_output.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"
#include "tools/cli/converge_figures.h"
#include "tools/cli/measurement.h"
#include "tools/cli/report_html.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace iblx::cli {

namespace {

// The flags of `iblx hardcases`.
struct HardCasesOptions {
  RenderSpec render;                   // --json and the device flags
  MeasurementSpec spec;                // the measurement flags, over the suite's defaults
  std::vector<std::string> caseNames;  // every case when no --case was given
  bool quick = false;
  double familyAlpha = 1e-3;
  std::filesystem::path outDir;  // empty: no files
};

// Declares the flags and parses `args`; none when --help or --list was answered.
std::optional<HardCasesOptions> parseHardCasesOptions(const Args& args) {
  HardCasesOptions options;
  RenderSpec& render = options.render;
  MeasurementSpec& spec = options.spec;
  spec.seeds = 1;
  spec.budget.firstSpp = 16;
  spec.defaultMaxSpp = 512;
  bool list = false;
  ArgParser parser("hardcases");
  parser.toggle("--list", "list the cases and exit", [&] { list = true; });
  parser.value("--case", "NAME", "only this case (repeatable; default: every case)",
               [&](const std::string& v) { options.caseNames.push_back(findHardCase(v).name); });
  parser.toggle("--quick", "the test sizes: small maps (64 texels wide for most cases) and 24 px images",
                [&] { options.quick = true; });
  addMeasurementFlags(parser, spec);
  addDeviceFlags(parser, render);
  parser.value("--alpha", "A", "family-wise false-alarm rate of the z-tests (default 1e-3)",
               [&](const std::string& v) { options.familyAlpha = parseDouble("--alpha", v, 1e-12, 0.5); });
  parser.value("--out-dir", "DIR",
               "also write one CSV per case, hardcases.md, report.html and the final images there",
               [&](const std::string& v) { options.outDir = v; });
  parser.toggle("--json", "one JSON object per case and method instead of the tables",
                [&] { render.json = true; });
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (list) {
    for (const auto& c : hardCases()) std::printf("%-12s %s\n", c.name.c_str(), c.description.c_str());
    return std::nullopt;
  }
  if (options.caseNames.empty())
    for (const auto& c : hardCases()) options.caseNames.push_back(c.name);
  return options;
}

// The suite's reports as the cases add to them (hardcases.md and report.html), and the counts its exit
// status comes from.
struct SuiteReport {
  explicit SuiteReport(const std::string& title) : html(title) {}
  std::ostringstream markdown;
  HtmlReport html;
  int failures = 0, skippedRuns = 0;
};

// A case that could not run (a device limit): its heading and why, on the terminal and in both reports.
void reportNotRun(SuiteReport& suite, bool json, const std::string& name, const std::string& why) {
  const std::string note = "### " + name + "\n\n" + why + "\n";
  if (!json) std::printf("%s\n", note.c_str());
  suite.markdown << note << "\n";
  suite.html.heading(name);
  suite.html.paragraph(why);
}

// The methods run on `hardCase`; the case's exclusions it dropped are named in `excluded` ("a, b").
std::vector<ResolvedMethod> caseMethods(const MeasurementSpec& spec, const HardCase& hardCase,
                                        const BrdfInfo& brdf, std::string& excluded) {
  std::vector<ResolvedMethod> methods = resolveMethods(spec, brdf);
  if (spec.methods.empty())  // the case's exclusions apply to the default list, not to asked-for methods
    std::erase_if(methods, [&](const ResolvedMethod& m) {
      const auto& names = hardCase.excludedMethods;
      if (std::find(names.begin(), names.end(), m.method->name) == names.end()) return false;
      if (excluded.find(m.method->name) == std::string::npos)
        excluded += (excluded.empty() ? "" : ", ") + m.method->name;
      return true;
    });
  return methods;
}

// One case's methods, checked and ranked by MSE at equal time.
struct RankedCase {
  std::string intro;  // the case, its sizes, budget and z bound, and the methods not run
  TextTable table;
  int failures = 0;  // methods that failed a check
};

// Checks each method that ran (a finite image, no NaN or Inf estimate, the z-test) and ranks them; with
// --json prints one JSON object per method.
RankedCase rankCase(const HardCasesOptions& options, const std::string& name, const HardCase& hardCase,
                    const Scene& scene, const ConvergenceResult& result, const std::string& excluded) {
  const ConvergenceSummary summary = summarize(result.runs, 1e-3);
  const double zBound = familyZBound(options.familyAlpha, 3 * result.runs.size());
  std::vector<std::size_t> rank(summary.rows.size());
  std::iota(rank.begin(), rank.end(), 0);
  std::stable_sort(rank.begin(), rank.end(), [&](auto a, auto b) {
    return summary.rows[a].equalTimeRatio < summary.rows[b].equalTimeRatio;
  });
  RankedCase ranked;
  std::ostringstream intro;
  intro << hardCase.description << ". Env " << scene.env.width << "x" << scene.env.height << ", "
        << scene.gbuffer.width << "x" << scene.gbuffer.height << " px, " << summary.rows.front().spp
        << " spp, |z| bound " << std::to_string(zBound).substr(0, 4)
        << (hardCase.zTested ? "" : " (not judged: rare tail events this budget has not sampled)") << "."
        << (excluded.empty() ? "" : " Not run: " + excluded + " (" + hardCase.exclusionReason + ").");
  ranked.intro = intro.str();
  TextTable& table = ranked.table;
  table.headers = {"rank",    "method",  "seq",  "relMSE", "MSE × best at equal time",
                   "max |z|", "NaN/Inf", "check"};
  table.rightAligned = {true, false, false, true, true, true, true, false};
  for (std::size_t position = 0; position < rank.size(); ++position) {
    const auto& r = summary.rows[rank[position]];
    const bool ok = r.finite && r.nonFiniteSamples == 0 && (!hardCase.zTested || r.maxAbsZ < zBound);
    ranked.failures += !ok;
    char relMse[32], ratio[32], z[32];
    std::snprintf(relMse, sizeof relMse, "%.3g", r.relMse);
    std::snprintf(ratio, sizeof ratio, "%.2f", r.equalTimeRatio);
    std::snprintf(z, sizeof z, "%.2f", r.maxAbsZ);
    table.rows.push_back({std::to_string(position + 1), r.method, r.sequence, relMse, ratio, z,
                          std::to_string(r.nonFiniteSamples), ok ? "pass" : "FAIL"});
    if (options.render.json)
      printJsonLine({{"case", name},
                     {"rank", position + 1},
                     {"method", r.method},
                     {"sequence", r.sequence},
                     {"spp", r.spp},
                     {"relmse", r.relMse},
                     {"equal_time_ratio", r.equalTimeRatio},
                     {"max_abs_z", r.maxAbsZ},
                     {"z_bound", zBound},
                     {"non_finite", r.nonFiniteSamples},
                     {"finite", r.finite},
                     {"pass", ok}});
  }
  for (const auto& skipped : result.skipped)
    table.rows.push_back(
        {"—", skipped.method, skipped.sequence, "skipped: " + skipped.reason, "", "", "", ""});
  return ranked;
}

// The final images under the reference's display transform, in images/ beside the report.
void addCaseImages(HtmlReport& report, const std::filesystem::path& outDir, const std::string& name,
                   const Scene& scene, const ConvergenceResult& result, const std::vector<float>& reference) {
  const std::filesystem::path imageDir = outDir / "images" / name;
  std::filesystem::create_directories(imageDir);
  const std::vector<std::string> files = writeFinalImages(imageDir, scene.gbuffer, result.images, reference);
  std::vector<HtmlReport::Figure> figures = {{"reference", imageDir / files.front()}};
  for (std::size_t i = 0; i < result.images.size(); ++i)
    figures.push_back({imageCaption(result.images[i]), imageDir / files[i + 1]});
  report.figures(figures, std::max(scene.gbuffer.width, 128));
}

// Runs every method on the case `name` and adds it to `suite`. False when the remaining cases are not run
// (Ctrl-C, or no method to run).
bool runCase(const HardCasesOptions& options, const VulkanContext& context, ShaderCompiler& compiler,
             const ConvergenceBudget& budget, const InterruptGuard& interrupt, const std::string& name,
             SuiteReport& suite) {
  const MeasurementSpec& spec = options.spec;
  const bool json = options.render.json;
  const HardCase& hardCase = findHardCase(name);
  const Scene scene = makeHardCaseScene(hardCase, options.quick ? HardCaseSize::Test : HardCaseSize::Full);
  std::string excluded;
  const std::vector<ResolvedMethod> methods = caseMethods(spec, hardCase, *scene.brdf, excluded);
  ConvergenceResult result;
  std::vector<float> reference;
  try {
    reference = obtainReference(context, compiler, scene, &hardCase, spec).rgb;
    result = runConvergence(context, compiler, scene, reference, methods, seedList(spec), budget,
                            showProgress, &interrupt.flag());
  } catch (const DeviceLimitError& e) {
    endProgressLine();
    reportNotRun(suite, json, name, "Skipped on " + context.deviceName() + ": " + e.what());
    return true;
  }
  endProgressLine();
  if (result.runs.empty() && (result.interrupted || result.skipped.empty())) return false;
  suite.skippedRuns += int(result.skipped.size());
  if (result.runs.empty()) {
    // Every method asked for was skipped (a table above a device limit): say which and why, and go on.
    std::string why = hardCase.description + ". Nothing ran on " + context.deviceName() + ":\n";
    for (const auto& skipped : result.skipped)
      why.append("\n- ")
          .append(skipped.method)
          .append("/")
          .append(skipped.sequence)
          .append(": ")
          .append(skipped.reason);
    reportNotRun(suite, json, name, why);
    return true;
  }
  if (!options.outDir.empty()) writeConvergenceCsv(options.outDir / (name + ".csv"), result.runs);
  const RankedCase ranked = rankCase(options, name, hardCase, scene, result, excluded);
  suite.failures += ranked.failures;
  const std::string text = "### " + name + "\n\n" + ranked.intro + "\n\n" + formatMarkdownTable(ranked.table);
  if (!json) std::printf("%s\n", text.c_str());
  std::fflush(stdout);
  suite.markdown << text << "\n";
  suite.html.heading(name);
  suite.html.paragraph(ranked.intro);
  suite.html.table(ranked.table);
  if (!options.outDir.empty()) addCaseImages(suite.html, options.outDir, name, scene, result, reference);
  if (result.interrupted) {
    warn("interrupted: the remaining cases were not run");
    return false;
  }
  return true;
}

int runHardCases(const HardCasesOptions& options) {
  const RenderSpec& render = options.render;
  const std::filesystem::path& outDir = options.outDir;
  const ConvergenceBudget budget = options.spec.finalBudget();
  std::optional<FileLock> outDirLock;
  if (!outDir.empty()) {
    checkOutDir(outDir);
    outDirLock.emplace(claimOutDir(outDir));
  }
  VulkanContext context({render.device, render.validation ? Validation::On : Validation::Auto});
  ShaderCompiler compiler;
  SuiteReport suite("iblx hardcases on " + context.deviceName());
  suite.html.paragraph(
      "Each case renders with every method; a method passes when its image is finite, no estimate was "
      "NaN or Inf, and its z-test of the mean signed error stays inside the bound. Rows are ranked "
      "by MSE at equal time; click a column's header to sort by it.");
  InterruptGuard interrupt;
  for (const auto& name : options.caseNames)
    if (!runCase(options, context, compiler, budget, interrupt, name, suite)) break;
  if (!outDir.empty()) {
    writeFileAtomically(outDir / "hardcases.md",
                        "# iblx hardcases on " + context.deviceName() + "\n\n" + suite.markdown.str());
    suite.html.write(outDir / "report.html");
  }
  if (suite.failures) {
    std::fprintf(stderr, "iblx hardcases: %d method(s) failed a check\n", suite.failures);
    return 1;
  }
  if (suite.skippedRuns)
    std::fprintf(stderr, "iblx hardcases: every method that ran passed; %d skipped at a device limit\n",
                 suite.skippedRuns);
  else
    std::fprintf(stderr, "iblx hardcases: every method passed on every case\n");
  return interrupt.flag().load() ? 130 : 0;
}

}  // namespace

int cmdHardCases(const Args& args) {
  if (const std::optional<HardCasesOptions> options = parseHardCasesOptions(args))
    return runHardCases(*options);
  return 0;
}

}  // namespace iblx::cli
