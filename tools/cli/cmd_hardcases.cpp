// `iblx hardcases`: the hard-case suite (DESIGN §5). Runs every method on each case and checks that the
// output is finite and converges to the reference (z-test of the image-mean error, family-wise false-alarm
// rate 1e-3), then ranks the methods by MSE at equal time. Exit status 1 when any check fails.
#include "engine/analysis/convergence.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/measurement.h"

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
  parser.value("--out-dir", "DIR", "also write one CSV per case and hardcases.md there",
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
  int failures = 0;
  InterruptGuard interrupt;
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
    try {
      const std::vector<float> reference = obtainReference(context, compiler, scene, &hardCase, spec);
      result = runConvergence(context, compiler, scene, reference, methods, seedList(spec), budget,
                              showProgress, &interrupt.flag());
    } catch (const DeviceLimitError& e) {
      endProgressLine();
      const std::string note =
          "### " + name + "\n\nSkipped on " + context.deviceName() + ": " + e.what() + "\n";
      std::printf("%s\n", note.c_str());
      markdown << note << "\n";
      continue;
    }
    endProgressLine();
    if (result.runs.empty()) break;
    if (!outDir.empty()) writeConvergenceCsv(outDir / (name + ".csv"), result.runs);
    const ConvergenceSummary summary = summarize(result.runs, 1e-3);
    const double zBound = familyZBound(familyAlpha, 3 * result.runs.size());
    std::vector<std::size_t> rank(summary.rows.size());
    std::iota(rank.begin(), rank.end(), 0);
    std::stable_sort(rank.begin(), rank.end(), [&](auto a, auto b) {
      return summary.rows[a].equalTimeRatio < summary.rows[b].equalTimeRatio;
    });
    std::ostringstream table;
    table << "### " << name << "\n\n"
          << hardCase.description << ". Env " << scene.env.width << "x" << scene.env.height << ", "
          << scene.gbuffer.width << "x" << scene.gbuffer.height << " px, " << summary.rows.front().spp
          << " spp, |z| bound " << std::to_string(zBound).substr(0, 4)
          << (hardCase.zTested ? "" : " (not judged: rare tail events this budget has not sampled)")
          << "." << (excluded.empty() ? "" : " Not run: " + excluded + " (" + hardCase.exclusionReason + ").")
          << "\n\n"
          << "| rank | method | seq | relMSE | MSE × best at equal time | max |z| | NaN/Inf | check |\n"
          << "|---:|---|---|---:|---:|---:|---:|---|\n";
    for (std::size_t position = 0; position < rank.size(); ++position) {
      const auto& r = summary.rows[rank[position]];
      const bool ok = r.finite && r.nonFiniteSamples == 0 && (!hardCase.zTested || r.maxAbsZ < zBound);
      failures += !ok;
      char line[512];
      std::snprintf(line, sizeof line, "| %zu | %s | %s | %.3g | %.2f | %.2f | %u | %s |\n", position + 1,
                    r.method.c_str(), r.sequence.c_str(), r.relMse, r.equalTimeRatio, r.maxAbsZ,
                    r.nonFiniteSamples, ok ? "pass" : "FAIL");
      table << line;
      if (render.json)
        std::printf(
            "{\"case\": \"%s\", \"rank\": %zu, \"method\": \"%s\", \"sequence\": \"%s\", \"spp\": %llu, "
            "\"relmse\": %.6g, \"equal_time_ratio\": %.6g, \"max_abs_z\": %.4g, \"z_bound\": %.4g, "
            "\"non_finite\": %u, \"finite\": %s, \"pass\": %s}\n",
            name.c_str(), position + 1, jsonEscape(r.method).c_str(), r.sequence.c_str(),
            static_cast<unsigned long long>(r.spp), r.relMse, r.equalTimeRatio, r.maxAbsZ, zBound,
            r.nonFiniteSamples, r.finite ? "true" : "false", ok ? "true" : "false");
    }
    for (const auto& skipped : result.skipped)
      table << "| — | " << skipped.method << " | " << skipped.sequence << " | skipped: " << skipped.reason
            << " | | | | |\n";
    if (!render.json) std::printf("%s\n", table.str().c_str());
    std::fflush(stdout);
    markdown << table.str() << "\n";
    if (result.interrupted) {
      warn("interrupted: the remaining cases were not run");
      break;
    }
  }
  if (!outDir.empty()) {
    writeFileAtomically(outDir / "hardcases.md",
                        "# iblx hardcases on " + context.deviceName() + "\n\n" + markdown.str());
  }
  if (failures) {
    std::fprintf(stderr, "iblx hardcases: %d method(s) failed a check\n", failures);
    return 1;
  }
  std::fprintf(stderr, "iblx hardcases: every method passed on every case\n");
  return interrupt.flag().load() ? 130 : 0;
}

}  // namespace iblx::cli
