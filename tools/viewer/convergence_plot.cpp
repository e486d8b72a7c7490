// The viewer's convergence plot (convergence_plot.h).
#include "tools/viewer/convergence_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace iblx::viewer {

void drawConvergencePlot(std::span<const ConvergenceCurve> curves, PlotSettings& settings) {
  ImGui::Checkbox("against time", &settings.againstTime);
  ImGui::SameLine();
  ImGui::Checkbox("relMSE", &settings.relative);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 size(ImGui::GetContentRegionAvail().x, 180.0f);
  ImGui::InvisibleButton("plot", size);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y), IM_COL32(20, 20, 24, 255));
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  const auto xs = [&](const ConvergenceCurve& c) -> const std::vector<double>& {
    return settings.againstTime ? c.seconds : c.spp;
  };
  const auto ys = [&](const ConvergenceCurve& c) -> const std::vector<double>& {
    return settings.relative ? c.relMse : c.mse;
  };
  for (const ConvergenceCurve& c : curves)
    for (std::size_t i = 0; i < c.spp.size(); ++i) {
      if (!(xs(c)[i] > 0.0) || !(ys(c)[i] > 0.0)) continue;
      x0 = std::min(x0, std::log10(xs(c)[i])), x1 = std::max(x1, std::log10(xs(c)[i]));
      y0 = std::min(y0, std::log10(ys(c)[i])), y1 = std::max(y1, std::log10(ys(c)[i]));
    }
  if (x0 > x1) {
    draw->AddText(ImVec2(origin.x + 8, origin.y + 8), IM_COL32(160, 160, 160, 255), "no points yet");
    return;
  }
  // Whole decades on both axes, so slopes can be read off (-1 is 1/N).
  x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1), y0 = std::floor(y0),
  y1 = std::max(std::ceil(y1), y0 + 1);
  const float left = 44.0f, bottom = 18.0f;
  const auto toScreen = [&](double lx, double ly) {
    return ImVec2(origin.x + left + float((lx - x0) / (x1 - x0)) * (size.x - left - 6.0f),
                  origin.y + 4.0f + float((y1 - ly) / (y1 - y0)) * (size.y - bottom - 8.0f));
  };
  char label[32];
  for (double d = x0; d <= x1; d += 1.0) {
    const ImVec2 a = toScreen(d, y0), b = toScreen(d, y1);
    draw->AddLine(a, b, IM_COL32(60, 60, 70, 255));
    std::snprintf(label, sizeof label, "1e%d", int(d));
    draw->AddText(ImVec2(a.x - 10, a.y + 2), IM_COL32(160, 160, 160, 255), label);
  }
  for (double d = y0; d <= y1; d += 1.0) {
    const ImVec2 a = toScreen(x0, d), b = toScreen(x1, d);
    draw->AddLine(a, b, IM_COL32(60, 60, 70, 255));
    std::snprintf(label, sizeof label, "1e%d", int(d));
    draw->AddText(ImVec2(origin.x + 2, a.y - 7), IM_COL32(160, 160, 160, 255), label);
  }
  static constexpr ImU32 kColors[] = {IM_COL32(255, 120, 90, 255),  IM_COL32(90, 180, 255, 255),
                                      IM_COL32(130, 220, 110, 255), IM_COL32(240, 200, 80, 255),
                                      IM_COL32(200, 130, 255, 255), IM_COL32(240, 240, 240, 255)};
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const ConvergenceCurve& c = curves[k];
    // The newest curve is always white-ish on top; earlier ones keep their colours.
    const ImU32 color = k + 1 == curves.size() ? kColors[5] : kColors[k % 5];
    std::vector<ImVec2> points;
    for (std::size_t i = 0; i < c.spp.size(); ++i)
      if (xs(c)[i] > 0.0 && ys(c)[i] > 0.0)
        points.push_back(toScreen(std::log10(xs(c)[i]), std::log10(ys(c)[i])));
    if (points.size() >= 2)
      draw->AddPolyline(points.data(), int(points.size()), color, ImDrawFlags_None, 1.5f);
    else if (points.size() == 1)
      draw->AddCircleFilled(points[0], 2.0f, color);
    ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(color), "%s: %s %.3g", c.label.c_str(),
                       settings.relative ? "relMSE" : "MSE", ys(c).empty() ? 0.0 : ys(c).back());
  }
}

}  // namespace iblx::viewer
