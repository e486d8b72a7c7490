// The viewer's convergence plot (convergence_plot.h): the figures' log axes (engine/analysis/log_axes.h) and
// palette (engine/analysis/palette.h), drawn with Dear ImGui's draw list.
#include "tools/viewer/convergence_plot.h"

#include "engine/analysis/log_axes.h"
#include "engine/analysis/palette.h"

#include <algorithm>
#include <cstddef>

namespace iblx::viewer {
namespace {

constexpr ImU32 kBackground = IM_COL32(20, 20, 24, 255);
constexpr ImU32 kGrid = IM_COL32(60, 60, 70, 255);
constexpr ImU32 kLabel = IM_COL32(160, 160, 160, 255);

ImU32 curveColor(std::size_t index) {
  const Rgb8 c = paletteColor(index);
  return IM_COL32(c.r, c.g, c.b, 255);
}

}  // namespace

void drawConvergencePlot(std::span<const ConvergenceCurve> curves, PlotSettings& settings) {
  ImGui::Checkbox("against time", &settings.againstTime);
  ImGui::SameLine();
  ImGui::Checkbox("relMSE", &settings.relative);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 size(ImGui::GetContentRegionAvail().x, 180.0f);
  ImGui::InvisibleButton("plot", size);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y), kBackground);
  const auto xs = [&](const ConvergenceCurve& c) -> const std::vector<double>& {
    return settings.againstTime ? c.seconds : c.spp;
  };
  const auto ys = [&](const ConvergenceCurve& c) -> const std::vector<double>& {
    return settings.relative ? c.relMse : c.mse;
  };
  LogLogBounds bounds;
  for (const ConvergenceCurve& c : curves) bounds.add(xs(c), ys(c));
  if (bounds.empty()) {
    draw->AddText(ImVec2(origin.x + 8, origin.y + 8), kLabel, "no points yet");
    return;
  }

  // Whole decades on both axes, so slopes can be read off (-1 is 1/N); the ticks are then the decades.
  const LogRange xRange = wholeDecades(bounds.x), yRange = wholeDecades(bounds.y);
  const std::vector<double> xTicks = ticksForLog10Range(xRange.lo, xRange.hi);
  const std::vector<double> yTicks = ticksForLog10Range(yRange.lo, yRange.hi);
  float widestX = 0, widestY = 0;
  for (double t : xTicks) widestX = std::max(widestX, ImGui::CalcTextSize(tickLabel(t).c_str()).x);
  for (double t : yTicks) widestY = std::max(widestY, ImGui::CalcTextSize(tickLabel(t).c_str()).x);
  const float lineHeight = ImGui::GetTextLineHeight();
  // The y labels left of the plot area, the x labels under it.
  LogLogAxes axes;
  axes.left = origin.x + 2 + widestY + 6;
  axes.right = std::max(double(origin.x + size.x - 6), axes.left + 1);
  axes.top = origin.y + 4;
  axes.bottom = origin.y + size.y - 4 - lineHeight;
  axes.log10XMin = xRange.lo, axes.log10XMax = xRange.hi;
  axes.log10YMin = yRange.lo, axes.log10YMax = yRange.hi;

  std::vector<double> xPositions, yPositions;
  for (double t : xTicks) xPositions.push_back(axes.pixelX(t));
  for (double t : yTicks) yPositions.push_back(axes.pixelY(t));
  const std::size_t xStride = labelStride(xPositions, widestX), yStride = labelStride(yPositions, lineHeight);
  for (std::size_t i = 0; i < xTicks.size(); ++i) {
    const float x = float(xPositions[i]);
    draw->AddLine(ImVec2(x, float(axes.top)), ImVec2(x, float(axes.bottom)), kGrid);
    if (i % xStride != 0) continue;
    const std::string label = tickLabel(xTicks[i]);
    draw->AddText(ImVec2(x - ImGui::CalcTextSize(label.c_str()).x / 2, float(axes.bottom) + 2), kLabel,
                  label.c_str());
  }
  for (std::size_t i = 0; i < yTicks.size(); ++i) {
    const float y = float(yPositions[i]);
    draw->AddLine(ImVec2(float(axes.left), y), ImVec2(float(axes.right), y), kGrid);
    if (i % yStride != 0) continue;
    const std::string label = tickLabel(yTicks[i]);
    draw->AddText(ImVec2(float(axes.left) - 6 - ImGui::CalcTextSize(label.c_str()).x, y - lineHeight / 2),
                  kLabel, label.c_str());
  }

  for (std::size_t k = 0; k < curves.size(); ++k) {
    const ConvergenceCurve& c = curves[k];
    // Each curve keeps its palette colour; the current (last) one is drawn last and thicker, over the others.
    const bool current = k + 1 == curves.size();
    const ImU32 color = curveColor(k);
    std::vector<ImVec2> points;
    for (std::size_t i = 0; i < std::min(xs(c).size(), ys(c).size()); ++i)
      if (validLogLogPoint(xs(c)[i], ys(c)[i]))
        points.emplace_back(float(axes.pixelX(xs(c)[i])), float(axes.pixelY(ys(c)[i])));
    if (points.size() >= 2)
      draw->AddPolyline(points.data(), int(points.size()), color, ImDrawFlags_None, current ? 2.5f : 1.5f);
    else if (points.size() == 1)
      draw->AddCircleFilled(points[0], current ? 3.0f : 2.0f, color);
    ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(color), "%s: %s %.3g%s", c.label.c_str(),
                       settings.relative ? "relMSE" : "MSE", ys(c).empty() ? 0.0 : ys(c).back(),
                       current && curves.size() > 1 ? " (current)" : "");
  }
}

}  // namespace iblx::viewer
