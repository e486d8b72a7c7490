// A study plan of `iblx study` (docs/STUDIES.md): scenes x methods x sequences x seeds, each a `converge`
// run, read from a TOML file. A plan is converge's flags written as data: every scene key and measurement key
// is the converge flag of the same name (`max_spp` is --max-spp), so a plan accepts and checks exactly what
// the command line does. Each run has a stable id, a hash of what defines it, so the same plan always has
// the same runs and adding a method, a seed or a scene adds runs without renaming the others.
#pragma once

#include "tools/cli/commands.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace iblx::cli {

// A file the plan generates with an iblx command before any run needs it (e.g. a `merl-synth` material),
// under the study directory's inputs/, referred to as ${inputs}/NAME.
struct StudyInput {
  std::string name;
  Args command;      // the command and its flags, without --out; or
  std::string text;  // the file's text (e.g. an ALTA function file written by hand)
};

struct StudyScene {
  std::string name;
  Args flags;              // converge's scene and measurement flags, plan defaults first
  std::string definition;  // the scene's defining flags as one canonical line (part of each run's id)
};

struct StudyRun {
  std::string id;  // 16 hex digits
  std::size_t scene = 0;
  std::string method;  // as the plan names it: NAME[:OPTION]...
  std::string sequence;
  std::uint32_t seed = 0;
  bool firstSeed = false;  // the scene's first seed: its final image is kept for the report's figures
};

struct StudyPlan {
  std::filesystem::path file;             // the plan
  std::filesystem::path directory;        // where the runs' results go (`directory`, relative to the plan)
  std::filesystem::path reportDirectory;  // where `merge` writes (`report_directory`; default: directory)
  std::string title;
  double targetRelMse = 1e-3;
  std::vector<StudyInput> inputs;
  std::vector<StudyScene> scenes;
  // Which figures `merge` keeps per scene: plot names (e.g. "relmse_vs_time") and "method/sequence" heat
  // maps; unset: all (an empty list: none).
  std::optional<std::vector<std::string>> plots, heatMaps;
  // `merge` splits each method's equal-time loss against this method's (`decompose_against`) into factors
  // (engine/analysis/loss_decomposition.h); empty: no decomposition.
  std::string decomposeAgainst;
};

// Reads and checks a plan: TOML syntax, known keys of the right types, unique scene names. Errors name the
// file, the line where TOML gives one, and the scene. Flags are checked when the runs are listed.
StudyPlan readStudyPlan(const std::filesystem::path& file);

// Writes every input the plan generates that the study directory lacks (under a lock, atomically: tasks
// that start together generate each once).
void prepareStudyInputs(const StudyPlan& plan);

// Every run of the plan, scene by scene in plan order, then sequence, method, seed (converge's order): the
// scene's flags are parsed as converge parses them (an error names the plan and the scene), and without
// `methods` a scene gets every method that applies to its BRDF, which reads the BRDF file. Needs the plan's
// inputs.
std::vector<StudyRun> listStudyRuns(const StudyPlan& plan);

// The value of the scene's last `flag` (the last wins, as in the parser), if it has one.
std::optional<std::string> sceneFlag(const StudyScene& scene, std::string_view flag);
// The scene's time budget per run (its --time), if it has a valid one.
std::optional<double> sceneTimeBudget(const StudyScene& scene);

// A task's share: --shard I/N takes the I-th of N contiguous blocks of runs (1-based; contiguous keeps each
// scene's runs, and its ground truth, within one or two tasks).
struct StudyShard {
  std::size_t index = 1, count = 1;
};
StudyShard parseStudyShard(const std::string& text);  // "I/N"
std::vector<StudyRun> shardOf(const std::vector<StudyRun>& runs, StudyShard shard);

// The path of a run's record and final image in the study directory.
std::filesystem::path runRecordPath(const StudyPlan& plan, const StudyRun& run);
std::filesystem::path runImagePath(const StudyPlan& plan, const StudyRun& run);
// The folder holding a scene's ground truth and pixel mask (written by the first task to reach the scene).
std::filesystem::path sceneDataDirectory(const StudyPlan& plan, const StudyScene& scene);

}  // namespace iblx::cli
