// The sample overlay (sample_overlay.h).
#include "tools/viewer/sample_overlay.h"

#include <algorithm>
#include <cmath>

namespace iblx::viewer {

ImU32 techniqueColor(std::size_t k) {
  static constexpr ImU32 kColors[] = {IM_COL32(255, 110, 80, 255), IM_COL32(80, 200, 255, 255),
                                      IM_COL32(150, 255, 100, 255), IM_COL32(255, 220, 60, 255)};
  return kColors[k % 4];
}

void SampleOverlay::setEnvironment(const EnvImage& env) {
  // Box-average the luminance (Rec. 709) into the grid, on a log scale.
  std::vector<double> sum(std::size_t(kGridWidth) * kGridHeight, 0.0);
  std::vector<int> count(sum.size(), 0);
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const std::size_t t = 3 * (std::size_t(y) * env.width + x);
      const double l = 0.2126 * env.rgb[t] + 0.7152 * env.rgb[t + 1] + 0.0722 * env.rgb[t + 2];
      const std::size_t c =
          std::size_t(y * kGridHeight / env.height) * kGridWidth + x * kGridWidth / env.width;
      sum[c] += std::max(l, 0.0), ++count[c];
    }
  logLuminance_.assign(sum.size(), -30.0f);
  std::vector<float> lit;
  for (std::size_t c = 0; c < sum.size(); ++c)
    if (count[c] > 0 && sum[c] > 0.0) lit.push_back(logLuminance_[c] = float(std::log10(sum[c] / count[c])));
  // The scale runs from the 5th percentile of the lit cells to the brightest, so a sun 1e4 times the sky
  // leaves the sky's structure visible; at most 8 decades.
  std::sort(lit.begin(), lit.end());
  logMax_ = lit.empty() ? 0.0f : lit.back();
  logMin_ = lit.empty() ? -1.0f : std::max(lit[lit.size() / 20], logMax_ - 8.0f);
  if (logMin_ >= logMax_) logMin_ = logMax_ - 1.0f;
}

namespace {

// The pixel's shading frame (normal, tangent, bitangent = n x t), as the integrator builds it from the
// G-buffer.
struct Frame {
  glm::dvec3 n, t, b;
};
Frame pixelFrame(const gpu::GPixel& pixel) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(pixel.normal.x, pixel.normal.y, pixel.normal.z));
  const glm::dvec3 t = glm::normalize(glm::dvec3(pixel.tangent.x, pixel.tangent.y, pixel.tangent.z));
  return {n, t, glm::cross(n, t)};
}

}  // namespace

std::vector<double> SampleOverlay::lobeOnDisc(
    const gpu::GPixel& pixel,
    const std::function<std::vector<glm::dvec3>(std::span<const glm::dvec3>, std::span<const glm::dvec3>)>&
        evaluate) {
  const Frame f = pixelFrame(pixel);
  const glm::dvec3 view(pixel.view.x, pixel.view.y, pixel.view.z);
  const glm::dvec3 woLocal =
      glm::normalize(glm::dvec3(glm::dot(view, f.t), glm::dot(view, f.b), glm::dot(view, f.n)));
  std::vector<glm::dvec3> wi, wo;
  std::vector<std::size_t> cells;
  std::vector<double> lobe(std::size_t(kLobeGrid) * kLobeGrid, -1.0);
  for (int j = 0; j < kLobeGrid; ++j)
    for (int i = 0; i < kLobeGrid; ++i) {
      // The cell's centre on the disc; up on the screen is +bitangent, as draw() places the samples.
      const double x = 2.0 * (i + 0.5) / kLobeGrid - 1.0, y = 1.0 - 2.0 * (j + 0.5) / kLobeGrid;
      const double r2 = x * x + y * y;
      if (r2 >= 1.0) continue;
      wi.emplace_back(x, y, std::sqrt(1.0 - r2));
      wo.push_back(woLocal);
      cells.push_back(std::size_t(j) * kLobeGrid + i);
    }
  const std::vector<glm::dvec3> values = evaluate(wi, wo);
  for (std::size_t k = 0; k < cells.size(); ++k)
    lobe[cells[k]] =
        std::max(0.0, (0.2126 * values[k].x + 0.7152 * values[k].y + 0.0722 * values[k].z) * wi[k].z);
  return lobe;
}

void SampleOverlay::setSamples(int x, int y, const gpu::GPixel& pixel, std::vector<RecordedSample> samples,
                               std::string methodLabel, std::vector<double> lobe) {
  x_ = x, y_ = y, pixel_ = pixel;
  methodLabel_ = std::move(methodLabel);
  lobe_ = std::move(lobe);
  lobeLogMax_ = -300.0;
  for (double v : lobe_)
    if (v > 0.0) lobeLogMax_ = std::max(lobeLogMax_, std::log10(v));
  samples_ = std::move(samples);
  techniques_.clear();
  for (const RecordedSample& s : samples_)
    if (std::find(techniques_.begin(), techniques_.end(), s.technique) == techniques_.end())
      techniques_.emplace_back(s.technique);
  productNodes_.clear();
  productColumns_ = productRows_ = 0;
  for (const RecordedSample& s : samples_) {
    if (!s.productNode || !(s.productNode->probability > 0.0)) continue;
    const ProductNodeChoice& c = *s.productNode;
    // The table's own size: the coarsest choice's (a split node's children are on finer levels).
    if (productColumns_ == 0 || c.columns < productColumns_)
      productColumns_ = c.columns, productRows_ = c.rows;
    if (std::none_of(productNodes_.begin(), productNodes_.end(),
                     [&](const ProductNodeChoice& n) { return n.node == c.node && n.columns == c.columns; }))
      productNodes_.push_back(c);
  }
  productLogMin_ = productLogMax_ = 0.0;
  if (!productNodes_.empty()) {
    const auto [least, most] =
        std::minmax_element(productNodes_.begin(), productNodes_.end(),
                            [](const auto& a, const auto& b) { return a.probability < b.probability; });
    productLogMin_ = std::log10(least->probability), productLogMax_ = std::log10(most->probability);
  }
}

void SampleOverlay::draw(float mapWidth, float hemisphereSide) const {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float mapHeight = 0.5f * mapWidth;
  // The density: one rectangle per grid cell, dark blue (4 decades down or black) to warm white.
  const float cw = mapWidth / kGridWidth, ch = mapHeight / kGridHeight;
  for (int gy = 0; gy < kGridHeight; ++gy)
    for (int gx = 0; gx < kGridWidth; ++gx) {
      const float t = std::clamp(
          (logLuminance_[std::size_t(gy) * kGridWidth + gx] - logMin_) / (logMax_ - logMin_), 0.0f, 1.0f);
      const ImU32 c = IM_COL32(int(20 + 235 * t), int(20 + 200 * t * t), int(60 + 100 * t * (1 - t)), 255);
      const ImVec2 a(origin.x + gx * cw, origin.y + gy * ch);
      draw->AddRectFilled(a, ImVec2(a.x + cw + 0.5f, a.y + ch + 0.5f), c);
    }
  // Hemisphere: seen from above the normal, orthographic (x, y of the local direction), rings at 30 and 60
  // deg.
  const ImVec2 centre(origin.x + mapWidth + 12.0f + 0.5f * hemisphereSide, origin.y + 0.5f * hemisphereSide);
  const float radius = 0.5f * hemisphereSide - 2.0f;
  draw->AddCircleFilled(centre, radius, IM_COL32(30, 30, 36, 255), 64);
  // The lobe f cos under the points, 3 decades down from its peak.
  if (lobe_.size() == std::size_t(kLobeGrid) * kLobeGrid) {
    const float cell = 2.0f * radius / kLobeGrid;
    for (int j = 0; j < kLobeGrid; ++j)
      for (int i = 0; i < kLobeGrid; ++i) {
        const double v = lobe_[std::size_t(j) * kLobeGrid + i];
        if (!(v > 0.0)) continue;
        const float level = std::clamp(float((std::log10(v) - (lobeLogMax_ - 3.0)) / 3.0), 0.0f, 1.0f);
        const ImVec2 a(centre.x - radius + float(i) * cell, centre.y - radius + float(j) * cell);
        draw->AddRectFilled(
            a, ImVec2(a.x + cell + 0.5f, a.y + cell + 0.5f),
            IM_COL32(int(30 + 120 * level), int(30 + 90 * level), int(36 + 150 * level), 255));
      }
  }
  for (double deg : {30.0, 60.0})
    draw->AddCircle(centre, radius * float(std::sin(deg * 3.14159265358979 / 180.0)),
                    IM_COL32(70, 70, 80, 255), 64);
  draw->AddCircle(centre, radius, IM_COL32(120, 120, 130, 255), 64);
  const auto xyz = [](const auto& v) { return glm::dvec3(v.x, v.y, v.z); };
  const Frame frame = pixelFrame(pixel_);
  const glm::dvec3 n = frame.n, t = frame.t, b = frame.b;
  const auto toDisc = [&](const glm::dvec3& d) {
    return ImVec2(centre.x + radius * float(glm::dot(d, t)), centre.y - radius * float(glm::dot(d, b)));
  };
  const glm::dvec3 wo = glm::normalize(xyz(pixel_.view));
  const glm::dvec3 mirror = 2.0 * glm::dot(n, wo) * n - wo;  // where a mirror-like lobe sits
  draw->AddCircle(toDisc(mirror), 5.0f, IM_COL32(255, 255, 255, 200), 12, 1.5f);
  for (const RecordedSample& s : samples_) {
    // "none" (ris kept no candidate) and failed draws (pdf 0, a placeholder direction) are not samples to
    // show.
    if (s.technique == "none" || !(s.pdf > 0.0)) continue;
    const std::size_t k =
        std::size_t(std::find(techniques_.begin(), techniques_.end(), s.technique) - techniques_.begin());
    const ImU32 color = techniqueColor(k);
    draw->AddCircleFilled(ImVec2(origin.x + float(s.uv.x) * mapWidth, origin.y + float(s.uv.y) * mapHeight),
                          1.8f, color, 6);
    if (glm::dot(s.direction, n) > 0.0) draw->AddCircleFilled(toDisc(s.direction), 1.8f, color, 6);
  }
  // The chosen product nodes: outlined on the map where they are blocks of texels, and on the table panel
  // (right of the hemisphere, the table's columns x rows over the sampler's unit square) shaded from dark at
  // the least probable chosen node to kProductNodeColor at the most probable.
  float tableWidth = 0.0f;
  if (!productNodes_.empty()) {
    for (const ProductNodeChoice& c : productNodes_)
      if (c.mapUv)
        draw->AddRect(
            ImVec2(origin.x + float(c.mapUv->x) * mapWidth, origin.y + float(c.mapUv->y) * mapHeight),
            ImVec2(origin.x + float(c.mapUv->z) * mapWidth, origin.y + float(c.mapUv->w) * mapHeight),
            kProductNodeColor);
    tableWidth = hemisphereSide;
    const float cellW = tableWidth / float(productColumns_), cellH = cellW;
    const ImVec2 table(origin.x + mapWidth + 24.0f + hemisphereSide, origin.y);
    draw->AddRectFilled(table, ImVec2(table.x + tableWidth, table.y + cellH * float(productRows_)),
                        IM_COL32(30, 30, 36, 255));
    const double span = std::max(productLogMax_ - productLogMin_, 1e-9);
    const ImVec4 peak = ImGui::ColorConvertU32ToFloat4(kProductNodeColor);
    for (const ProductNodeChoice& c : productNodes_) {
      const float shade = 0.25f + 0.75f * float((std::log10(c.probability) - productLogMin_) / span);
      // A split node's child or grandchild: a half or quarter cell of its node.
      const float w = tableWidth / float(c.columns);
      const ImVec2 a(table.x + float(c.column()) * w, table.y + float(c.row()) * w);
      draw->AddRectFilled(
          a, ImVec2(a.x + w, a.y + w),
          ImGui::ColorConvertFloat4ToU32(ImVec4(peak.x * shade, peak.y * shade, peak.z * shade, 1.0f)));
    }
    draw->AddRect(table, ImVec2(table.x + tableWidth, table.y + cellH * float(productRows_)),
                  IM_COL32(120, 120, 130, 255));
  }
  ImGui::Dummy(ImVec2(mapWidth + 12.0f + hemisphereSide + (tableWidth > 0.0f ? 12.0f + tableWidth : 0.0f),
                      std::max(mapHeight, hemisphereSide)));
  for (std::size_t k = 0; k < techniques_.size(); ++k) {
    const auto count = std::count_if(samples_.begin(), samples_.end(),
                                     [&](const RecordedSample& s) { return s.technique == techniques_[k]; });
    ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(techniqueColor(k)), "%s: %lld", techniques_[k].c_str(),
                       static_cast<long long>(count));
    if (k + 1 < techniques_.size()) ImGui::SameLine();
  }
  ImGui::TextDisabled(
      "map: luminance, %.1f decades (log); disc: hemisphere from above over f cos, ring: mirror direction",
      double(logMax_ - logMin_));
  if (!productNodes_.empty())
    ImGui::TextDisabled(
        "product table %ux%u: %zu nodes chosen (%zu in split nodes), P(node) %.2g to %.2g (log "
        "shade)%s",
        productColumns_, productRows_, productNodes_.size(),
        std::size_t(std::count_if(productNodes_.begin(), productNodes_.end(),
                                  [&](const auto& c) { return c.columns > productColumns_; })),
        std::pow(10.0, productLogMin_), std::pow(10.0, productLogMax_),
        productNodes_.front().mapUv ? "; outlined on the map" : "");
}

}  // namespace iblx::viewer
