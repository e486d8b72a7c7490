// The progressive renderer (docs/DESIGN.md §2, §6): builds the method's sampling data, assembles and compiles
// its integrator, and adds one batch of samples per pixel per pass to a running mean, timed on the GPU and
// the wall.
//
//   Renderer renderer(ctx, compiler, scene, resolveMethod(methodSpec, *scene.brdf), seed);
//   for (int i = 0; i < 16; ++i) renderer.runPass(64);
//   auto rgb = renderer.meanRgb();
#pragma once

#include "engine/render/kernel_assembly.h"
#include "engine/render/scene_gpu.h"
#include "engine/scene/scene.h"
#include "engine/vk/compute_kernel.h"
#include "engine/vk/shader_compiler.h"

#include <array>
#include <chrono>
#include <memory>

namespace iblx {

static_assert(sizeof(gpu::SampleRecord) ==
              112);  // std430: four vec4, two floats, two uints, four scalars, a vec4

struct PassTiming {
  double gpuSeconds = 0.0;   // the pass's dispatches alone (timestamp queries)
  double wallSeconds = 0.0;  // record + submit + wait
};

class Renderer {
 public:
  // IntegratorMode::RecordPixel integrates only the pixel of setRecordedPixel and records its samples
  // (engine/render/sample_recorder.h uses it); everything else works as for an image.
  Renderer(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
           const ResolvedMethod& method, uint32_t seed = 1, IntegratorMode mode = IntegratorMode::Image);

  PassTiming runPass(uint32_t samplesPerPass);
  void restart(uint32_t seed);  // drops everything accumulated

  // New BRDF parameter values (complete, as resolveParams returns them; range-checked): rewrites the
  // parameter block and restarts accumulation, without recompiling (the viewer's sliders, --param sweeps).
  // The BRDF technique's tables stay those of the values the renderer was made with: still exact pdfs, so
  // still unbiased, though brdf-tab may fit the new lobe less well until a new renderer rebuilds them.
  void setParams(const ParamValues& values);
  const ParamValues& params() const { return params_; }
  // Another view of the same scene: `scene` may differ from the current one only in its G-buffer (camera or
  // object moved), with the same image size. Uploads the G-buffer and restarts accumulation; tables, shaders
  // and the environment stay (the viewer's orbit). `scene` must outlive the renderer, as in the constructor.
  // Throws iblx::Error on a different image size or environment.
  void setView(const Scene& scene);

  uint64_t samplesPerPixel() const { return samplesPerPixel_; }
  std::vector<float> meanRgb() const;  // width*height*3
  // The accumulation (gpu::AccumPixel per pixel, running means) and the G-buffer on the device, for kernels
  // that show the image without reading it back (the viewer's display kernel).
  const Buffer& accumulation() const { return gpu_.accum; }
  const Buffer& gbufferBuffer() const { return gpu_.gbuffer; }
  std::vector<float> varianceRgb() const;  // per-pixel sample variance of one estimate, width*height*3
  uint32_t nonFiniteSamples() const;
  double setupSeconds() const { return setupSeconds_; }  // table builds + shader compile + upload
  // How many buffers hold the per-pixel product tables across dispatches (0: rebuilt in every dispatch).
  std::size_t productTableChunks() const { return productTables_.size(); }

  // IntegratorMode::RecordPixel only: the pixel the passes integrate (restarts accumulation; the caller
  // checks it is an object pixel), and the records of the last pass's samples in sample order.
  void setRecordedPixel(uint32_t x, uint32_t y);
  std::vector<gpu::SampleRecord> lastPassRecords() const;
  // The running mean of one pixel (meanRgb without reading the whole image).
  std::array<float, 3> pixelMean(uint32_t x, uint32_t y) const;

 private:
  std::chrono::steady_clock::time_point created_ = std::chrono::steady_clock::now();  // first: setup timing
  const VulkanContext& context_;
  const Scene* scene_;  // a pointer, not a reference: setView rebinds it
  ResolvedMethod method_;
  SceneGpu gpu_;
  std::vector<Buffer> envBuffers_, brdfTechniqueBuffers_;
  IntegratorMode mode_;
  Buffer sampleRecords_;  // RecordPixel: one pass's records, grown with the samples per pass
  // Image mode of a product strategy: every pixel's product table, kept across the dispatches of an
  // accumulation (kProductTableBinding on), in up to kProductTableMaxChunks buffers; else empty.
  std::vector<Buffer> productTables_;
  uint32_t recordX_ = 0, recordY_ = 0, lastPassSamples_ = 0;
  std::unique_ptr<ComputeKernel> kernel_;  // after the buffers its sets refer to: destroyed before them
  // With productTables_: builds them, dispatched before the integrator at the start of an accumulation.
  std::unique_ptr<ComputeKernel> productTableKernel_;
  void bindFrameSet();  // set 0: the frame buffers, then sampleRecords_ or productTables_ when in use
  TimestampPair timestamps_;
  uint64_t samplesPerPixel_ = 0;
  uint32_t seed_ = 1;
  ParamValues params_;
  double setupSeconds_ = 0.0;
};

}  // namespace iblx
