// The viewer's window: a GLFW window, its Vulkan swapchain and render pass, and Dear ImGui drawn on top of an
// image uploaded from the CPU each frame. Knows nothing about rendering methods (tools/viewer/viewer.cpp
// does).
//
//   ViewerWindow window("iblx", 800, 600, {.device = "llvmpipe"});
//   while (window.beginFrame()) { ImGui::Text("..."); window.endFrame(bgra, w, h, /*readback=*/false); }
#pragma once

#include "engine/vk/buffer.h"
#include "engine/vk/context.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

struct GLFWwindow;

namespace iblx::viewer {

inline constexpr std::uint8_t kWindowGrey = 24;  // the window's own background (around and behind the image)

// The image the viewer reads back from the swapchain (F12, the menu, --screenshot): what was on screen.
struct Screenshot {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 3 bytes per pixel, top row first
};

class ViewerWindow {
 public:
  // Opens the window and the Vulkan context on it. Throws iblx::Error when there is no display or no device
  // that can present to it.
  ViewerWindow(const std::string& title, int width, int height, const ContextOptions& contextOptions);
  ~ViewerWindow();
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  const VulkanContext& context() const { return *context_; }
  GLFWwindow* handle() const { return window_; }

  // Polls events and starts an ImGui frame; false once the window was asked to close.
  bool beginFrame();
  // Draws `canvas` (BGRA8, canvasWidth x canvasHeight, placed at the top left; the rest is the clear colour)
  // with the ImGui frame over it and presents. With readback, the presented image is also returned.
  std::optional<Screenshot> endFrame(std::span<const std::uint8_t> canvas, int canvasWidth, int canvasHeight,
                                     bool readback);
  // The drawable size in pixels.
  int width() const { return int(extent_.width); }
  int height() const { return int(extent_.height); }

 private:
  void createSwapchain();
  void release();  // everything, in dependency order; idempotent

  GLFWwindow* window_ = nullptr;
  std::unique_ptr<VulkanContext> context_;
  vk::Format format_ = vk::Format::eUndefined;
  vk::Extent2D extent_;
  vk::raii::SwapchainKHR swapchain_ = nullptr;
  std::vector<vk::Image> images_;
  std::vector<vk::raii::ImageView> views_;
  vk::raii::RenderPass renderPass_ = nullptr;
  std::vector<vk::raii::Framebuffer> framebuffers_;
  vk::raii::DescriptorPool imguiPool_ = nullptr;
  vk::raii::CommandPool commandPool_ =
      nullptr;  // the window's own: the context's is shared with other threads
  vk::raii::CommandBuffers commands_ = nullptr;
  vk::raii::Semaphore imageAvailable_ = nullptr;
  std::vector<vk::raii::Semaphore> renderFinished_;  // one per swapchain image
  vk::raii::Fence frameDone_ = nullptr;
  Buffer upload_, readback_;
  bool imguiReady_ = false;
  bool needsRecreate_ = false;
  int builtForWidth_ = 0, builtForHeight_ = 0;  // the framebuffer size the swapchain was made for
};

}  // namespace iblx::viewer
