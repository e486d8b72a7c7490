// The viewer's convergence plot: error curves of the methods tried on one ground truth, drawn log-log with
// Dear ImGui's draw list, whole decades on both axes so slopes can be read off (-1 is 1/N).
#pragma once

#include "tools/viewer/convergence_curve.h"

#include <imgui.h>

#include <span>
#include <string>
#include <vector>

namespace iblx::viewer {

struct PlotSettings {
  bool againstTime = false;  // x: wall seconds instead of spp
  bool relative = false;     // y: relMSE instead of MSE
};

// Draws its two toggles, the plot (180 px high, the available width) and one legend line per curve, each
// curve in the figures' palette colour of its index. The last curve is the current one: drawn last and
// thicker, and marked "(current)" in the legend when there are others.
void drawConvergencePlot(std::span<const ConvergenceCurve> curves, PlotSettings& settings);

}  // namespace iblx::viewer
