// The GPU copy of a scene (engine/scene/scene.h): the set-0 and set-3 buffers shared by the integrator and
// the reference kernel, and the upload of a technique's tables.
#pragma once

#include "engine/scene/kernel_prelude.h"
#include "engine/scene/scene.h"
#include "engine/vk/buffer.h"

#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

// Set-0 and set-3 buffers shared by the integrator and the reference kernel.
// A map's radiance may exceed the device's largest storage buffer (lavapipe: 128 MiB, 11 M texels): it is
// then uploaded in up to this many buffers of whole texels (shaders/lib/frame_resources.glsl).
inline constexpr std::size_t kMaxEnvRadianceChunks = 4;

struct SceneGpu {
  Buffer gbuffer, accum, envRows, stats, brdfParams;
  std::vector<Buffer> envRgb;  // the radiance in chunks of envTexelsPerChunk texels (usually one)
  std::size_t envTexelsPerChunk = 0;
  std::vector<Buffer> brdfData;  // the BRDF's own tables (BrdfInfo::data), bindings 1.. of set 3
  TechniqueData brdfDataLayout;  // their names and widths, for the preludes
  // Set 0 (shaders/lib/frame_resources.glsl) in binding order; bindings 5-7 repeat chunk 0 when unused.
  std::array<const Buffer*, 8> frameSet() const;
  // The chunking of the radiance, for the preludes of kernels that include frame_resources.glsl.
  EnvChunking chunking() const;
  // Set 3: the parameter block, the BRDF's data, then `techniqueBuffers` (a BRDF technique's tables).
  std::vector<const Buffer*> brdfSet(std::span<const Buffer> techniqueBuffers = {}) const;
};
SceneGpu uploadScene(const VulkanContext& context, const Scene& scene);

// Throws a SettingError naming the image size when the per-pixel buffers of a width x height image exceed
// the device's largest storage buffer; checked before the scene (its G-buffer) is built.
void checkImageFitsDevice(const VulkanContext& context, int width, int height);
// loadScene (engine/scene/scene.h) for this device: an image larger than it can hold is refused before the
// scene's G-buffer is built.
Scene loadSceneFor(const VulkanContext& context, const SceneSpec& spec);
Scene loadSceneFor(const VulkanContext& context, const SceneSpec& spec, LoadedBrdf brdf);
// A technique's (or a BRDF's) tables as buffers, in binding order, each viewed with its element width and
// named "<owner> <table>" for validation messages.
std::vector<Buffer> uploadTables(const VulkanContext& context, const TechniqueData& data,
                                 const std::string& owner);

}  // namespace iblx
