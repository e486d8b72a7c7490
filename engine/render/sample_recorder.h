// The samples the integrator draws for one pixel (`iblx samples`, the viewer's sample overlay), recorded by
// the integrator itself: integrate.comp compiled with IBLX_RECORD_SAMPLES runs the method's own parts for
// that pixel and stores what the strategy reports per sample (shaders/lib/sample_record.glsl), pass by pass
// as Renderer::runPass splits them. A new technique or method is recorded without any change here.
//
//   SampleRecorder recorder(ctx, compiler, scene, resolveMethod(spec, *scene.brdf), seed);
//   recorder.start(120, 80);                              // throws for a pixel off the image or the object
//   for (int pass = 0; pass < 4; ++pass) for (const RecordedSample& s : recorder.runPass(32)) use(s);
#pragma once

#include "engine/render/renderer.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace iblx {

// The node a product draw chose in the pixel's table of columns x rows nodes (row-major index node), with its
// probability P(node). On the lat-long map the node is the rectangle mapUv (u0, v0, u1, v1) when it is a
// block of texels (`product`, `product-mis`); the cells of a warp's unit square (`product-warp`,
// `product-warp-ot`) have no rectangle there.
struct ProductNodeChoice {
  uint32_t node = 0, columns = 0, rows = 0;
  double probability = 0.0;
  std::optional<glm::dvec4> mapUv;
  uint32_t column() const { return node % columns; }
  uint32_t row() const { return node / columns; }
};

// One direction drawn by a sample. A sample draws ResolvedMethod::drawsPerSample() directions (two-sample
// MIS: one from each technique, in that order), so runPass returns that many records per sample, with one
// index.
struct RecordedSample {
  uint64_t index = 0;  // of the sample in the pixel's sequence, from 0
  uint64_t pass = 0;   // the pass that drew it
  // Registry name of the technique that drew it (e.g. "env-cdf", "ggx-vndf"), "none" when nothing was drawn
  // (ris: every candidate had zero weight; all other fields are then 0).
  std::string_view technique;
  glm::dvec3 direction{0.0};     // world space (docs/DESIGN.md §3)
  glm::dvec3 envDirection{0.0};  // the same in the environment's frame (they differ under --env-rotation)
  glm::dvec2 uv{0.0};            // lat-long coordinates of envDirection (docs/DESIGN.md §3): its place on the map
  double pdf = 0.0;              // solid-angle density of the technique that drew it
  double misWeight = 0.0;        // MIS weight; 1 for a single technique and ris; 0 if it contributes nothing
  // Contribution weight per channel, as the strategy uses it: estimate = radiance * weight. Single technique:
  // f cos / pdf. mis: w f cos / p (two-sample), w f cos / (c p) with c the technique's share of samples
  // (one-sample, --mis-split). ris: f cos W with W = sum(w) / (M p^), the kept candidate's resampling weight.
  glm::dvec3 weight{0.0};
  glm::dvec3 radiance{0.0};  // the environment radiance the estimate used; 0 if it contributes nothing
  // What the integrator accumulated for this draw (after its NaN/Inf guard): the records of one sample sum
  // to the sample's estimate.
  glm::dvec3 estimate{0.0};
  glm::dvec2 point{0.0};  // the sequence's 2D point the direction was drawn from
  // Product draws (`product`, `product-mis`, `product-warp`, `product-warp-ot`): the node of the pixel's
  // table that the draw chose.
  std::optional<ProductNodeChoice> productNode;
};

// Why pixel (x, y) of `gbuffer` cannot be recorded (outside the image, background), or nothing.
std::optional<std::string> unrecordablePixel(const GBuffer& gbuffer, int x, int y);

class SampleRecorder {
 public:
  SampleRecorder(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                 const ResolvedMethod& method, uint32_t seed = 1);

  // Starts over at pixel (x, y) with sample 0. Throws iblx::Error for a pixel that unrecordablePixel rejects.
  void start(int x, int y);
  // The next pass: `samplesPerPass` samples of the pixel, as Renderer::runPass draws them, in sample order.
  std::vector<RecordedSample> runPass(uint32_t samplesPerPass);

  uint64_t samplesPerPixel() const { return renderer_.samplesPerPixel(); }
  glm::dvec3 pixelMean() const;  // the integrator's running mean of the pixel over every sample so far
  uint32_t nonFiniteSamples() const { return renderer_.nonFiniteSamples(); }
  double setupSeconds() const { return renderer_.setupSeconds(); }

 private:
  const Scene& scene_;
  ResolvedMethod method_;
  Renderer renderer_;
  uint32_t x_ = 0, y_ = 0;
  bool started_ = false;
  uint64_t passes_ = 0;  // run since start()
};

}  // namespace iblx
