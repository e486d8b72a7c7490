// Buffer allocation in host-visible memory and the plain-copy upload/read-back.
#include "engine/vk/buffer.h"

#include "engine/core/error.h"

namespace iblx {
namespace {

uint32_t chooseMemoryType(const vk::raii::PhysicalDevice& physical, uint32_t typeBits,
                          const std::string& what) {
  const auto memory = physical.getMemoryProperties();
  using F = vk::MemoryPropertyFlagBits;
  const vk::MemoryPropertyFlags wanted[] = {F::eDeviceLocal | F::eHostVisible | F::eHostCoherent,
                                            F::eHostVisible | F::eHostCoherent};
  for (auto flags : wanted)
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
      if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & flags) == flags) return i;
  throw Error("no host-visible coherent memory for buffer '" + what + "' on this Vulkan device");
}

}  // namespace

Buffer::Buffer(const VulkanContext& context, vk::DeviceSize size, std::string name)
    : size_(std::max<vk::DeviceSize>(size, 16)), name_(std::move(name)) {
  if (size_ > context.limits().maxStorageBufferRange)
    throw DeviceLimitError("buffer '" + name_ + "' needs " + std::to_string(size_ >> 20) +
                           " MiB, more than this device's " + "largest storage buffer (" +
                           std::to_string(context.limits().maxStorageBufferRange >> 20) +
                           " MiB); use a smaller environment map or image");
  using U = vk::BufferUsageFlagBits;
  buffer_ = vk::raii::Buffer(
      context.device(),
      vk::BufferCreateInfo({}, size_,
                           U::eStorageBuffer | U::eUniformTexelBuffer | U::eTransferSrc | U::eTransferDst));
  const auto requirements = buffer_.getMemoryRequirements();
  try {
    memory_ = vk::raii::DeviceMemory(
        context.device(),
        vk::MemoryAllocateInfo(requirements.size, chooseMemoryType(context.physicalDevice(),
                                                                   requirements.memoryTypeBits, name_)));
  } catch (const vk::SystemError& e) {
    throw Error("cannot allocate " + std::to_string(size_ >> 20) + " MiB for buffer '" + name_ +
                "': " + e.what());
  }
  context.nameObject(*buffer_, name_);
  context.nameObject(*memory_, name_ + " memory");
  buffer_.bindMemory(*memory_, 0);
  mapped_ = memory_.mapMemory(0, VK_WHOLE_SIZE);
  std::memset(mapped_, 0, size_);  // padding of small or empty tables reads as 0, never as garbage
}

void Buffer::write(const void* data, vk::DeviceSize bytes, vk::DeviceSize offset) {
  IBLX_ASSERT(offset + bytes <= size_);
  if (bytes) std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
}

void Buffer::read(void* data, vk::DeviceSize bytes, vk::DeviceSize offset) const {
  IBLX_ASSERT(offset + bytes <= size_);
  if (bytes) std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
}

void Buffer::setTableElementWords(uint32_t words) {
  if (words != 1 && words != 2 && words != 4)
    throw Error("buffer '" + name_ + "': a table has 1, 2 or 4 words per element, not " +
                std::to_string(words));
  tableElementWords_ = words;
}

void Buffer::fill(uint32_t value) {
  auto* p = static_cast<uint32_t*>(mapped_);
  std::fill(p, p + size_ / 4, value);
}

}  // namespace iblx
