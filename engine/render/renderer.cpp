// Progressive renderer implementation.
#include "engine/render/renderer.h"

#include "engine/core/error.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/render/kernel_assembly.h"
#include "engine/sampling/env/mis_compensation.h"
#include "engine/core/sphere_mapping.h"
#include "engine/scene/brdf_params.h"

#include <chrono>
#include <cmath>
#include <limits>

namespace iblx {
namespace {
constexpr uint32_t kMaxSamplesPerDispatch = 256;
constexpr vk::DeviceSize kProductTableBudget = vk::DeviceSize(2) << 30;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
}  // namespace

Renderer::Renderer(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                   const ResolvedMethod& method, uint32_t seed, IntegratorMode mode)
    : context_(context),
      scene_(&scene),
      method_(method),
      gpu_(uploadScene(context, scene)),
      mode_(mode),
      timestamps_(context),
      seed_(seed),
      params_(scene.params) {
  // MIS compensation changes only the density the env technique samples; radiance still comes from scene.env.
  TechniqueData envData;
  if (method.envTechnique) {
    const auto& build = method.method->envData ? method.method->envData : method.envTechnique->build;
    envData = method.misCompensation ? build(misCompensated(scene.env)) : build(scene.env);
  }
  envBuffers_ = uploadTables(context, envData, method.envTechnique ? method.envTechnique->name : "");
  TechniqueData brdfData = method.brdfTechnique && method.brdfTechnique->build
                               ? method.brdfTechnique->build(scene, VulkanServices(context, compiler))
                               : TechniqueData{};
  brdfTechniqueBuffers_ =
      uploadTables(context, brdfData, method.brdfTechnique ? method.brdfTechnique->name : "");
  const bool recording = mode == IntegratorMode::RecordPixel;
  // A product strategy keeps its per-pixel tables across dispatches where the image's fit
  // kProductTableMaxChunks of the device's largest buffers and kProductTableBudget (lavapipe's 128 MiB
  // buffers hold 85,816 pixels' tables each, so 512 x 512 in four and up to 585 x 585; 2 GiB holds
  // 1024 x 1024); else each dispatch rebuilds them in private memory.
  const ProductTableChunks productTables = [&] {
    const vk::DeviceSize pixels = vk::DeviceSize(scene.gbuffer.width) * vk::DeviceSize(scene.gbuffer.height);
    const vk::DeviceSize pixelBytes = vk::DeviceSize(kProductTableStride) * sizeof(uint32_t);
    const vk::DeviceSize perChunk = context.limits().maxStorageBufferRange / pixelBytes;
    if (recording || !method.method->strategyInfo().buildsProductTable || perChunk == 0 ||
        pixels * pixelBytes > kProductTableBudget)
      return ProductTableChunks{};
    const vk::DeviceSize chunks = (pixels + perChunk - 1) / perChunk;
    if (chunks > kProductTableMaxChunks) return ProductTableChunks{};
    // Even chunks: the last holds no fewer pixels than the others need.
    const vk::DeviceSize pixelsPerChunk = (pixels + chunks - 1) / chunks;
    return ProductTableChunks{uint32_t(chunks), uint32_t(pixelsPerChunk)};
  }();
  for (uint32_t c = 0; c < productTables.chunks; ++c) {
    const vk::DeviceSize first = vk::DeviceSize(c) * productTables.pixelsPerChunk;
    const vk::DeviceSize pixels = std::min<vk::DeviceSize>(
        productTables.pixelsPerChunk, vk::DeviceSize(scene.gbuffer.width) * scene.gbuffer.height - first);
    productTables_.emplace_back(context, pixels * kProductTableStride * sizeof(uint32_t),
                                "product tables " + std::to_string(c));
  }
  const std::string name = (recording ? "record samples " : "integrate ") + method.label();
  const KernelParts parts = integratorParts(scene, gpu_.brdfDataLayout, gpu_.chunking(), method, envData,
                                            brdfData, mode, productTables);
  const auto spirv = compileKernel(compiler, parts, name);
  const auto brdfSet = gpu_.brdfSet(brdfTechniqueBuffers_);
  KernelLayout layout = sceneKernelLayout(uint32_t(envBuffers_.size()), uint32_t(brdfSet.size() - 1));
  if (recording) layout.buffersPerSet[0] = kSampleRecordBinding + 1;
  if (productTables.chunks > 0) layout.buffersPerSet[0] = kProductTableBinding + productTables.chunks;
  kernel_ = std::make_unique<ComputeKernel>(context, spirv, layout, name);
  if (productTables.chunks > 0) {
    // The product-table kernel: lavapipe would run a build inside the integrator in every dispatch, behind
    // whatever branch.
    const std::string tablesName = "product-table kernel " + method.label();
    productTableKernel_ = std::make_unique<ComputeKernel>(
        context,
        compileKernel(compiler,
                      integratorParts(scene, gpu_.brdfDataLayout, gpu_.chunking(), method, envData, brdfData,
                                      IntegratorMode::ProductTables, productTables),
                      tablesName),
        layout, tablesName);
  }
  if (recording) sampleRecords_ = Buffer(context, 0, "sample records");
  bindFrameSet();
  std::vector<const Buffer*> env;
  for (const auto& b : envBuffers_) env.push_back(&b);
  for (ComputeKernel* k : {kernel_.get(), productTableKernel_.get()}) {
    if (!k) continue;
    k->bindBuffers(2, env);
    k->bindBuffers(3, brdfSet);
  }
  setupSeconds_ = since(created_);
}

void Renderer::bindFrameSet() {
  const auto frame = gpu_.frameSet();
  static_assert(std::tuple_size_v<decltype(frame)> == kSampleRecordBinding &&
                    kSampleRecordBinding == kProductTableBinding,
                "the records or the product tables follow the frame set");
  std::vector<const Buffer*> set(frame.begin(), frame.end());
  if (mode_ == IntegratorMode::RecordPixel)
    set.push_back(&sampleRecords_);
  else
    for (const Buffer& chunk : productTables_) set.push_back(&chunk);
  kernel_->bindBuffers(0, set);
  if (productTableKernel_) productTableKernel_->bindBuffers(0, set);
}

void Renderer::setRecordedPixel(uint32_t x, uint32_t y) {
  if (mode_ != IntegratorMode::RecordPixel)
    throw Error("setRecordedPixel: the renderer does not record samples");
  if (x >= uint32_t(scene_->gbuffer.width) || y >= uint32_t(scene_->gbuffer.height))
    throw Error("setRecordedPixel: pixel outside the image");
  recordX_ = x;
  recordY_ = y;
  restart(seed_);
}

std::vector<gpu::SampleRecord> Renderer::lastPassRecords() const {
  if (mode_ != IntegratorMode::RecordPixel)
    throw Error("lastPassRecords: the renderer does not record samples");
  std::vector<gpu::SampleRecord> records(std::size_t(lastPassSamples_) * method_.drawsPerSample());
  sampleRecords_.read(records.data(), records.size() * sizeof(gpu::SampleRecord));
  return records;
}

std::array<float, 3> Renderer::pixelMean(uint32_t x, uint32_t y) const {
  gpu::AccumPixel pixel;
  gpu_.accum.read(&pixel, sizeof pixel,
                  (vk::DeviceSize(y) * uint32_t(scene_->gbuffer.width) + x) * sizeof pixel);
  return {pixel.mean.x, pixel.mean.y, pixel.mean.z};
}

void Renderer::setParams(const ParamValues& values) {
  for (const ParamDecl& p : scene_->brdf->params) {
    const auto it = values.find(p.name);
    if (it == values.end()) throw Error("setParams: no value for parameter '" + p.name + "'");
    for (int c = 0; c < (p.type == ParamType::Color ? 3 : 1); ++c)
      if (!(it->second[std::size_t(c)] >= p.min && it->second[std::size_t(c)] <= p.max))
        throw Error("setParams: '" + p.name + "' out of range [" + std::to_string(p.min) + ", " +
                    std::to_string(p.max) + "]");
  }
  if (values.size() != scene_->brdf->params.size())
    throw Error("setParams: a value for a parameter BRDF '" + scene_->brdf->name + "' does not have");
  const std::vector<float> packed = packParams(*scene_->brdf, values);
  gpu_.brdfParams.write(packed.data(), packed.size() * sizeof(float));
  params_ = values;
  restart(seed_);
}

void Renderer::setView(const Scene& scene) {
  if (scene.gbuffer.width != scene_->gbuffer.width || scene.gbuffer.height != scene_->gbuffer.height)
    throw Error("setView: the image size changed (" + std::to_string(scene_->gbuffer.width) + "x" +
                std::to_string(scene_->gbuffer.height) + " to " + std::to_string(scene.gbuffer.width) + "x" +
                std::to_string(scene.gbuffer.height) + "); build a new renderer");
  if (scene.env.width != scene_->env.width || scene.env.height != scene_->env.height ||
      scene.envRotationDeg != scene_->envRotationDeg || scene.brdf != scene_->brdf)
    throw Error(
        "setView: only the G-buffer may change; build a new renderer for another environment or BRDF");
  gpu_.gbuffer.write(scene.gbuffer.pixels.data(), scene.gbuffer.pixels.size() * sizeof(gpu::GPixel));
  scene_ = &scene;
  restart(seed_);
}

void Renderer::restart(uint32_t seed) {
  seed_ = seed;
  samplesPerPixel_ = 0;
  lastPassSamples_ = 0;
  gpu_.stats.fill(0);
}

PassTiming Renderer::runPass(uint32_t samplesPerPass) {
  if (samplesPerPass == 0) throw Error("samples per pass must be at least 1");
  if (samplesPerPixel_ + samplesPerPass > std::numeric_limits<uint32_t>::max())
    throw Error("more than 2^32 samples per pixel: the sample index would wrap");
  const auto start = Clock::now();
  const double rotation = scene_->envRotationDeg * kPi / 180.0;
  gpu::FrameParams params{};
  params.width = uint32_t(scene_->gbuffer.width);
  params.height = uint32_t(scene_->gbuffer.height);
  params.envWidth = uint32_t(scene_->env.width);
  params.envHeight = uint32_t(scene_->env.height);
  params.sampleOffset = uint32_t(samplesPerPixel_);
  params.samplesPerPass = samplesPerPass;
  params.seed = seed_;
  params.envRotation = {float(std::cos(rotation)), float(std::sin(rotation)), 0, 0};
  params.strategy = {method_.misEnvFraction, method_.misPower ? 1.0f : 0.0f, 0, 0};
  // Recording integrates one pixel with one invocation (integrate.comp), so one group is dispatched.
  const bool recording = mode_ == IntegratorMode::RecordPixel;
  const uint32_t groupsX = recording ? 1 : (params.width + 7) / 8,
                 groupsY = recording ? 1 : (params.height + 7) / 8;
  if (recording) {
    const vk::DeviceSize recordBytes =
        vk::DeviceSize(samplesPerPass) * method_.drawsPerSample() * sizeof(gpu::SampleRecord);
    if (sampleRecords_.size() < recordBytes) {
      sampleRecords_ = Buffer(context_, recordBytes, "sample records");
      bindFrameSet();
    }
    params.recordPixelX = recordX_;
    params.recordPixelY = recordY_;
    params.recordFirstSample = uint32_t(samplesPerPixel_);
    params.recordCapacity = samplesPerPass;
    lastPassSamples_ = samplesPerPass;
  }
  context_.submitAndWait([&](vk::CommandBuffer cmd) {
    timestamps_.begin(cmd);
    // A pass is split into dispatches of at most kMaxSamplesPerDispatch samples: lavapipe ends loops after
    // about 65535 iterations per invocation, and parts may loop per sample; short dispatches also suit GPU
    // watchdogs.
    for (uint32_t done = 0; done < samplesPerPass; done += kMaxSamplesPerDispatch) {
      params.sampleOffset = uint32_t(samplesPerPixel_) + done;
      params.samplesPerPass = std::min(kMaxSamplesPerDispatch, samplesPerPass - done);
      if (done > 0)
        recordShaderWriteBarrier(cmd, false);  // accumulation of the previous dispatch -> this one
      if (params.sampleOffset == 0 && productTableKernel_) {
        productTableKernel_->record(cmd, groupsX, groupsY, &params, sizeof params);
        recordShaderWriteBarrier(cmd, false);  // the tables -> the integrator that samples them
      }
      kernel_->record(cmd, groupsX, groupsY, &params, sizeof params);
    }
    timestamps_.end(cmd);
    recordShaderWriteBarrier(cmd, true);  // -> the next pass and the host
  });
  samplesPerPixel_ += samplesPerPass;
  return {timestamps_.seconds(), since(start)};
}

std::vector<float> Renderer::meanRgb() const {
  const auto accum = gpu_.accum.readAll<gpu::AccumPixel>();
  std::vector<float> rgb(accum.size() * 3);
  for (size_t i = 0; i < accum.size(); ++i) {
    rgb[3 * i] = accum[i].mean.x;
    rgb[3 * i + 1] = accum[i].mean.y;
    rgb[3 * i + 2] = accum[i].mean.z;
  }
  return rgb;
}

std::vector<float> Renderer::varianceRgb() const {
  const auto accum = gpu_.accum.readAll<gpu::AccumPixel>();
  std::vector<float> var(accum.size() * 3);
  const double n = double(samplesPerPixel_);
  for (size_t i = 0; i < accum.size(); ++i) {
    const float m[3] = {accum[i].mean.x, accum[i].mean.y, accum[i].mean.z};
    const float s[3] = {accum[i].meanSquare.x, accum[i].meanSquare.y, accum[i].meanSquare.z};
    for (int c = 0; c < 3; ++c) {
      const double v = std::max(0.0, double(s[c]) - double(m[c]) * m[c]);
      var[3 * i + c] = float(n > 1 ? v * n / (n - 1) : 0.0);  // unbiased sample variance
    }
  }
  return var;
}

uint32_t Renderer::nonFiniteSamples() const {
  gpu::KernelStats stats;
  gpu_.stats.read(&stats, sizeof stats);
  return stats.nonFiniteSamples;
}

}  // namespace iblx
