// `iblx study merge` (tools/cli/study_merge.h).
#include "tools/cli/study_merge.h"

#include "engine/analysis/convergence.h"
#include "engine/analysis/loss_decomposition.h"
#include "engine/core/csv.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json_output.h"
#include "engine/core/log.h"
#include "engine/io/env_image.h"
#include "tools/cli/converge_figures.h"
#include "tools/cli/report_html.h"
#include "tools/cli/study_records.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace iblx::cli {

namespace fs = std::filesystem;

namespace {

// What the first task to reach a scene left (cmd_study.cpp, writeSceneData).
struct SceneData {
  std::string title, reference, device;
  ReferenceNoise noise;
  GBuffer mask;  // object pixels only: normal.w
  std::vector<float> referenceRgb;
};

std::optional<SceneData> readSceneData(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir / "scene.json", ec)) return std::nullopt;
  try {
    const nlohmann::json json = nlohmann::json::parse(readInputText(dir / "scene.json", 64u << 20));
    SceneData data;
    data.title = json.at("title").get<std::string>();
    data.reference = json.at("reference").get<std::string>();
    data.device = json.at("device").get<std::string>();
    data.noise.mse = json.at("noise_mse").get<double>();
    data.noise.relMse = json.at("noise_relmse").get<double>();
    data.mask.width = json.at("width").get<int>();
    data.mask.height = json.at("height").get<int>();
    const std::string mask = json.at("object_mask").get<std::string>();
    if (mask.size() != std::size_t(data.mask.width) * std::size_t(data.mask.height))
      throw Error("object_mask has " + std::to_string(mask.size()) + " pixels");
    data.mask.pixels.resize(mask.size());
    for (std::size_t p = 0; p < mask.size(); ++p) data.mask.pixels[p].normal.w = mask[p] == '1' ? 1.0f : 0.0f;
    EnvImage reference = loadRgbImage(dir / "reference.exr");
    if (reference.width != data.mask.width || reference.height != data.mask.height)
      throw Error("reference.exr is not the scene's size");
    data.referenceRgb = std::move(reference.rgb);
    return data;
  } catch (const std::exception& e) {
    warn(dir.string() + ": " + e.what() + "; the scene's figures are left out");
    return std::nullopt;
  }
}

std::string numberText(double value) {
  if (!std::isfinite(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

std::string today() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d", std::gmtime(&now));
  return text;
}

// A plan method and sequence: one row of the matrices.
struct RowKey {
  std::string method, sequence;
  bool operator<(const RowKey& o) const {
    return std::tie(method, sequence) < std::tie(o.method, o.sequence);
  }
};

struct SceneResult {
  const StudyScene* scene = nullptr;
  std::vector<ConvergenceRun> runs;
  std::vector<ConvergenceImage> images;
  std::map<std::string, std::string> planMethodOfLabel;  // "mis(env-cdf+cosine, balance)" -> "mis"
  std::set<std::string> devices;
  std::vector<SamplerRuns> samplers;  // per plan method, in plan order: its random and sobol runs
  std::optional<ConvergenceSummary> summary;
  std::optional<TextTable> table;
  std::optional<SceneData> data;  // read once: the figures and the decomposition use it
};

// Keeps the files of `written` named in `keep` (by their stem, e.g. "relmse_vs_time"); removes the others.
std::vector<std::string> keepPlots(const fs::path& dir, const std::vector<std::string>& written,
                                   const std::optional<std::vector<std::string>>& keepList) {
  if (!keepList) return written;
  const std::vector<std::string>& keep = *keepList;
  std::vector<std::string> kept;
  for (const auto& file : written) {
    if (std::find(keep.begin(), keep.end(), fs::path(file).stem().string()) != keep.end())
      kept.push_back(file);
    else {
      std::error_code ec;
      fs::remove(dir / file, ec);
    }
  }
  return kept;
}

// The scene's summary row for a plan method and sequence; null when it has none.
const MethodSummary* summaryRow(const SceneResult& s, const RowKey& row, std::size_t* index = nullptr) {
  if (!s.summary) return nullptr;
  for (std::size_t i = 0; i < s.summary->rows.size(); ++i) {
    const MethodSummary& r = s.summary->rows[i];
    const auto it = s.planMethodOfLabel.find(r.method);
    if (it != s.planMethodOfLabel.end() && it->second == row.method && r.sequence == row.sequence) {
      if (index) *index = i;
      return &r;
    }
  }
  return nullptr;
}

// A matrix over scenes: one row per plan method and sequence, one column per scene, each cell cell(scene, i)
// of the scene's summary row i for that method and sequence, "—" where it has none.
TextTable matrix(const std::vector<RowKey>& rows, const std::vector<SceneResult>& scenes,
                 const std::function<std::string(const SceneResult&, std::size_t)>& cell) {
  TextTable t;
  t.headers = {"method", "seq"};
  t.rightAligned = {false, false};
  for (const auto& s : scenes) {
    t.headers.push_back(s.scene->name);
    t.rightAligned.push_back(true);
  }
  for (const auto& row : rows) {
    std::vector<std::string> cells = {row.method, row.sequence};
    for (const auto& s : scenes) {
      std::size_t i = 0;
      cells.push_back(summaryRow(s, row, &i) ? cell(s, i) : "—");
    }
    t.rows.push_back(std::move(cells));
  }
  return t;
}

constexpr const char* kDecompositionLegend =
    "Per scene, from the median curves over seeds (fits skip the first two points of six or more): C, the "
    "variance per sample with `random` (MSE = C / spp, slope fixed at -1); Q, the `sobol` MSE over C / N at "
    "the spp N each method reaches at equal GPU time T (the end of the shortest `sobol` run); the free "
    "log-log slopes; ns per sample (GPU time over spp x object pixels, `sobol`); R, the equal-time `sobol` "
    "MSE "
    "over the baseline's. R = pdf (C / C_h) x QMC (Q / Q_h at the same N) x cost ((N_h / N)^-b_h, b_h the "
    "baseline's `sobol` slope) x residual (the baseline's curve off its power law; 1 when it follows it). "
    "docs/STUDIES.md, \"Decomposition\".";

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// The image size a scene is rendered at: its last --size flag, "" for converge's default.
std::string sceneSize(const StudyScene& scene) {
  return sceneFlag(scene, "--size").value_or("");
}

// Across the scenes that `include` accepts: per plan method and sequence, its MSE and relMSE at equal time
// over each scene's best, as a geometric mean and the worst scene, and on how many scenes it is the best. A
// method that is never far behind is the one to default to, not only the one that wins most often.
TextTable acrossScenes(const std::vector<RowKey>& rows, const std::vector<SceneResult>& scenes,
                       const std::function<bool(const SceneResult&)>& include) {
  TextTable t;
  t.headers = {"method",
               "seq",
               "scenes",
               "best (MSE / relMSE)",
               "MSE × best: geometric mean",
               "worst",
               "relMSE × best: geometric mean",
               "worst"};
  t.rightAligned = {false, false, true, true, true, false, true, false};
  for (const auto& row : rows) {
    int count = 0, bestMse = 0, bestRel = 0;
    double logMse = 0.0, logRel = 0.0, worstMse = 0.0, worstRel = 0.0;
    std::string worstMseScene, worstRelScene;
    for (const auto& s : scenes) {
      const MethodSummary* found = include(s) ? summaryRow(s, row) : nullptr;
      if (!found) continue;
      const MethodSummary& r = *found;
      if (!(r.equalTimeRatio > 0.0) || !(r.equalTimeRelRatio > 0.0) || !std::isfinite(r.equalTimeRatio) ||
          !std::isfinite(r.equalTimeRelRatio))
        continue;
      ++count;
      bestMse += r.equalTimeRatio <= 1.0 ? 1 : 0;
      bestRel += r.equalTimeRelRatio <= 1.0 ? 1 : 0;
      logMse += std::log(r.equalTimeRatio);
      logRel += std::log(r.equalTimeRelRatio);
      if (r.equalTimeRatio > worstMse) worstMse = r.equalTimeRatio, worstMseScene = s.scene->name;
      if (r.equalTimeRelRatio > worstRel) worstRel = r.equalTimeRelRatio, worstRelScene = s.scene->name;
    }
    if (count == 0) continue;
    t.rows.push_back(
        {row.method, row.sequence, std::to_string(count),
         std::to_string(bestMse) + " / " + std::to_string(bestRel), format("%.3g", std::exp(logMse / count)),
         format("%.3g", worstMse) + " (" + worstMseScene + ")", format("%.3g", std::exp(logRel / count)),
         format("%.3g", worstRel) + " (" + worstRelScene + ")"});
  }
  return t;
}

// One scene's decomposition against `baseline` (engine/analysis/loss_decomposition.h): a table and the
// attribution of each method's R, or a line saying why there is none.
std::string decompositionSection(const std::string& baseline, const SceneResult& scene,
                                 const std::optional<SceneData>& data) {
  std::string text = "### " + scene.scene->name + "\n\n";
  std::vector<SamplerRuns> samplers;
  for (const auto& s : scene.samplers)
    if (!s.random.empty() && !s.sobol.empty()) samplers.push_back(s);
  const auto h = std::find_if(samplers.begin(), samplers.end(),
                              [&](const SamplerRuns& s) { return s.name == baseline; });
  if (h == samplers.end() || !data)
    return text + "No decomposition: " +
           (data ? baseline + " has no `random` and `sobol` runs here" : "no scene data") + ".\n\n";
  try {
    const LossDecomposition d =
        decomposeLoss(samplers, std::size_t(h - samplers.begin()), data->mask.objectPixelCount());
    TextTable t;
    t.headers = {"method", "C", "C / baseline", "Q", "slopes random / sobol", "ns / sample", "N at T", "R"};
    t.rightAligned = {false, true, true, true, true, true, true, true};
    for (const auto& r : d.rows)
      t.rows.push_back({r.name, format("%.3g", r.c), format("%.2f", r.cRatio), format("%.3g", r.q),
                        format("%.2f", r.slopeRandom) + " / " + format("%.2f", r.slopeSobol),
                        format("%.1f", r.nsPerSample), format("%.0f", r.spp), format("%.2f", r.ratio)});
    text += "Equal GPU time T = " + format("%.3g", d.equalTimeSeconds) + " s; " +
            std::to_string(data->mask.objectPixelCount()) +
            " object pixels; the baseline's `sobol` slope b_h = " + format("%.2f", d.baselineSlope) +
            ".\n\n" + formatMarkdownTable(t) + "\n";
    for (const auto& r : d.rows)
      if (r.name != baseline)
        text += "- `" + r.name + "`: R = " + format("%.2f", r.ratio) + " = pdf " + format("%.2f", r.pdf) +
                " × QMC " + format("%.2f", r.qmc) + " × cost " + format("%.2f", r.cost) +
                " (N = " + format("%.0f", r.spp) + " against " + format("%.0f", d.baselineSpp) +
                ") × residual " + format("%.2f", r.residual) + "\n";
    return text + "\n";
  } catch (const Error& e) {
    return text + "No decomposition: " + e.what() + ".\n\n";
  }
}

}  // namespace

MergeOutcome mergeStudy(const StudyPlan& plan, const std::vector<StudyRun>& runs) {
  MergeOutcome outcome;
  std::error_code ec;
  fs::create_directories(plan.reportDirectory, ec);
  if (!fs::is_directory(plan.reportDirectory))
    throw Error("cannot create the report directory " + plan.reportDirectory.string());

  std::vector<SceneResult> scenes(plan.scenes.size());
  for (std::size_t s = 0; s < plan.scenes.size(); ++s) scenes[s].scene = &plan.scenes[s];
  // Rows sequence by sequence, methods in plan order within each (as docs/RESULTS.md shows them).
  std::vector<std::string> methodOrder, sequenceOrder;
  std::set<RowKey> seenRows;
  std::ostringstream csv;
  csv << "scene,id,method,label,sequence,seed,pass,spp,gpu_s,wall_s,mse,relmse\n";
  JsonObject runList = JsonObject::array();
  std::vector<std::string> problems;  // "ID scene method/sequence seed N: missing | failed: ERROR"
  for (const auto& run : runs) {
    const std::optional<StudyRecord> record = readStudyRecord(runRecordPath(plan, run));
    SceneResult& scene = scenes[run.scene];
    const std::string where = run.id + " " + scene.scene->name + " " + run.method + "/" + run.sequence +
                              " seed " + std::to_string(run.seed);
    JsonObject entry;
    entry["id"] = run.id;
    entry["scene"] = scene.scene->name;
    entry["method"] = run.method;
    entry["sequence"] = run.sequence;
    entry["seed"] = run.seed;
    entry["status"] = record ? runStatusName(record->status) : "missing";
    entry["message"] = record ? record->message : "";
    runList.push_back(std::move(entry));
    if (!record) {
      ++outcome.missing;
      problems.push_back(where + ": missing");
      continue;
    }
    if (record->status == RunStatus::Failed) {
      ++outcome.failed;
      problems.push_back(where + ": failed: " + record->message);
      continue;
    }
    if (record->status == RunStatus::Skipped) {
      ++outcome.skipped;
      problems.push_back(where + ": skipped: " + record->message);
      continue;
    }
    ++outcome.done;
    const ConvergenceRun& measured = record->run;
    seenRows.insert({run.method, run.sequence});
    if (std::find(methodOrder.begin(), methodOrder.end(), run.method) == methodOrder.end())
      methodOrder.push_back(run.method);
    if (std::find(sequenceOrder.begin(), sequenceOrder.end(), run.sequence) == sequenceOrder.end())
      sequenceOrder.push_back(run.sequence);
    scene.planMethodOfLabel[measured.method] = run.method;
    scene.devices.insert(record->device);
    for (std::size_t p = 0; p < measured.points.size(); ++p) {
      const auto& point = measured.points[p];
      csv << csvQuoted(scene.scene->name) << ',' << run.id << ',' << csvQuoted(run.method) << ','
          << csvQuoted(measured.method) << ',' << run.sequence << ',' << run.seed << ',' << p + 1 << ','
          << point.spp << ',' << numberText(point.gpuSeconds) << ',' << numberText(point.wallSeconds) << ','
          << numberText(point.mse) << ',' << numberText(point.relMse) << '\n';
    }
    scene.runs.push_back(measured);
    auto sampler = std::find_if(scene.samplers.begin(), scene.samplers.end(),
                                [&](const SamplerRuns& r) { return r.name == run.method; });
    if (sampler == scene.samplers.end())
      sampler = scene.samplers.insert(sampler, SamplerRuns{run.method, {}, {}});
    if (run.sequence == "random") sampler->random.push_back(measured);
    if (run.sequence == "sobol") sampler->sobol.push_back(measured);
    if (run.firstSeed) {
      std::error_code exists;
      if (fs::exists(runImagePath(plan, run), exists)) {
        try {
          EnvImage image = loadRgbImage(runImagePath(plan, run));
          scene.images.push_back(
              {measured.method, run.sequence, std::move(image.rgb), measured.points.back()});
        } catch (const std::exception& e) {
          warn(std::string(e.what()) + "; its figures are left out");
        }
      }
    }
  }
  writeFileAtomically(plan.reportDirectory / "study.csv", csv.str());

  // Per scene: what converge writes.
  HtmlReport report("iblx study: " + plan.title);
  std::string summaries;
  JsonObject sceneList = JsonObject::array();
  struct SceneFigures {
    std::vector<HtmlReport::Figure> plots, finals, heats;
    int width = 0;
    std::string setting;
  };
  std::vector<SceneFigures> figures(scenes.size());
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    SceneResult& scene = scenes[s];
    if (scene.runs.empty()) continue;
    const fs::path dir = plan.reportDirectory / scene.scene->name;
    fs::create_directories(dir, ec);
    // The figures of an earlier merge go: their numbering follows the runs, which a plan's change shifts.
    std::vector<fs::path> stale;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      if (entry.path().extension() == ".png" &&
          (name.rfind("final-", 0) == 0 || name.rfind("heat-", 0) == 0 ||
           name.find("_vs_") != std::string::npos))
        stale.push_back(entry.path());
    }
    for (const auto& path : stale) fs::remove(path, ec);
    scene.data = readSceneData(sceneDataDirectory(plan, *scene.scene));
    const std::optional<SceneData>& data = scene.data;
    scene.summary = summarize(scene.runs, plan.targetRelMse);
    if (data) {
      scene.summary->referenceNoiseMse = data->noise.mse;
      scene.summary->referenceNoiseRelMse = data->noise.relMse;
    }
    scene.table = summaryTable(*scene.summary);
    std::string devices;
    for (const auto& d : scene.devices) devices += (devices.empty() ? "" : ", ") + d;
    const std::string title = data ? data->title : scene.scene->name;
    std::set<std::uint32_t> seeds;
    for (const auto& r : scene.runs) seeds.insert(r.seed);
    const std::string setting = "Device: " + devices + ". Seeds: " + std::to_string(seeds.size()) +
                                ". Reference: " + (data ? data->reference : "unknown") + ".";
    const std::string table = formatSummaryTable(*scene.summary);
    writeFileAtomically(dir / "summary.md",
                        "# " + scene.scene->name + ": " + title + "\n\n" + setting + "\n\n" + table);
    writeConvergenceCsv(dir / "converge.csv", scene.runs);
    summaries += "## " + scene.scene->name + "\n\n" + setting + "\n\n" + table + "\n";
    SceneFigures& f = figures[s];
    f.setting = setting;
    const std::vector<std::string> plots =
        keepPlots(dir,
                  writeConvergencePlots(dir, scene.scene->name + ": " + title, scene.runs,
                                        data ? data->noise : ReferenceNoise{}),
                  plan.plots);
    for (const auto& p : plots) f.plots.push_back({p, dir / p});
    if (data && !scene.images.empty()) {
      const std::vector<std::string> finals =
          writeFinalImages(dir, data->mask, scene.images, data->referenceRgb);
      f.finals.push_back({"reference (ground truth)", dir / finals.front()});
      for (std::size_t i = 0; i < scene.images.size(); ++i)
        f.finals.push_back({imageCaption(scene.images[i]), dir / finals[i + 1]});
      std::vector<ConvergenceImage> heat;
      for (const auto& image : scene.images) {
        const std::string key = scene.planMethodOfLabel[image.method] + "/" + image.sequence;
        if (!plan.heatMaps ||
            std::find(plan.heatMaps->begin(), plan.heatMaps->end(), key) != plan.heatMaps->end())
          heat.push_back(image);
      }
      const std::vector<std::string> heats = writeErrorHeatMaps(dir, data->mask, heat, data->referenceRgb);
      for (std::size_t i = 0; i < heat.size(); ++i)
        f.heats.push_back({imageCaption(heat[i]), dir / heats[i]});
      f.width = std::max(data->mask.width, 192);
    }
    JsonObject sceneJson;
    sceneJson["name"] = scene.scene->name;
    sceneJson["title"] = title;
    sceneJson["equal_time_s"] = scene.summary->equalTimeSeconds;
    JsonObject summaryRows = JsonObject::array();
    for (const auto& r : scene.summary->rows) {
      JsonObject row;
      row["method"] = scene.planMethodOfLabel[r.method];
      row["label"] = r.method;
      row["sequence"] = r.sequence;
      row["seeds"] = r.seeds;
      row["spp"] = r.spp;
      row["mse"] = r.mse;
      row["relmse"] = r.relMse;
      row["slope_spp"] = r.slopeSpp;
      row["time_to_target_s"] = r.timeToTarget;
      row["equal_time_mse"] = r.equalTimeMse;
      row["equal_time_ratio"] = r.equalTimeRatio;
      row["equal_time_relmse"] = r.equalTimeRelMse;
      row["equal_time_relmse_ratio"] = r.equalTimeRelRatio;
      row["samples_per_second"] = r.samplesPerSecond;
      summaryRows.push_back(std::move(row));
    }
    sceneJson["rows"] = std::move(summaryRows);
    sceneList.push_back(std::move(sceneJson));
    ++outcome.scenesWritten;
  }

  std::string decompositions;
  if (!plan.decomposeAgainst.empty())
    for (std::size_t s = 0; s < scenes.size(); ++s)
      if (scenes[s].summary)
        decompositions += decompositionSection(plan.decomposeAgainst, scenes[s], scenes[s].data);
  std::vector<RowKey> rows;
  for (const auto& sequence : sequenceOrder)
    for (const auto& method : methodOrder)
      if (seenRows.count({method, sequence})) rows.push_back({method, sequence});
  // The matrices over scenes: three columns of summaryTable (the same text as the scenes' summary.md), the
  // variance per sample and the speed.
  const auto column = [](std::size_t c) {
    return [c](const SceneResult& s, std::size_t i) { return s.table->rows[i][c]; };
  };
  constexpr std::size_t kRatioColumn = 11, kSlopeColumn = 8, kTimeToTargetColumn = 9;
  const TextTable ratios = matrix(rows, scenes, column(kRatioColumn));
  const TextTable slopes = matrix(rows, scenes, column(kSlopeColumn));
  const TextTable times = matrix(rows, scenes, column(kTimeToTargetColumn));
  const TextTable variances = matrix(rows, scenes, [](const SceneResult& s, std::size_t i) {
    const MethodSummary& r = s.summary->rows[i];
    return format("%.3g", r.mse * double(r.spp));
  });
  const TextTable speeds = matrix(rows, scenes, [](const SceneResult& s, std::size_t i) {
    return format("%.3g", s.summary->rows[i].samplesPerSecond);
  });
  // Over every scene, and over each image size's scenes when the plan has several.
  std::vector<std::pair<std::string, TextTable>> across = {
      {"Every scene", acrossScenes(rows, scenes, [](const SceneResult&) { return true; })}};
  std::set<std::string> sizes;
  for (const auto& s : scenes)
    if (s.summary) sizes.insert(sceneSize(*s.scene));
  if (sizes.size() > 1)
    for (const auto& size : sizes)
      across.emplace_back(
          "The " + (size.empty() ? std::string("default size's") : size) + " scenes",
          acrossScenes(rows, scenes, [size](const SceneResult& s) { return sceneSize(*s.scene) == size; }));
  std::string acrossText;
  for (const auto& [title, table] : across) acrossText += title + ":\n\n" + formatMarkdownTable(table) + "\n";
  char target[32];
  std::snprintf(target, sizeof target, "%g", plan.targetRelMse);
  std::string problemText;
  for (const auto& p : problems) problemText += "- " + p + "\n";
  const std::string header = "Generated by `iblx study merge " + plan.file.filename().string() + "` on " +
                             today() + " from " + std::to_string(outcome.done) + " runs of " +
                             std::to_string(runs.size()) + " (" + std::to_string(outcome.skipped) +
                             " skipped at a device limit, " + std::to_string(outcome.failed) + " failed, " +
                             std::to_string(outcome.missing) +
                             " missing). Columns of the scene tables: docs/RESULTS.md.";
  std::string tables = "# " + plan.title + "\n\n" + header + "\n\n";
  tables += "## MSE at equal time over the best method's, per scene\n\n" + formatMarkdownTable(ratios) + "\n";
  tables +=
      "## Across the scenes: MSE and relMSE at equal time over each scene's best\n\n" + acrossText + "\n";
  tables += "## Log-log slope of MSE against spp\n\n" + formatMarkdownTable(slopes) + "\n";
  tables += std::string("## Time to relMSE ") + target + "\n\n" + formatMarkdownTable(times) + "\n";
  tables +=
      "## MSE × spp at the end of the runs (mean over seeds): the variance per sample with `random`\n\n" +
      formatMarkdownTable(variances) + "\n";
  tables += "## Samples per pixel per second of wall time (median over seeds)\n\n" +
            formatMarkdownTable(speeds) + "\n";
  if (!decompositions.empty())
    tables += "## Where each method loses against " + plan.decomposeAgainst +
              "/sobol at equal time, in factors\n\n" + kDecompositionLegend + "\n\n" + decompositions;
  tables += summaries;
  if (!problems.empty()) tables += "## Runs not in the tables\n\n" + problemText;
  writeFileAtomically(plan.reportDirectory / "tables.md", tables);

  JsonObject json;
  json["title"] = plan.title;
  json["plan"] = plan.file.string();
  json["target_relmse"] = plan.targetRelMse;
  json["done"] = outcome.done;
  json["skipped"] = outcome.skipped;
  json["failed"] = outcome.failed;
  json["missing"] = outcome.missing;
  json["runs"] = std::move(runList);
  json["scenes"] = std::move(sceneList);
  writeFileAtomically(plan.reportDirectory / "study.json", formatJson(json) + "\n");

  report.paragraph(header);
  report.heading("MSE at equal time over the best method's");
  report.table(ratios);
  report.heading("Across the scenes: MSE and relMSE at equal time over each scene's best");
  for (const auto& [title, table] : across) {
    report.paragraph(title + ":");
    report.table(table);
  }
  report.heading("Log-log slope of MSE against spp");
  report.table(slopes);
  report.heading(std::string("Time to relMSE ") + target);
  report.table(times);
  report.heading("MSE × spp at the end of the runs: the variance per sample with random numbers");
  report.table(variances);
  report.heading("Samples per pixel per second of wall time");
  report.table(speeds);
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    if (!scenes[s].summary) continue;
    report.heading(scenes[s].scene->name);
    report.paragraph(figures[s].setting);
    report.table(*scenes[s].table);
    report.figures(figures[s].plots, 620);
    if (!figures[s].finals.empty()) {
      report.heading("Final images", 3);
      report.figures(figures[s].finals, figures[s].width);
    }
    if (!figures[s].heats.empty()) {
      report.heading("Per-pixel error", 3);
      report.figures(figures[s].heats, 0);
    }
  }
  if (!problems.empty()) {
    report.heading("Runs not in the tables");
    for (const auto& p : problems) report.paragraph(p);
  }
  report.write(plan.reportDirectory / "report.html");
  return outcome;
}

}  // namespace iblx::cli
