// A buffer that owns its memory, bound either as a storage buffer or as a read-only table (a uniform texel
// buffer, KernelLayout::tableBindings). Host-visible memory is used so that uploads and read-backs are plain
// copies; device-local host-visible memory is preferred when the device has it (integrated GPUs, lavapipe,
// ReBAR).
#pragma once

#include "engine/vk/context.h"

#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace iblx {

class Buffer {
 public:
  Buffer() = default;
  // size 0 is allowed and becomes a 16-byte buffer, so optional tables can always be bound.
  Buffer(const VulkanContext& context, vk::DeviceSize size, std::string name);

  // tableElementWords: how a kernel that binds it as a table views it (1, 2 or 4 32-bit words per element).
  template <typename T>
  static Buffer fromData(const VulkanContext& context, std::span<const T> data, std::string name,
                         uint32_t tableElementWords = 1) {
    Buffer buffer(context, data.size_bytes(), std::move(name));
    buffer.write(data.data(), data.size_bytes());
    buffer.setTableElementWords(tableElementWords);
    return buffer;
  }
  template <typename T>
  static Buffer fromData(const VulkanContext& context, const std::vector<T>& data, std::string name,
                         uint32_t tableElementWords = 1) {
    return fromData(context, std::span<const T>(data), std::move(name), tableElementWords);
  }

  void write(const void* data, vk::DeviceSize bytes, vk::DeviceSize offset = 0);
  void read(void* data, vk::DeviceSize bytes, vk::DeviceSize offset = 0) const;
  template <typename T>
  std::vector<T> readAll() const {
    std::vector<T> out(size_ / sizeof(T));
    read(out.data(), out.size() * sizeof(T));
    return out;
  }
  void fill(uint32_t value);

  void setTableElementWords(uint32_t words);  // 1, 2 or 4
  uint32_t tableElementWords() const { return tableElementWords_; }

  vk::Buffer handle() const { return *buffer_; }
  vk::DeviceSize size() const { return size_; }
  const std::string& name() const { return name_; }

 private:
  // Members are destroyed in reverse: mapping, buffer, then memory.
  vk::raii::DeviceMemory memory_ = nullptr;
  vk::raii::Buffer buffer_ = nullptr;
  void* mapped_ = nullptr;
  vk::DeviceSize size_ = 0;
  std::string name_;
  uint32_t tableElementWords_ = 1;
};

}  // namespace iblx
