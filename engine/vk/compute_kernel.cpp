// Pipeline, descriptor-set and timestamp plumbing for compute kernels.
#include "engine/vk/compute_kernel.h"

#include "engine/core/error.h"

namespace iblx {

ComputeKernel::ComputeKernel(const VulkanContext& context, std::span<const uint32_t> spirv,
                             const KernelLayout& layout, std::string name)
    : context_(&context), layout_(layout), name_(std::move(name)) {
  const auto& device = context.device();
  uint32_t totalBuffers = 0;
  for (uint32_t set = 0; set < 4; ++set) {
    std::vector<vk::DescriptorSetLayoutBinding> bindings;
    for (uint32_t b = 0; b < layout.buffersPerSet[set]; ++b)
      bindings.emplace_back(b, vk::DescriptorType::eStorageBuffer, 1, vk::ShaderStageFlagBits::eCompute);
    totalBuffers += layout.buffersPerSet[set];
    setLayouts_.emplace_back(device, vk::DescriptorSetLayoutCreateInfo({}, bindings));
  }
  std::vector<vk::DescriptorSetLayout> rawLayouts;
  for (const auto& l : setLayouts_) rawLayouts.push_back(*l);
  std::vector<vk::PushConstantRange> ranges;
  if (layout.pushConstantBytes)
    ranges.emplace_back(vk::ShaderStageFlagBits::eCompute, 0, layout.pushConstantBytes);
  pipelineLayout_ = vk::raii::PipelineLayout(device, vk::PipelineLayoutCreateInfo({}, rawLayouts, ranges));
  module_ = vk::raii::ShaderModule(device, vk::ShaderModuleCreateInfo({}, spirv.size_bytes(), spirv.data()));
  vk::PipelineShaderStageCreateInfo stage({}, vk::ShaderStageFlagBits::eCompute, *module_, "main");
  pipeline_ = vk::raii::Pipeline(device, nullptr, vk::ComputePipelineCreateInfo({}, stage, *pipelineLayout_));

  vk::DescriptorPoolSize poolSize(vk::DescriptorType::eStorageBuffer, std::max(totalBuffers, 1u));
  pool_ = vk::raii::DescriptorPool(
      device,
      vk::DescriptorPoolCreateInfo(vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet, 4, poolSize));
  vk::raii::DescriptorSets sets(device, vk::DescriptorSetAllocateInfo(*pool_, rawLayouts));
  for (auto& s : sets) sets_.push_back(std::move(s));
}

void ComputeKernel::bindBuffers(uint32_t set, std::initializer_list<const Buffer*> buffers) {
  bindBuffers(set, std::span<const Buffer* const>(buffers.begin(), buffers.size()));
}

void ComputeKernel::bindBuffers(uint32_t set, std::span<const Buffer* const> buffers) {
  IBLX_ASSERT(set < 4);
  if (buffers.size() != layout_.buffersPerSet[set])
    throw Error("kernel '" + name_ + "': set " + std::to_string(set) + " expects " +
                std::to_string(layout_.buffersPerSet[set]) + " buffers, got " +
                std::to_string(buffers.size()));
  std::vector<vk::DescriptorBufferInfo> infos;
  infos.reserve(buffers.size());
  for (const Buffer* b : buffers) infos.emplace_back(b->handle(), 0, VK_WHOLE_SIZE);
  std::vector<vk::WriteDescriptorSet> writes;
  for (uint32_t i = 0; i < infos.size(); ++i)
    writes.emplace_back(*sets_[set], i, 0, 1, vk::DescriptorType::eStorageBuffer, nullptr, &infos[i]);
  context_->device().updateDescriptorSets(writes, {});
}

void ComputeKernel::record(vk::CommandBuffer cmd, uint32_t groupsX, uint32_t groupsY,
                           const void* pushConstants, uint32_t pushBytes) const {
  IBLX_ASSERT(pushBytes == layout_.pushConstantBytes);
  cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_);
  std::vector<vk::DescriptorSet> raw;
  for (const auto& s : sets_) raw.push_back(*s);
  cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipelineLayout_, 0, raw, {});
  if (pushBytes)
    cmd.pushConstants(*pipelineLayout_, vk::ShaderStageFlagBits::eCompute, 0, pushBytes, pushConstants);
  cmd.dispatch(groupsX, groupsY, 1);
}

void recordShaderWriteBarrier(vk::CommandBuffer cmd, bool host) {
  vk::AccessFlags dstAccess = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite;
  vk::PipelineStageFlags dstStages = vk::PipelineStageFlagBits::eComputeShader;
  if (host) {
    dstAccess |= vk::AccessFlagBits::eHostRead;
    dstStages |= vk::PipelineStageFlagBits::eHost;
  }
  vk::MemoryBarrier barrier(vk::AccessFlagBits::eShaderWrite, dstAccess);
  cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, dstStages, {}, barrier, {}, {});
}

TimestampPair::TimestampPair(const VulkanContext& context) : context_(&context) {
  if (context.hasTimestamps())
    pool_ = vk::raii::QueryPool(context.device(), vk::QueryPoolCreateInfo({}, vk::QueryType::eTimestamp, 2));
}

void TimestampPair::begin(vk::CommandBuffer cmd) const {
  if (!context_->hasTimestamps()) return;
  cmd.resetQueryPool(*pool_, 0, 2);
  cmd.writeTimestamp(vk::PipelineStageFlagBits::eTopOfPipe, *pool_, 0);
}

void TimestampPair::end(vk::CommandBuffer cmd) const {
  if (!context_->hasTimestamps()) return;
  cmd.writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *pool_, 1);
}

double TimestampPair::seconds() const {
  if (!context_->hasTimestamps()) return 0.0;
  auto [result, values] =
      pool_.getResults<uint64_t>(0, 2, 2 * sizeof(uint64_t), sizeof(uint64_t),
                                 vk::QueryResultFlagBits::e64 | vk::QueryResultFlagBits::eWait);
  if (result != vk::Result::eSuccess || values[1] < values[0]) return 0.0;
  return double(values[1] - values[0]) * context_->timestampPeriodNs() * 1e-9;
}

}  // namespace iblx
