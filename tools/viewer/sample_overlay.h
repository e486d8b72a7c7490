// The viewer's sample overlay: one pixel's recorded samples (engine/render/sample_recorder.h) drawn as points
// on the lat-long environment map, over the map's luminance (the density env-cdf and env-hier sample, per
// solid angle) on a log scale, and on a view of the pixel's hemisphere seen from above the normal, one colour
// per technique. For the product strategies it also shows the node each draw chose in the pixel's product
// table (the deepest: a split node's child or grandchild where `product` refined it): outlined on the map
// where nodes are blocks of texels, and on a panel of the whole table, each at its own size, shaded by its
// probability.
#pragma once

#include "engine/render/sample_recorder.h"

#include <imgui.h>

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace iblx::viewer {

class SampleOverlay {
 public:
  // The map whose density is shown (downsampled once per scene).
  void setEnvironment(const EnvImage& env);
  // methodLabel: the method that drew them (ResolvedMethod::label()); lobe: lobeOnDisc's values.
  void setSamples(int x, int y, const gpu::GPixel& pixel, std::vector<RecordedSample> samples,
                  std::string methodLabel, std::vector<double> lobe);

  // The BRDF lobe f cos (luminance) of the pixel's view over the hemisphere disc, kLobeGrid^2 cells seen from
  // above the normal (orthographic); -1 outside the disc. evaluate(wi, wo) gives f in the local frame (normal
  // +z), as engine/render/brdf_tabulation.h's evaluateBrdf does.
  static constexpr int kLobeGrid = 48;
  static std::vector<double> lobeOnDisc(
      const gpu::GPixel& pixel,
      const std::function<std::vector<glm::dvec3>(std::span<const glm::dvec3>, std::span<const glm::dvec3>)>&
          evaluate);
  void clear() { samples_.clear(); }
  bool empty() const { return samples_.empty(); }
  int pixelX() const { return x_; }
  int pixelY() const { return y_; }
  std::size_t sampleCount() const { return samples_.size(); }
  // Whether the samples chose nodes of a product table (the table panel is drawn).
  bool hasProductNodes() const { return !productNodes_.empty(); }
  const std::string& methodLabel() const { return methodLabel_; }

  // Draws the map panel (width w, height w/2), the hemisphere (side h) and, with product nodes, the product
  // table (width h) side by side at the cursor.
  void draw(float mapWidth, float hemisphereSide) const;

 private:
  static constexpr int kGridWidth = 128, kGridHeight = 64;
  std::vector<float> logLuminance_;       // kGridWidth x kGridHeight, log10, row 0 at v = 0 (the top, +Y)
  float logMin_ = -1.0f, logMax_ = 0.0f;  // the colour scale's ends
  std::vector<RecordedSample> samples_;
  std::vector<double> lobe_;
  double lobeLogMax_ = 0.0;
  std::vector<std::string> techniques_;  // in order of first appearance: the colour index
  // The distinct product nodes chosen, the deepest node of each draw (their first choice; a node's
  // probability is the pixel's, the same in every draw), and the table's size.
  std::vector<ProductNodeChoice> productNodes_;
  uint32_t productColumns_ = 0, productRows_ = 0;
  double productLogMin_ = 0.0, productLogMax_ = 0.0;  // log10 P over the chosen nodes
  gpu::GPixel pixel_{};
  int x_ = -1, y_ = -1;
  std::string methodLabel_;
};

// The colour of the k-th technique (also the legend's).
ImU32 techniqueColor(std::size_t k);
// The outline of a chosen product node on the map, and the colour of the most probable node on the table
// panel.
inline constexpr ImU32 kProductNodeColor = IM_COL32(255, 60, 230, 255);

}  // namespace iblx::viewer
