// The result of one run of a study (tools/cli/study_plan.h) on disk: runs/ID.json in the study directory,
// written atomically once the run has ended, so a task killed at any point leaves every record whole and
// loses at most the run in flight. A run that failed is recorded with its error (a rerun tries it again);
// a run whose data exceed the device's limits is recorded as skipped with the reason.
#pragma once

#include "engine/analysis/convergence.h"
#include "tools/cli/study_plan.h"

#include <filesystem>
#include <optional>
#include <string>

namespace iblx::cli {

enum class RunStatus { Done, Skipped, Failed };
const char* runStatusName(RunStatus status);

struct StudyRecord {
  std::string id, scene, method, sequence;
  std::uint32_t seed = 0;
  RunStatus status = RunStatus::Done;
  std::string message;  // Skipped: why; Failed: the error
  std::string device, host;
  double seconds = 0.0;  // the whole run, setup included
  ConvergenceRun run;    // run.method is the method's label, e.g. "mis(env-cdf+cosine, balance)"
};

void writeStudyRecord(const std::filesystem::path& path, const StudyRecord& record);
// The record at path; nothing when there is none. A record that cannot be read (damaged by hand, or by a
// disk that lost it) is reported and treated as missing, so its run is measured again.
std::optional<StudyRecord> readStudyRecord(const std::filesystem::path& path);

// Whether a run needs measuring: it has no record, or its record says it failed.
bool runIsComplete(const std::optional<StudyRecord>& record);

}  // namespace iblx::cli
