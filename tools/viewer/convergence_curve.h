// One method's error against the viewer's ground truth, pass by pass (the viewer model measures it, the
// convergence plot draws it).
#pragma once

#include <string>
#include <vector>

namespace iblx::viewer {

// Error against spp and time for one method on the current ground truth, one entry per pass.
struct ConvergenceCurve {
  std::string label;
  std::vector<double> spp, seconds, mse, relMse;
};

}  // namespace iblx::viewer
