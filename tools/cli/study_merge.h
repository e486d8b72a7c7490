// `iblx study merge`: every run record of a study gathered into one report, without a device. Writes into
// the plan's report directory:
//   study.csv    every recorded point of every run (scene, id, method, label, sequence, seed, pass, spp,
//                gpu_s, wall_s, mse, relmse);
//   study.json   every run with its status, and each scene's summary rows;
//   tables.md    the matrices over scenes (MSE at equal time over the best method's, the log-log slope of
//                MSE against spp, the time to the target relMSE), then each scene's summary, then the runs
//                missing or failed;
//   report.html  the same with each scene's plots, error heat maps and final images;
//   SCENE/       per scene, what `converge` writes: summary.md, converge.csv and the figures.
#pragma once

#include "tools/cli/study_plan.h"

#include <cstddef>
#include <vector>

namespace iblx::cli {

struct MergeOutcome {
  std::size_t done = 0, skipped = 0, failed = 0, missing = 0;
  std::size_t scenesWritten = 0;  // scenes with at least one finished run
};

MergeOutcome mergeStudy(const StudyPlan& plan, const std::vector<StudyRun>& runs);

}  // namespace iblx::cli
