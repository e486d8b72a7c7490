// `iblx study`: a study (scenes x methods x sequences x seeds, each a `converge` run) as one command over a
// plan file (tools/cli/study_plan.h): `plan` lists its runs, `run` measures a task's share of them and
// records each as it ends (tools/cli/study_records.h), `merge` gathers every record into one report
// (tools/cli/study_merge.h). docs/STUDIES.md is the guide.
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json_output.h"
#include "engine/core/log.h"
#include "engine/io/image_write.h"
#include "engine/render/convergence_runner.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"
#include "tools/cli/converge_scene.h"
#include "tools/cli/measurement.h"
#include "tools/cli/study_merge.h"
#include "tools/cli/study_plan.h"
#include "tools/cli/study_records.h"

#include <vulkan/vulkan_raii.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>
#include <unistd.h>

namespace iblx::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStudyUsage =
    "usage: iblx study plan PLAN [--shard I/N] [--json]\n"
    "         list the runs, their ids and whether each is recorded, with a time estimate\n"
    "       iblx study run PLAN [--shard I/N | --task ID...] [--device D]\n"
    "         measure the runs not recorded yet: all of them, a shard, or runs by id\n"
    "       iblx study merge PLAN [--out-dir DIR]\n"
    "         gather every record into tables, plots and a report (no device needed)\n"
    "A plan is a TOML file of converge's flags (docs/STUDIES.md). Each run is recorded when it ends; Ctrl-C "
    "or\n"
    "SIGTERM drops the run in flight and stops, and the same command run again measures the rest.\n";

std::string durationText(double seconds) {
  char text[64];
  if (seconds < 90)
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  else if (seconds < 5400)
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  else
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  return text;
}

std::string hostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "?";
  return name;
}

// "about T of rendering (N runs x S s) plus setup and ground truths", from the budgets of the runs' scenes.
std::string estimateText(const StudyPlan& plan, const std::vector<StudyRun>& runs) {
  double seconds = 0.0;
  std::size_t timed = 0;
  std::map<std::size_t, std::optional<double>> budgets;
  for (const auto& run : runs) {
    auto it = budgets.find(run.scene);
    if (it == budgets.end()) it = budgets.emplace(run.scene, sceneTimeBudget(plan.scenes[run.scene])).first;
    if (it->second) seconds += *it->second, ++timed;
  }
  std::string text;
  if (timed > 0)
    text = "about " + durationText(seconds) + " of rendering for the " + std::to_string(timed) +
           " runs with a time budget, plus setup and ground truths";
  if (timed < runs.size())
    text += (text.empty() ? "" : "; ") + std::to_string(runs.size() - timed) +
            " runs have a sample budget: the progress lines estimate their time from the runs measured";
  return text;
}

// The plan argument: the first word that is neither a flag nor the value of one of `valueFlags`.
struct StudyArgs {
  fs::path plan;
  Args flags;
};
StudyArgs splitPlan(const std::string& command, const Args& args, const std::set<std::string>& valueFlags) {
  StudyArgs split;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (split.plan.empty() && !a.empty() && a[0] != '-') {
      split.plan = a;
      continue;
    }
    split.flags.push_back(a);
    if (valueFlags.count(a) && i + 1 < args.size()) split.flags.push_back(args[++i]);
  }
  const bool help = std::find(args.begin(), args.end(), "--help") != args.end() ||
                    std::find(args.begin(), args.end(), "-h") != args.end();
  if (split.plan.empty() && !help)
    throw Error("study " + command + ": no plan file (iblx study " + command + " PLAN.toml)");
  return split;
}

// Selects the runs a task measures: a shard, ids, or all.
std::vector<StudyRun> selectRuns(const std::vector<StudyRun>& runs, const std::optional<StudyShard>& shard,
                                 const std::vector<std::string>& ids) {
  if (ids.empty()) return shard ? shardOf(runs, *shard) : runs;
  std::vector<StudyRun> selected;
  for (const auto& id : ids) {
    auto it = std::find_if(runs.begin(), runs.end(), [&](const StudyRun& r) { return r.id == id; });
    if (it == runs.end())
      throw Error("--task " + id + ": no run of the plan has this id (iblx study plan PLAN)");
    selected.push_back(*it);
  }
  return selected;
}

int studyPlan(const Args& args) {
  const StudyArgs split = splitPlan("plan", args, {"--shard"});
  std::optional<StudyShard> shard;
  bool json = false;
  ArgParser parser("study plan");
  parser.value("--shard", "I/N", "list the I-th of N shards only",
               [&](const std::string& v) { shard = parseStudyShard(v); });
  parser.toggle("--json", "one JSON object per run", [&] { json = true; });
  if (parser.parseOrShowHelp(split.flags)) return 0;
  const StudyPlan plan = readStudyPlan(split.plan);
  prepareStudyInputs(plan);
  const std::vector<StudyRun> all = listStudyRuns(plan);
  const std::vector<StudyRun> runs = selectRuns(all, shard, {});
  std::map<std::string, std::size_t> counts;
  for (const auto& run : runs) {
    const auto record = readStudyRecord(runRecordPath(plan, run));
    const std::string status = record ? runStatusName(record->status) : "missing";
    ++counts[status];
    const std::string& scene = plan.scenes[run.scene].name;
    if (json) {
      JsonObject line;
      line["id"] = run.id;
      line["scene"] = scene;
      line["method"] = run.method;
      line["sequence"] = run.sequence;
      line["seed"] = run.seed;
      line["status"] = status;
      printJsonLine(line);
    } else
      std::printf("%s  %-24s %-28s %-7s seed %-4u %s\n", run.id.c_str(), scene.c_str(), run.method.c_str(),
                  run.sequence.c_str(), run.seed, status.c_str());
  }
  std::string tally;
  for (const auto& [status, count] : counts) tally += ", " + std::to_string(count) + " " + status;
  std::fprintf(stderr, "study: %s: %zu scenes, %zu runs%s%s; results in %s\nstudy: %s\n", split.plan.c_str(),
               plan.scenes.size(), runs.size(), shard ? " in this shard" : "", tally.c_str(),
               plan.directory.c_str(), estimateText(plan, runs).c_str());
  return 0;
}

// What the first task to reach a scene leaves for `merge`: the ground truth and which pixels are the object.
void writeSceneData(const StudyPlan& plan, const StudyScene& studyScene, const Scene& scene,
                    const ObtainedReference& reference, const std::string& title, const std::string& device) {
  const fs::path dir = sceneDataDirectory(plan, studyScene);
  std::error_code ec;
  if (fs::exists(dir / "scene.json", ec)) return;
  fs::create_directories(dir, ec);
  writeExr(dir / "reference.exr", scene.gbuffer.width, scene.gbuffer.height, reference.rgb);
  std::string mask;
  for (const auto m : scene.gbuffer.objectMask()) mask += m ? '1' : '0';
  JsonObject json;
  json["title"] = title;
  json["width"] = scene.gbuffer.width;
  json["height"] = scene.gbuffer.height;
  json["reference"] = reference.description;
  json["noise_mse"] = reference.noise.mse;
  json["noise_relmse"] = reference.noise.relMse;
  json["device"] = device;
  json["object_mask"] = mask;
  writeFileAtomically(dir / "scene.json", json.dump() + "\n");  // last: it marks the folder complete
}

// A task of `study run`: its runs, scene by scene, on one device.
class StudyTask {
 public:
  StudyTask(const StudyPlan& plan, const RenderSpec& device)
      : plan_(plan),
        context_({device.device, device.validation ? Validation::On : Validation::Auto}),
        host_(hostName()) {}

  // Measures `pending` (in plan order) until done or interrupted; returns the exit status.
  int measure(const std::vector<StudyRun>& pending) {
    const auto start = std::chrono::steady_clock::now();
    std::size_t next = 0;
    while (next < pending.size() && !interrupt_.flag().load()) {
      // The pending runs of one scene: the scene and its ground truth are loaded once for them.
      std::size_t end = next;
      while (end < pending.size() && pending[end].scene == pending[next].scene) ++end;
      try {
        loadScene(plan_.scenes[pending[next].scene]);
      } catch (const Interrupted&) {
        break;
      } catch (const std::exception& e) {  // every run of the scene fails alike; the other scenes go on
        for (; next < end; ++next)
          recordFailure(pending[next], "scene " + plan_.scenes[pending[next].scene].name + ": " + e.what());
        continue;
      }
      for (; next < end && !interrupt_.flag().load(); ++next)
        if (!measureRun(pending[next], pending.size() - next - 1)) break;
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (interrupt_.flag().load()) {
      std::fprintf(stderr,
                   "study: interrupted after %zu runs (%s); the run in flight was dropped; rerun the same "
                   "command to finish the other %zu\n",
                   measured_, durationText(elapsed).c_str(), pending.size() - measured_ - failed_);
      return 130;
    }
    std::fprintf(stderr, "study: %zu runs measured in %s, %zu failed%s\n", measured_,
                 durationText(elapsed).c_str(), failed_,
                 failed_ ? " (recorded with their errors; a rerun tries them again)" : "");
    return failed_ ? 1 : 0;
  }

 private:
  void loadScene(const StudyScene& studyScene) {
    studyScene_ = &studyScene;
    scene_.reset();
    flags_ = ConvergeSceneFlags{};
    ArgParser parser("study");
    addConvergeSceneFlags(parser, flags_);
    parser.parse(studyScene.flags);
    finishConvergeSceneFlags(flags_);
    scene_.emplace(loadConvergeScene(context_, flags_, checkConvergeScene(flags_)));
    reference_ = obtainReference(context_, compiler_, *scene_, flags_.hardCase(), flags_.spec);
    writeSceneData(plan_, studyScene, *scene_, reference_, convergeSceneTitle(flags_, *scene_),
                   context_.deviceName());
  }

  // Measures one run of the loaded scene and records it; false when interrupted (nothing is recorded).
  bool measureRun(const StudyRun& run, std::size_t runsLeft) {
    const auto start = std::chrono::steady_clock::now();
    StudyRecord record{run.id, studyScene_->name,     run.method, run.sequence, run.seed, RunStatus::Done,
                       "",     context_.deviceName(), host_,      0.0,          {}};
    try {
      MeasurementSpec spec = flags_.spec;
      spec.methods = {run.method};
      spec.sequences = {run.sequence};
      spec.seeds = 1;
      spec.firstSeed = run.seed;
      const std::vector<ResolvedMethod> methods = resolveMethods(spec, *scene_->brdf);
      const std::vector<std::uint32_t> seeds = {run.seed};
      ConvergenceResult result =
          runConvergence(context_, compiler_, *scene_, reference_.rgb, methods, seeds, spec.finalBudget(),
                         showProgress, &interrupt_.flag(), reference_.noise);
      endProgressLine();
      if (result.interrupted) return false;  // the run in flight is dropped, never half-recorded
      if (!result.skipped.empty()) {
        record.status = RunStatus::Skipped;
        record.message = result.skipped.front().reason;
      } else {
        record.run = std::move(result.runs.front());
        // The image goes first: the record is what marks the run complete.
        if (run.firstSeed && !result.images.empty())
          writeExr(runImagePath(plan_, run), scene_->gbuffer.width, scene_->gbuffer.height,
                   result.images.front().rgb);
      }
    } catch (const Interrupted&) {
      return false;
    } catch (const vk::SystemError& e) {
      recordFailure(run, std::string("Vulkan error: ") + e.what());
      return true;
    } catch (const std::exception& e) {
      recordFailure(run, e.what());
      return true;
    }
    record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    writeStudyRecord(runRecordPath(plan_, run), record);
    ++measured_;
    measuredSeconds_ += record.seconds;
    reportProgress(run, record, runsLeft);
    return true;
  }

  // One line per run, with the rest of the task estimated from what the runs so far cost on average.
  void reportProgress(const StudyRun& run, const StudyRecord& record, std::size_t runsLeft) const {
    char line[512];
    if (record.status == RunStatus::Skipped)
      std::snprintf(line, sizeof line, "skipped: %s", record.message.c_str());
    else {
      const ConvergencePoint& last = record.run.points.back();
      std::snprintf(line, sizeof line, "%llu spp in %.2f s, relMSE %.3g",
                    static_cast<unsigned long long>(last.spp), last.wallSeconds, last.relMse);
    }
    const double perRun = measuredSeconds_ / double(measured_);
    std::fprintf(stderr, "study: [%zu/%zu] %s %s/%s seed %u: %s; about %s left\n", measured_ + failed_,
                 measured_ + failed_ + runsLeft, studyScene_->name.c_str(), run.method.c_str(),
                 run.sequence.c_str(), run.seed, line, durationText(double(runsLeft) * perRun).c_str());
  }

  void recordFailure(const StudyRun& run, const std::string& message) {
    const StudyRecord record{
        run.id,  plan_.scenes[run.scene].name, run.method, run.sequence, run.seed, RunStatus::Failed,
        message, context_.deviceName(),        host_,      0.0,          {}};
    writeStudyRecord(runRecordPath(plan_, run), record);
    ++failed_;
    std::fprintf(stderr, "study: %s %s/%s seed %u failed: %s\n", record.scene.c_str(), run.method.c_str(),
                 run.sequence.c_str(), run.seed, message.c_str());
  }

  const StudyPlan& plan_;
  InterruptGuard interrupt_;  // before the device: Ctrl-C during its creation is kept for the first check
  VulkanContext context_;
  ShaderCompiler compiler_;
  std::string host_;
  const StudyScene* studyScene_ = nullptr;
  ConvergeSceneFlags flags_;
  std::optional<Scene> scene_;
  ObtainedReference reference_;
  std::size_t measured_ = 0, failed_ = 0;
  double measuredSeconds_ = 0.0;
};

int studyRun(const Args& args) {
  const StudyArgs split = splitPlan("run", args, {"--shard", "--task", "--device"});
  std::optional<StudyShard> shard;
  std::vector<std::string> ids;
  RenderSpec device;
  ArgParser parser("study run");
  parser.value("--shard", "I/N", "measure the I-th of N contiguous blocks of the plan's runs",
               [&](const std::string& v) { shard = parseStudyShard(v); });
  parser.value("--task", "ID", "measure the run with this id (repeatable; ids: iblx study plan PLAN)",
               [&](const std::string& v) { ids.push_back(v); });
  addDeviceFlags(parser, device);
  if (parser.parseOrShowHelp(split.flags)) return 0;
  if (shard && !ids.empty()) throw Error("study run: --shard and --task exclude each other");

  const StudyPlan plan = readStudyPlan(split.plan);
  prepareStudyInputs(plan);
  const std::vector<StudyRun> selected = selectRuns(listStudyRuns(plan), shard, ids);
  std::vector<StudyRun> pending;
  for (const auto& run : selected)
    if (!runIsComplete(readStudyRecord(runRecordPath(plan, run)))) pending.push_back(run);
  std::error_code ec;
  fs::create_directories(plan.directory / "runs", ec);
  if (!fs::is_directory(plan.directory / "runs"))
    throw Error(plan.file.string() + ": cannot create " + (plan.directory / "runs").string());
  const std::string share = shard
                                ? "shard " + std::to_string(shard->index) + "/" + std::to_string(shard->count)
                            : ids.empty() ? "the whole plan"
                                          : std::to_string(ids.size()) + " ids";
  std::fprintf(stderr, "study: %s, %s: %zu runs, %zu already recorded, %zu to measure\n", split.plan.c_str(),
               share.c_str(), selected.size(), selected.size() - pending.size(), pending.size());
  if (pending.empty()) return 0;
  std::fprintf(stderr, "study: %s\n", estimateText(plan, pending).c_str());
  StudyTask task(plan, device);
  return task.measure(pending);
}

int studyMerge(const Args& args) {
  const StudyArgs split = splitPlan("merge", args, {"--out-dir"});
  fs::path outDir;
  ArgParser parser("study merge");
  parser.value("--out-dir", "DIR", "where the report goes (default: the plan's report_directory)",
               [&](const std::string& v) { outDir = v; });
  if (parser.parseOrShowHelp(split.flags)) return 0;
  StudyPlan plan = readStudyPlan(split.plan);
  if (!outDir.empty()) plan.reportDirectory = outDir;
  prepareStudyInputs(plan);
  const MergeOutcome outcome = mergeStudy(plan, listStudyRuns(plan));
  std::printf("wrote %s: tables.md, study.csv, study.json, report.html and %zu scene folders\n",
              plan.reportDirectory.c_str(), outcome.scenesWritten);
  if (outcome.missing || outcome.failed) {
    warn(std::to_string(outcome.missing) + " runs missing and " + std::to_string(outcome.failed) +
         " failed (listed in tables.md and study.json): `iblx study run " + split.plan.string() +
         "` measures them");
    return 1;
  }
  return 0;
}

}  // namespace

int cmdStudy(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(kStudyUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "plan") return studyPlan(rest);
  if (args[0] == "run") return studyRun(rest);
  if (args[0] == "merge") return studyMerge(rest);
  throw Error("study: unknown subcommand '" + args[0] + "' (plan, run or merge)");
}

}  // namespace iblx::cli
