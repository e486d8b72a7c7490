// A compute pipeline with its four role descriptor sets (DESIGN §2 / STYLE "For iblx" 6: 0 frame, 1 sequence,
// 2 env sampler, 3 BRDF), each holding only storage buffers numbered from 0, plus one push-constant block.
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
};

class ComputeKernel {
 public:
  ComputeKernel(const VulkanContext& context, std::span<const uint32_t> spirv, const KernelLayout& layout,
                std::string name);

  // Binds buffers[i] to binding i of `set`; the count must match the layout.
  void bindBuffers(uint32_t set, std::initializer_list<const Buffer*> buffers);
  void bindBuffers(uint32_t set, std::span<const Buffer* const> buffers);

  void record(vk::CommandBuffer cmd, uint32_t groupsX, uint32_t groupsY, const void* pushConstants,
              uint32_t pushBytes) const;

  const std::string& name() const { return name_; }

 private:
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
