// `iblx hardcases`: the hard-case suite (docs/DESIGN.md §5). Runs every method on each case and checks that
// the output is finite and converges to the reference (z-test of the image-mean error, family-wise
// false-alarm rate 1e-3), then ranks the methods by MSE at equal time. Exit status 1 when any check fails.
#include "engine/analysis/convergence.h"
#include "engine/core/error.h"
#include "engine/core/json_output.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/converge_figures.h"
#include "tools/cli/measurement.h"
#include "tools/cli/report_html.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <numeric>

namespace iblx::cli {

int cmdHardCases(const Args& args) {
  RenderSpec render;
  MeasurementSpec spec;
  spec.seeds = 1;
  spec.budget.firstSpp = 16;
  spec.defaultMaxSpp = 512;
  std::vector<std::string> caseNames;
  bool list = false, quick = false;
  double familyAlpha = 1e-3;
  std::filesystem::path outDir;
  ArgParser parser("hardcases");
  parser.toggle("--list", "list the cases and exit", [&] { list = true; });
  parser.value("--case", "NAME", "only this case (repeatable; default: every case)",
               [&](const std::string& v) { caseNames.push_back(findHardCase(v).name); });
  parser.toggle("--quick", "the test sizes: small maps (64 texels wide for most cases) and 24 px images",
                [&] { quick = true; });
  addMeasurementFlags(parser, spec);
  addDeviceFlags(parser, render);
  parser.value("--alpha", "A", "family-wise false-alarm rate of the z-tests (default 1e-3)",
               [&](const std::string& v) { familyAlpha = parseDouble("--alpha", v, 1e-12, 0.5); });
  parser.value("--out-dir", "DIR",
               "also write one CSV per case, hardcases.md, report.html and the final images there",
               [&](const std::string& v) { outDir = v; });
  parser.toggle("--json", "one JSON object per case and method instead of the tables",
                [&] { render.json = true; });
  if (parser.parseOrShowHelp(args)) return 0;
  if (list) {
    for (const auto& c : hardCases()) std::printf("%-12s %s\n", c.name.c_str(), c.description.c_str());
    return 0;
  }
  if (caseNames.empty())
    for (const auto& c : hardCases()) caseNames.push_back(c.name);
  const ConvergenceBudget budget = spec.finalBudget();
  if (!outDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (!std::filesystem::is_directory(outDir))
      throw Error("--out-dir " + outDir.string() + ": cannot create it");
  }
  VulkanContext context({render.device, render.validation ? Validation::On : Validation::Auto});
  ShaderCompiler compiler;
  std::ostringstream markdown;
  HtmlReport report("iblx hardcases on " + context.deviceName());
  report.paragraph(
      "Each case renders with every method; a method passes when its image is finite, no estimate was "
      "NaN or Inf, and its z-test of the mean signed error stays inside the bound. Rows are ranked "
      "by MSE at equal time; click a column's header to sort by it.");
  int failures = 0, skippedRuns = 0;
  InterruptGuard interrupt;
  // A case that could not run (a device limit): its heading and why, on the terminal and in both reports.
  const auto reportNotRun = [&](const std::string& name, const std::string& why) {
    const std::string note = "### " + name + "\n\n" + why + "\n";
    if (!render.json) std::printf("%s\n", note.c_str());
    markdown << note << "\n";
    report.heading(name);
    report.paragraph(why);
  };
  for (const auto& name : caseNames) {
    const HardCase& hardCase = findHardCase(name);
    const Scene scene = makeHardCaseScene(hardCase, quick ? HardCaseSize::Test : HardCaseSize::Full);
    std::vector<ResolvedMethod> methods = resolveMethods(spec, *scene.brdf);
    std::string excluded;
    if (spec.methods.empty())  // the case's exclusions apply to the default list, not to asked-for methods
      std::erase_if(methods, [&](const ResolvedMethod& m) {
        const auto& names = hardCase.excludedMethods;
        if (std::find(names.begin(), names.end(), m.method->name) == names.end()) return false;
        if (excluded.find(m.method->name) == std::string::npos)
          excluded += (excluded.empty() ? "" : ", ") + m.method->name;
        return true;
      });
    ConvergenceResult result;
    std::vector<float> reference;
    try {
      reference = obtainReference(context, compiler, scene, &hardCase, spec).rgb;
      result = runConvergence(context, compiler, scene, reference, methods, seedList(spec), budget,
                              showProgress, &interrupt.flag());
    } catch (const DeviceLimitError& e) {
      endProgressLine();
      reportNotRun(name, "Skipped on " + context.deviceName() + ": " + e.what());
      continue;
    }
    endProgressLine();
    if (result.runs.empty() && (result.interrupted || result.skipped.empty())) break;
    skippedRuns += int(result.skipped.size());
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
      reportNotRun(name, why);
      continue;
    }
    if (!outDir.empty()) writeConvergenceCsv(outDir / (name + ".csv"), result.runs);
    const ConvergenceSummary summary = summarize(result.runs, 1e-3);
    const double zBound = familyZBound(familyAlpha, 3 * result.runs.size());
    std::vector<std::size_t> rank(summary.rows.size());
    std::iota(rank.begin(), rank.end(), 0);
    std::stable_sort(rank.begin(), rank.end(), [&](auto a, auto b) {
      return summary.rows[a].equalTimeRatio < summary.rows[b].equalTimeRatio;
    });
    std::ostringstream intro;
    intro << hardCase.description << ". Env " << scene.env.width << "x" << scene.env.height << ", "
          << scene.gbuffer.width << "x" << scene.gbuffer.height << " px, " << summary.rows.front().spp
          << " spp, |z| bound " << std::to_string(zBound).substr(0, 4)
          << (hardCase.zTested ? "" : " (not judged: rare tail events this budget has not sampled)") << "."
          << (excluded.empty() ? "" : " Not run: " + excluded + " (" + hardCase.exclusionReason + ").");
    TextTable table;
    table.headers = {"rank",    "method",  "seq",  "relMSE", "MSE × best at equal time",
                     "max |z|", "NaN/Inf", "check"};
    table.rightAligned = {true, false, false, true, true, true, true, false};
    for (std::size_t position = 0; position < rank.size(); ++position) {
      const auto& r = summary.rows[rank[position]];
      const bool ok = r.finite && r.nonFiniteSamples == 0 && (!hardCase.zTested || r.maxAbsZ < zBound);
      failures += !ok;
      char relMse[32], ratio[32], z[32];
      std::snprintf(relMse, sizeof relMse, "%.3g", r.relMse);
      std::snprintf(ratio, sizeof ratio, "%.2f", r.equalTimeRatio);
      std::snprintf(z, sizeof z, "%.2f", r.maxAbsZ);
      table.rows.push_back({std::to_string(position + 1), r.method, r.sequence, relMse, ratio, z,
                            std::to_string(r.nonFiniteSamples), ok ? "pass" : "FAIL"});
      if (render.json)
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
    const std::string text = "### " + name + "\n\n" + intro.str() + "\n\n" + formatMarkdownTable(table);
    if (!render.json) std::printf("%s\n", text.c_str());
    std::fflush(stdout);
    markdown << text << "\n";
    report.heading(name);
    report.paragraph(intro.str());
    report.table(table);
    if (!outDir.empty()) {
      // The final images under the reference's display transform, in images/ beside the report.
      const std::filesystem::path imageDir = outDir / "images" / name;
      std::filesystem::create_directories(imageDir);
      const std::vector<std::string> files =
          writeFinalImages(imageDir, scene.gbuffer, result.images, reference);
      std::vector<HtmlReport::Figure> figures = {{"reference", imageDir / files.front()}};
      for (std::size_t i = 0; i < result.images.size(); ++i)
        figures.push_back({imageCaption(result.images[i]), imageDir / files[i + 1]});
      report.figures(figures, std::max(scene.gbuffer.width, 128));
    }
    if (result.interrupted) {
      warn("interrupted: the remaining cases were not run");
      break;
    }
  }
  if (!outDir.empty()) {
    writeFileAtomically(outDir / "hardcases.md",
                        "# iblx hardcases on " + context.deviceName() + "\n\n" + markdown.str());
    report.write(outDir / "report.html");
  }
  if (failures) {
    std::fprintf(stderr, "iblx hardcases: %d method(s) failed a check\n", failures);
    return 1;
  }
  if (skippedRuns)
    std::fprintf(stderr, "iblx hardcases: every method that ran passed; %d skipped at a device limit\n",
                 skippedRuns);
  else
    std::fprintf(stderr, "iblx hardcases: every method passed on every case\n");
  return interrupt.flag().load() ? 130 : 0;
}

}  // namespace iblx::cli
