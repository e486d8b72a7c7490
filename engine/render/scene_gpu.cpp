// Upload of a scene's buffers and a technique's tables (scene_gpu.h).
#include "engine/render/scene_gpu.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/setting.h"
#include "engine/io/latlong_texel.h"
#include "engine/scene/brdf_params.h"

#include <algorithm>
#include <cmath>

namespace iblx {

void checkImageFitsDevice(const VulkanContext& context, int width, int height) {
  const std::uint64_t pixels = std::uint64_t(std::max(width, 0)) * std::uint64_t(std::max(height, 0));
  const std::uint64_t largest = context.limits().maxStorageBufferRange;
  const std::uint64_t bytesPerPixel = std::max(sizeof(gpu::GPixel), sizeof(gpu::AccumPixel));
  if (pixels * bytesPerPixel <= largest) return;
  const int side = int(std::sqrt(double(largest / bytesPerPixel)));
  std::string problem = " " + std::to_string(width) + "x" + std::to_string(height);
  problem.append(": the G-buffer needs ").append(formatBytes(pixels * sizeof(gpu::GPixel)));
  problem.append(", more than this device's largest storage buffer (").append(formatBytes(largest));
  problem.append("); images up to about ")
      .append(std::to_string(side))
      .append("x")
      .append(std::to_string(side));
  throw SettingError(Setting::ImageSize, "", problem.append(" pixels fit"));
}

Scene loadSceneFor(const VulkanContext& context, const SceneSpec& spec) {
  checkImageFitsDevice(context, spec.width, spec.height);
  const DeviceTableLimit tableLimit(
      [&context] { return std::uint64_t(context.limits().maxStorageBufferRange); });
  return loadScene(spec);
}

Scene loadSceneFor(const VulkanContext& context, const SceneSpec& spec, LoadedBrdf brdf) {
  checkImageFitsDevice(context, spec.width, spec.height);
  return loadScene(spec, std::move(brdf));
}

SceneGpu uploadScene(const VulkanContext& context, const Scene& scene) {
  const auto& g = scene.gbuffer;
  const std::size_t pixels = g.pixels.size();
  std::vector<float> rows = envRowTable(scene.env.width, scene.env.height);
  std::vector<float> params = packParams(*scene.brdf, scene.params);
  SceneGpu gpu{Buffer::fromData(context, g.pixels, "gbuffer"),
               Buffer(context, pixels * sizeof(gpu::AccumPixel), "accumulation"),
               Buffer::fromData(context, rows, "environment row table", 4),
               Buffer(context, sizeof(gpu::KernelStats), "kernel stats"),
               Buffer::fromData(context, params, "brdf parameters")};
  const std::size_t texels = std::size_t(scene.env.width) * std::size_t(scene.env.height);
  const std::size_t bytesPerTexel = 3 * sizeof(float);
  // Each chunk is one buffer, read as a table: it must fit both limits.
  const std::size_t chunkBytes = std::min<std::size_t>(
      context.limits().maxStorageBufferRange, std::size_t(context.limits().maxTexelBufferElements) * 4);
  gpu.envTexelsPerChunk = std::min<std::size_t>(texels, chunkBytes / bytesPerTexel);
  const std::size_t chunks = (texels + gpu.envTexelsPerChunk - 1) / gpu.envTexelsPerChunk;
  if (chunks > kMaxEnvRadianceChunks)
    throw DeviceLimitError("the environment map's " + std::to_string(texels * bytesPerTexel >> 20) +
                           " MiB of radiance need " + std::to_string(chunks) + " buffers on this device (" +
                           std::to_string(chunkBytes >> 20) + " MiB each), more than " +
                           std::to_string(kMaxEnvRadianceChunks) + "; use a smaller map");
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t first = c * gpu.envTexelsPerChunk,
                      count = std::min(gpu.envTexelsPerChunk, texels - first);
    const std::span<const float> chunk(scene.env.rgb.data() + 3 * first, 3 * count);
    gpu.envRgb.push_back(Buffer::fromData(
        context, chunk, chunks == 1 ? "environment radiance" : "environment radiance " + std::to_string(c)));
  }
  if (scene.brdf->data) {
    const TechniqueData data = scene.brdf->data(scene);
    // A table too large for the device names the file it came from.
    gpu.brdfData = uploadTables(
        context, data, "BRDF " + (scene.brdfFile.empty() ? scene.brdf->name : scene.brdfFile.string()));
    gpu.brdfDataLayout = data.layout();
  }
  gpu.accum.fill(0);
  gpu.stats.fill(0);
  return gpu;
}

std::vector<Buffer> uploadTables(const VulkanContext& context, const TechniqueData& data,
                                 const std::string& owner) {
  std::vector<Buffer> buffers;
  for (const TechniqueTable& table : data.tables)
    buffers.push_back(Buffer::fromData(context, std::span<const std::byte>(table.bytes),
                                       owner + " " + table.name, table.words));
  return buffers;
}

std::array<const Buffer*, 8> SceneGpu::frameSet() const {
  auto chunk = [&](std::size_t c) { return c < envRgb.size() ? &envRgb[c] : &envRgb[0]; };
  return {&gbuffer, &accum, &envRgb[0], &envRows, &stats, chunk(1), chunk(2), chunk(3)};
}

EnvChunking SceneGpu::chunking() const {
  return {envRgb.size(), envTexelsPerChunk};
}

std::vector<const Buffer*> SceneGpu::brdfSet(std::span<const Buffer> techniqueBuffers) const {
  std::vector<const Buffer*> set{&brdfParams};
  for (const auto& b : brdfData) set.push_back(&b);
  for (const auto& b : techniqueBuffers) set.push_back(&b);
  return set;
}

}  // namespace iblx
