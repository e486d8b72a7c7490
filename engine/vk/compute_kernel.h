// A compute pipeline with its four role descriptor sets (docs/DESIGN.md §2: 0 frame, 1 sequence,
// 2 env sampler, 3 BRDF), each holding buffers numbered from 0, plus one push-constant block. A binding is a
// storage buffer or a read-only table: a uniform texel buffer whose elements are 1, 2 or 4 32-bit words
// (R32 / R32G32 / R32G32B32A32_UINT, Buffer::tableElementWords), read in GLSL through shaders/lib/table.glsl.
// Tables exist for speed: lavapipe turns a storage-buffer load at a lane-dependent index into a loop over the
// SIMD lanes with a branch per lane, and a texel fetch into one gather (docs/BENCHMARKS.md, "What was tried
// for speed").
//
//   ComputeKernel kernel(ctx, spirv, {.buffersPerSet = {4, 0, 2, 1}, .pushConstantBytes =
//   sizeof(FrameParams)}, "x"); kernel.bindBuffers(0, {&gbuffer, &accum, &env, &rows});
//   ctx.submitAndWait([&](vk::CommandBuffer cmd) { kernel.record(cmd, groupsX, groupsY, &params, sizeof
//   params); });
#pragma once

#include "engine/vk/buffer.h"

#include <array>
#include <initializer_list>

namespace iblx {

struct KernelLayout {
  std::array<uint32_t, 4> buffersPerSet{};
  uint32_t pushConstantBytes = 0;
  std::array<uint32_t, 4> tableBindings{};  // per set, bit b: binding b is a table, not a storage buffer
};

// The bit mask of `count` bindings from `first` on, for KernelLayout::tableBindings.
constexpr uint32_t bindingBits(uint32_t first, uint32_t count) {
  return count == 0 ? 0u : ((count >= 32u ? ~0u : (1u << count) - 1u) << first);
}
static_assert(bindingBits(2, 2) == 0b1100u && bindingBits(0, 0) == 0u && bindingBits(0, 32) == ~0u);

class ComputeKernel {
 public:
  ComputeKernel(const VulkanContext& context, std::span<const uint32_t> spirv, const KernelLayout& layout,
                std::string name);

  // Binds buffers[i] to binding i of `set`; the count must match the layout. A table larger than the device's
  // maxTexelBufferElements elements throws DeviceLimitError.
  void bindBuffers(uint32_t set, std::initializer_list<const Buffer*> buffers);
  void bindBuffers(uint32_t set, std::span<const Buffer* const> buffers);

  void record(vk::CommandBuffer cmd, uint32_t groupsX, uint32_t groupsY, const void* pushConstants,
              uint32_t pushBytes) const;

  const std::string& name() const { return name_; }

 private:
  vk::DescriptorType descriptorType(uint32_t set, uint32_t binding) const;

  const VulkanContext* context_;
  KernelLayout layout_;
  std::string name_;
  // Destruction in reverse declaration order: sets, pool, pipeline, layouts.
  std::vector<vk::raii::DescriptorSetLayout> setLayouts_;
  vk::raii::PipelineLayout pipelineLayout_ = nullptr;
  vk::raii::ShaderModule module_ = nullptr;
  vk::raii::Pipeline pipeline_ = nullptr;
  vk::raii::DescriptorPool pool_ = nullptr;
  std::vector<vk::raii::DescriptorSet> sets_;
  std::array<std::vector<vk::raii::BufferView>, 4> tableViews_;  // the views bound to each set's tables
};

// Barrier after a dispatch: its shader writes become visible to later dispatches' shader reads and writes and,
// with `host`, to host reads after the submission's fence.
void recordShaderWriteBarrier(vk::CommandBuffer cmd, bool host);

// Two GPU timestamps around recorded work; seconds() after the submission completed.
class TimestampPair {
 public:
  explicit TimestampPair(const VulkanContext& context);
  void begin(vk::CommandBuffer cmd) const;
  void end(vk::CommandBuffer cmd) const;
  double seconds() const;  // 0 when the queue has no timestamps

 private:
  const VulkanContext* context_;
  vk::raii::QueryPool pool_ = nullptr;
};

}  // namespace iblx
