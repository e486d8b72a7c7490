// The Vulkan instance, the chosen device and its compute queue, headless, with vk::raii ownership.
//
//   VulkanContext ctx({.deviceSelector = "llvmpipe"});      // or IBLX_DEVICE=... in the environment
//   ctx.submitAndWait([&](vk::CommandBuffer cmd) { ... });
#pragma once

#include <vulkan/vulkan_raii.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace iblx {

class DeviceTableLimit;  // engine/core/file_io.h

enum class Validation { Auto, On, Off };  // Auto: on in debug builds or when IBLX_VALIDATION=1, if installed

// What a window needs from the context (the viewer): the instance extensions of the window system, a callback
// that creates the window's surface once the instance exists, and then a queue family that can also draw and
// present to it, with VK_KHR_swapchain enabled. Headless contexts leave it empty.
struct PresentationRequest {
  std::vector<std::string> instanceExtensions;
  std::function<VkSurfaceKHR(VkInstance)> createSurface;  // throws on failure; the context owns the result
};

struct ContextOptions {
  // Empty: the IBLX_DEVICE environment variable, else the best device (discrete, integrated, virtual, CPU).
  // Otherwise a device index as listed by `iblx devices` or a case-insensitive substring of its name.
  std::string deviceSelector;
  Validation validation = Validation::Auto;
  std::optional<PresentationRequest> presentation;
};

struct DeviceDescription {
  uint32_t index = 0;
  std::string name;
  std::string type;
  std::string rejectedBecause;  // empty when usable
};

class VulkanContext {
 public:
  explicit VulkanContext(const ContextOptions& options = {});
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  const vk::raii::Instance& instance() const { return instance_; }
  const vk::raii::Device& device() const { return device_; }
  // The window's surface (null without a PresentationRequest); the queue can present to it.
  const vk::raii::SurfaceKHR& surface() const { return surface_; }
  const vk::raii::PhysicalDevice& physicalDevice() const { return physicalDevice_; }
  const vk::raii::Queue& queue() const { return queue_; }
  const vk::raii::CommandPool& commandPool() const { return commandPool_; }
  uint32_t queueFamily() const { return queueFamily_; }
  double timestampPeriodNs() const { return timestampPeriodNs_; }
  bool hasTimestamps() const { return hasTimestamps_; }
  const std::string& deviceName() const { return deviceName_; }
  bool validationEnabled() const { return validationEnabled_; }
  const vk::PhysicalDeviceLimits& limits() const { return limits_; }

  // Gives a Vulkan object a name that validation messages quote (VK_EXT_debug_utils), when the validation
  // layers are on; otherwise does nothing. Every object iblx creates is named after its role.
  template <typename Handle>
  void nameObject(const Handle& handle, const std::string& name) const {
    if (!validationEnabled_ || !handle) return;
    using CType = typename Handle::CType;
    setObjectName(Handle::objectType,
                  std::uint64_t(reinterpret_cast<std::uintptr_t>(static_cast<CType>(handle))), name);
  }

  // Messages of severity error reported by the validation layers since creation.
  uint32_t validationErrorCount() const { return validationErrors_.load(); }
  std::vector<std::string> validationMessages() const;

  // Records commands into a one-time command buffer, submits and waits for completion. Thread-safe.
  // A submission still running after gpuTimeoutSeconds() ends the process with exit status 4 and a message.
  void submitAndWait(const std::function<void(vk::CommandBuffer)>& record) const;

  // Held by anyone else who submits to or presents on queue() (the viewer's window), for Vulkan's external
  // synchronisation of the queue.
  std::unique_lock<std::mutex> lockQueue() const { return std::unique_lock(queueMutex_); }

  // Every physical device with the reason it would be rejected (for `iblx devices` and error messages).
  static std::vector<DeviceDescription> describeDevices();

 private:
  void setObjectName(vk::ObjectType type, std::uint64_t handle, const std::string& name) const;
  static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                      VkDebugUtilsMessageTypeFlagsEXT types,
                                                      const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                      void* user);

  // Declaration order is destruction order in reverse: the device goes before the instance.
  vk::raii::Context context_;
  vk::raii::Instance instance_ = nullptr;
  vk::raii::DebugUtilsMessengerEXT messenger_ = nullptr;
  vk::raii::SurfaceKHR surface_ = nullptr;
  vk::raii::PhysicalDevice physicalDevice_ = nullptr;
  vk::raii::Device device_ = nullptr;
  vk::raii::Queue queue_ = nullptr;
  vk::raii::CommandPool commandPool_ = nullptr;
  uint32_t queueFamily_ = 0;
  double timestampPeriodNs_ = 1.0;
  bool hasTimestamps_ = false;
  bool validationEnabled_ = false;
  std::string deviceName_;
  vk::PhysicalDeviceLimits limits_;
  std::atomic<uint32_t> validationErrors_{0};
  mutable std::vector<std::string> messages_;
  mutable std::mutex queueMutex_;  // also guards commandPool_
};

// How long one submission may run: 600 s, or $IBLX_GPU_TIMEOUT_S.
double gpuTimeoutSeconds();

// For the files a command reads before it starts its device (engine/core/file_io.h, DeviceTableLimit): a
// table above what every Vulkan device holds is checked against the largest storage buffer of the device
// `selector` names (ContextOptions::deviceSelector); that device is started to learn it, only for such a
// table.
DeviceTableLimit deviceTableLimit(const std::string& selector);

}  // namespace iblx
