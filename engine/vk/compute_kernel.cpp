// Pipeline, descriptor-set and timestamp plumbing for compute kernels.
#include "engine/vk/compute_kernel.h"

#include "engine/core/error.h"

namespace iblx {

ComputeKernel::ComputeKernel(const VulkanContext& context, std::span<const uint32_t> spirv,
                             const KernelLayout& layout, std::string name)
    : context_(&context), layout_(layout), name_(std::move(name)) {
  const auto& device = context.device();
  uint32_t storageCount = 0, tableCount = 0;
  for (uint32_t set = 0; set < 4; ++set) {
    std::vector<vk::DescriptorSetLayoutBinding> bindings;
    for (uint32_t b = 0; b < layout.buffersPerSet[set]; ++b) {
      const vk::DescriptorType type = descriptorType(set, b);
      ++(type == vk::DescriptorType::eStorageBuffer ? storageCount : tableCount);
      bindings.emplace_back(b, type, 1, vk::ShaderStageFlagBits::eCompute);
    }
    setLayouts_.emplace_back(device, vk::DescriptorSetLayoutCreateInfo({}, bindings));
    context.nameObject(*setLayouts_.back(), name_ + " set " + std::to_string(set) + " layout");
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
  context.nameObject(*pipelineLayout_, name_ + " pipeline layout");
  context.nameObject(*module_, name_ + " shader");
  context.nameObject(*pipeline_, name_);

  const std::array<vk::DescriptorPoolSize, 2> poolSizes{
      vk::DescriptorPoolSize(vk::DescriptorType::eStorageBuffer, std::max(storageCount, 1u)),
      vk::DescriptorPoolSize(vk::DescriptorType::eUniformTexelBuffer, std::max(tableCount, 1u))};
  pool_ = vk::raii::DescriptorPool(
      device,
      vk::DescriptorPoolCreateInfo(vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet, 4, poolSizes));
  vk::raii::DescriptorSets sets(device, vk::DescriptorSetAllocateInfo(*pool_, rawLayouts));
  context.nameObject(*pool_, name_ + " descriptor pool");
  for (auto& s : sets) {
    context.nameObject(*s, name_ + " set " + std::to_string(sets_.size()));
    sets_.push_back(std::move(s));
  }
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
  const uint32_t count = uint32_t(buffers.size());
  std::vector<vk::DescriptorBufferInfo> infos(count);
  std::vector<vk::raii::BufferView> views;
  std::vector<vk::BufferView> rawViews(count);
  std::vector<vk::WriteDescriptorSet> writes;
  for (uint32_t i = 0; i < count; ++i) {
    const Buffer& b = *buffers[i];
    const vk::DescriptorType type = descriptorType(set, i);
    if (type == vk::DescriptorType::eStorageBuffer) {
      infos[i] = vk::DescriptorBufferInfo(b.handle(), 0, VK_WHOLE_SIZE);
      writes.emplace_back(*sets_[set], i, 0, 1, type, nullptr, &infos[i]);
      continue;
    }
    const uint32_t words = b.tableElementWords();
    const vk::DeviceSize elements = b.size() / (words * sizeof(uint32_t));
    if (elements > context_->limits().maxTexelBufferElements)
      throw DeviceLimitError("buffer '" + b.name() + "' holds " + std::to_string(elements) +
                             " elements, more than this device's largest texel buffer (" +
                             std::to_string(context_->limits().maxTexelBufferElements) +
                             "); use a smaller environment map or table");
    const vk::Format format = words == 4   ? vk::Format::eR32G32B32A32Uint
                              : words == 2 ? vk::Format::eR32G32Uint
                                           : vk::Format::eR32Uint;
    views.emplace_back(context_->device(), vk::BufferViewCreateInfo({}, b.handle(), format, 0,
                                                                    elements * words * sizeof(uint32_t)));
    context_->nameObject(*views.back(), b.name() + " view");
    rawViews[i] = *views.back();
    writes.emplace_back(*sets_[set], i, 0, 1, type, nullptr, nullptr, &rawViews[i]);
  }
  context_->device().updateDescriptorSets(writes, {});
  tableViews_[set] = std::move(views);  // the previous views are no longer referenced by the set
}

vk::DescriptorType ComputeKernel::descriptorType(uint32_t set, uint32_t binding) const {
  return binding < 32 && (layout_.tableBindings[set] >> binding & 1u)
             ? vk::DescriptorType::eUniformTexelBuffer
             : vk::DescriptorType::eStorageBuffer;
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
  context.nameObject(*pool_, "timestamps");
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
