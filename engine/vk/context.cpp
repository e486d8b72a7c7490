// Instance creation (validation layers when asked and installed), device selection with reasons, compute
// queue.
#include "engine/vk/context.h"

#include "engine/core/environment.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace iblx {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
std::mutex gMessageMutex;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

int typeRank(vk::PhysicalDeviceType type) {
  switch (type) {
    case vk::PhysicalDeviceType::eDiscreteGpu:
      return 0;
    case vk::PhysicalDeviceType::eIntegratedGpu:
      return 1;
    case vk::PhysicalDeviceType::eVirtualGpu:
      return 2;
    case vk::PhysicalDeviceType::eCpu:
      return 3;
    default:
      return 4;
  }
}

std::string typeName(vk::PhysicalDeviceType type) {
  switch (type) {
    case vk::PhysicalDeviceType::eDiscreteGpu:
      return "discrete GPU";
    case vk::PhysicalDeviceType::eIntegratedGpu:
      return "integrated GPU";
    case vk::PhysicalDeviceType::eVirtualGpu:
      return "virtual GPU";
    case vk::PhysicalDeviceType::eCpu:
      return "CPU";
    default:
      return "other";
  }
}

// Why a device cannot run iblx, or empty if it can.
// surface: with a window, the family must also draw and present to it, and the device must have swapchains.
std::string rejectionReason(const vk::raii::PhysicalDevice& device, uint32_t* computeFamily,
                            vk::SurfaceKHR surface = {}) {
  const auto properties = device.getProperties();
  if (properties.apiVersion < VK_API_VERSION_1_2)
    return "supports only Vulkan " + std::to_string(VK_API_VERSION_MAJOR(properties.apiVersion)) + "." +
           std::to_string(VK_API_VERSION_MINOR(properties.apiVersion)) + ", iblx needs 1.2";
  const auto families = device.getQueueFamilyProperties();
  if (surface) {
    bool swapchain = false;
    for (const auto& e : device.enumerateDeviceExtensionProperties())
      swapchain = swapchain || std::string_view(e.extensionName) == VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    if (!swapchain) return "has no swapchain extension (cannot show a window)";
  }
  const vk::QueueFlags needed =
      surface ? vk::QueueFlagBits::eCompute | vk::QueueFlagBits::eGraphics : vk::QueueFlagBits::eCompute;
  for (uint32_t i = 0; i < families.size(); ++i) {
    if ((families[i].queueFlags & needed) != needed) continue;
    if (surface && !device.getSurfaceSupportKHR(i, surface)) continue;
    if (computeFamily) *computeFamily = i;
    return {};
  }
  return surface ? "has no queue that computes, draws and presents to the window" : "has no compute queue";
}

bool layerAvailable(const vk::raii::Context& context, const char* name) {
  for (const auto& layer : context.enumerateInstanceLayerProperties())
    if (std::string_view(layer.layerName) == name) return true;
  return false;
}

bool validationRequested(Validation v) {
  if (v == Validation::On) return true;
  if (v == Validation::Off) return false;
  if (const char* env = std::getenv("IBLX_VALIDATION")) return std::string_view(env) == "1";
#ifndef NDEBUG
  return true;
#else
  return false;
#endif
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                            VkDebugUtilsMessageTypeFlagsEXT,
                                                            const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                            void* user) {
  auto* self = static_cast<VulkanContext*>(user);
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    self->validationErrors_++;
    std::lock_guard lock(gMessageMutex);
    self->messages_.emplace_back(data->pMessage ? data->pMessage : "(no message)");
    std::fprintf(stderr, "iblx: Vulkan validation error: %s\n", data->pMessage ? data->pMessage : "");
  }
  return VK_FALSE;
}

void VulkanContext::setObjectName(vk::ObjectType type, std::uint64_t handle, const std::string& name) const {
  device_.setDebugUtilsObjectNameEXT(vk::DebugUtilsObjectNameInfoEXT(type, handle, name.c_str()));
}

std::vector<std::string> VulkanContext::validationMessages() const {
  std::lock_guard lock(gMessageMutex);
  return messages_;
}

std::vector<DeviceDescription> VulkanContext::describeDevices() {
  vk::raii::Context context;
  vk::ApplicationInfo app("iblx", 1, "iblx", 1, VK_API_VERSION_1_2);
  vk::raii::Instance instance(context, vk::InstanceCreateInfo({}, &app));
  std::vector<DeviceDescription> result;
  uint32_t index = 0;
  for (const auto& device : vk::raii::PhysicalDevices(instance)) {
    const auto properties = device.getProperties();
    result.push_back({index++, properties.deviceName.data(), typeName(properties.deviceType),
                      rejectionReason(device, nullptr)});
  }
  return result;
}

VulkanContext::VulkanContext(const ContextOptions& options) {
  std::vector<const char*> layers, extensions;
  if (validationRequested(options.validation)) {
    if (layerAvailable(context_, kValidationLayer)) {
      layers.push_back(kValidationLayer);
      extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
      validationEnabled_ = true;
    } else if (options.validation == Validation::On) {
      throw Error("Vulkan validation was requested but " + std::string(kValidationLayer) +
                  " is not installed (Debian package vulkan-validationlayers)");
    }
  }
  if (options.presentation)
    for (const std::string& e : options.presentation->instanceExtensions) extensions.push_back(e.c_str());
  vk::ApplicationInfo app("iblx", 1, "iblx", 1, VK_API_VERSION_1_2);
  instance_ = vk::raii::Instance(context_, vk::InstanceCreateInfo({}, &app, layers, extensions));
  if (options.presentation)
    surface_ = vk::raii::SurfaceKHR(instance_, options.presentation->createSurface(*instance_));
  if (validationEnabled_) {
    using S = vk::DebugUtilsMessageSeverityFlagBitsEXT;
    using T = vk::DebugUtilsMessageTypeFlagBitsEXT;
    messenger_ = vk::raii::DebugUtilsMessengerEXT(
        instance_, vk::DebugUtilsMessengerCreateInfoEXT({}, S::eError | S::eWarning,
                                                        T::eGeneral | T::eValidation | T::ePerformance,
                                                        &VulkanContext::debugCallback, this));
  }

  // Choose the device: explicit selector, else the best type.
  std::string selector = options.deviceSelector;
  if (selector.empty())
    if (const char* env = std::getenv("IBLX_DEVICE")) selector = env;
  vk::raii::PhysicalDevices devices(instance_);
  std::string report;
  int best = -1;
  uint32_t bestFamily = 0;
  for (uint32_t i = 0; i < devices.size(); ++i) {
    const auto properties = devices[i].getProperties();
    uint32_t family = 0;
    std::string reason = rejectionReason(devices[i], &family, *surface_);
    const std::string name = properties.deviceName.data();
    if (reason.empty() && !selector.empty()) {
      const bool isIndex = std::all_of(selector.begin(), selector.end(), ::isdigit);
      // An index of more digits than any device count (it once overflowed std::stoul) matches nothing.
      const bool match = isIndex ? selector.size() <= 9 && std::stoul(selector) == i
                                 : lower(name).find(lower(selector)) != std::string::npos;
      if (!match) reason = "does not match the device selector '" + selector + "'";
    }
    // One line for every device, so that the error stays one line (`iblx devices` lists them one per line).
    report += std::string(report.empty() ? " " : "; ") + "[" + std::to_string(i) + "] " + name + " (" +
              typeName(properties.deviceType) + "): " + (reason.empty() ? "usable" : reason);
    if (!reason.empty()) continue;
    if (best < 0 || typeRank(properties.deviceType) < typeRank(devices[best].getProperties().deviceType)) {
      best = int(i);
      bestFamily = family;
    }
  }
  if (best < 0) {
    throw Error(devices.empty()
                    ? "no Vulkan device found; install a driver (for CPU rendering: the Debian package "
                      "mesa-vulkan-drivers, which provides lavapipe)"
                    : "no usable Vulkan device:" + report);
  }
  physicalDevice_ = std::move(devices[best]);
  queueFamily_ = bestFamily;
  const auto properties = physicalDevice_.getProperties();
  deviceName_ = properties.deviceName.data();
  limits_ = properties.limits;
  // IBLX_MAX_BUFFER_MIB: behave as a device whose largest storage buffer holds that many MiB, so what a
  // smaller device does (a table split or refused, a method skipped) can be seen and tested on any device.
  if (const char* cap = std::getenv("IBLX_MAX_BUFFER_MIB")) {
    char* end = nullptr;
    const unsigned long mib = std::strtoul(cap, &end, 10);
    if (end == cap || *end != '\0' || mib == 0 || mib > 4095)
      throw Error("IBLX_MAX_BUFFER_MIB='" + std::string(cap) + "': use a whole number of MiB from 1 to 4095");
    limits_.maxStorageBufferRange = std::min(limits_.maxStorageBufferRange, uint32_t(mib) << 20);
  }
  timestampPeriodNs_ = properties.limits.timestampPeriod;
  hasTimestamps_ = physicalDevice_.getQueueFamilyProperties()[queueFamily_].timestampValidBits > 0 &&
                   properties.limits.timestampComputeAndGraphics;

  const float priority = 1.0f;
  vk::DeviceQueueCreateInfo queueInfo({}, queueFamily_, 1, &priority);
  vk::PhysicalDeviceFeatures features;
  std::vector<const char*> deviceExtensions;
  if (options.presentation) deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  vk::DeviceCreateInfo deviceInfo({}, queueInfo, {}, deviceExtensions, &features);
  device_ = vk::raii::Device(physicalDevice_, deviceInfo);
  queue_ = vk::raii::Queue(device_, queueFamily_, 0);
  commandPool_ = vk::raii::CommandPool(
      device_, vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer, queueFamily_));
  nameObject(*device_, "iblx device");
  nameObject(*queue_, "iblx queue");
  nameObject(*commandPool_, "shared command pool");
}

double gpuTimeoutSeconds() {
  return environmentNumber("IBLX_GPU_TIMEOUT_S", 600.0, 1e7);
}

void VulkanContext::submitAndWait(const std::function<void(vk::CommandBuffer)>& record) const {
  // The pool and the queue are shared by every thread (the viewer builds renderers and ground truths in the
  // background): both are locked for recording and submission, but not while the work runs.
  std::unique_lock lock(queueMutex_);
  std::optional<vk::raii::CommandBuffers> buffers(
      std::in_place, device_,
      vk::CommandBufferAllocateInfo(*commandPool_, vk::CommandBufferLevel::ePrimary, 1));
  vk::raii::CommandBuffer& cmd = (*buffers)[0];
  nameObject(*cmd, "one-time commands");
  cmd.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  record(*cmd);
  cmd.end();
  vk::raii::Fence fence(device_, vk::FenceCreateInfo());
  nameObject(*fence, "one-time commands done");
  vk::CommandBuffer handle = *cmd;
  queue_.submit(vk::SubmitInfo({}, {}, handle), *fence);
  lock.unlock();
  // A kernel that never ends (a .brdf whose BRDF() loops forever) would block here for good. Past the
  // timeout the device is still running it and no resource it uses can be freed safely, so the process ends
  // with one clear line instead of hanging.
  const double timeoutSeconds = gpuTimeoutSeconds();
  vk::Result waited = vk::Result::eSuccess;
  try {
    waited = device_.waitForFences(*fence, VK_TRUE, std::uint64_t(timeoutSeconds * 1e9));
  } catch (...) {
    lock.lock();  // the command buffer goes back to the shared pool under its lock, even on device loss
    buffers.reset();
    throw;
  }
  if (waited == vk::Result::eTimeout) {
    std::fprintf(stderr,
                 "iblx: error: the GPU did not finish a dispatch within %.3g s (IBLX_GPU_TIMEOUT_S sets the "
                 "limit): a .brdf whose BRDF() never returns, or more work per dispatch than this device "
                 "does in that time\n",
                 timeoutSeconds);
    std::fflush(stderr);
    std::_Exit(4);
  }
  lock.lock();
  buffers.reset();  // freeing touches the pool
}

DeviceTableLimit deviceTableLimit(const std::string& selector) {
  return DeviceTableLimit([selector] {
    return std::uint64_t(VulkanContext({selector, Validation::Off}).limits().maxStorageBufferRange);
  });
}

}  // namespace iblx
