// The viewer's window (window.h): GLFW, the swapchain, one render pass that loads the uploaded canvas and
// draws Dear ImGui over it, and an optional read-back of the presented image.
#include "tools/viewer/window.h"

#include "engine/core/error.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace iblx::viewer {

namespace {

void checkImguiVk(VkResult result) {
  if (result < 0)
    throw Error("Dear ImGui's Vulkan backend failed (VkResult " + std::to_string(int(result)) + ")");
}

std::string glfwErrorText() {
  const char* text = nullptr;
  glfwGetError(&text);
  return text ? text : "unknown GLFW error";
}

}  // namespace

ViewerWindow::ViewerWindow(const std::string& title, int width, int height,
                           const ContextOptions& contextOptions) {
  if (!glfwInit())
    throw Error("cannot open a window: " + glfwErrorText() +
                " (no display? run under a desktop session or `xvfb-run -a iblx view ...`)");
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw Error("cannot open a window: GLFW found no Vulkan loader");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string why = glfwErrorText();
    glfwTerminate();
    throw Error("cannot open a window: " + why);
  }
  try {
    ContextOptions options = contextOptions;
    PresentationRequest presentation;
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    for (uint32_t i = 0; i < count; ++i) presentation.instanceExtensions.emplace_back(names[i]);
    presentation.createSurface = [this](VkInstance instance) {
      VkSurfaceKHR surface = VK_NULL_HANDLE;
      if (glfwCreateWindowSurface(instance, window_, nullptr, &surface) != VK_SUCCESS)
        throw Error("cannot create a Vulkan surface for the window: " + glfwErrorText());
      return surface;
    };
    options.presentation = std::move(presentation);
    context_ = std::make_unique<VulkanContext>(options);

    const auto& device = context_->device();
    commandPool_ = vk::raii::CommandPool(
        device, vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer,
                                          context_->queueFamily()));
    commands_ = vk::raii::CommandBuffers(
        device, vk::CommandBufferAllocateInfo(*commandPool_, vk::CommandBufferLevel::ePrimary, 1));
    imageAvailable_ = vk::raii::Semaphore(device, vk::SemaphoreCreateInfo());
    frameDone_ = vk::raii::Fence(device, vk::FenceCreateInfo(vk::FenceCreateFlagBits::eSignaled));
    context_->nameObject(*commandPool_, "viewer command pool");
    context_->nameObject(*commands_[0], "viewer frame commands");
    context_->nameObject(*imageAvailable_, "viewer image available");
    context_->nameObject(*frameDone_, "viewer frame done");
    createSwapchain();

    // Dear ImGui's own descriptor sets (its font texture): a small pool, as in its Vulkan example.
    const vk::DescriptorPoolSize poolSize(vk::DescriptorType::eCombinedImageSampler, 16);
    imguiPool_ = vk::raii::DescriptorPool(
        device,
        vk::DescriptorPoolCreateInfo(vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet, 16, poolSize));
    context_->nameObject(*imguiPool_, "Dear ImGui descriptor pool");
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForVulkan(window_, true);
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = *context_->instance();
    info.PhysicalDevice = *context_->physicalDevice();
    info.Device = *device;
    info.QueueFamily = context_->queueFamily();
    info.Queue = *context_->queue();
    info.DescriptorPool = *imguiPool_;
    info.MinImageCount = 2;
    info.ImageCount = uint32_t(images_.size());
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkImguiVk;
    ImGui_ImplVulkan_Init(&info, *renderPass_);
    imguiReady_ = true;
    context_->submitAndWait([](vk::CommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
  } catch (...) {
    release();  // members are destroyed again by the unwinding, harmlessly: release() left them empty
    throw;
  }
}

ViewerWindow::~ViewerWindow() {
  release();
}

void ViewerWindow::release() {
  if (context_) {
    const auto lock = context_->lockQueue();
    context_->device().waitIdle();
  }
  if (imguiReady_) {
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    imguiReady_ = false;
  }
  // Vulkan objects before the context, the context (and its surface) before the window.
  upload_ = Buffer(), readback_ = Buffer();
  frameDone_ = nullptr, imageAvailable_ = nullptr;
  renderFinished_.clear();
  commands_ = nullptr, commandPool_ = nullptr;
  imguiPool_ = nullptr;
  framebuffers_.clear(), views_.clear();
  renderPass_ = nullptr, swapchain_ = nullptr;
  context_.reset();
  if (window_) glfwDestroyWindow(window_), window_ = nullptr, glfwTerminate();
}

void ViewerWindow::createSwapchain() {
  const auto& device = context_->device();
  const auto& physical = context_->physicalDevice();
  const vk::SurfaceKHR surface = *context_->surface();
  // Only this window's frame uses the images and framebuffers; waiting for the whole device would also wait
  // for a ground truth computing in the background.
  (void)device.waitForFences(*frameDone_, VK_TRUE, std::numeric_limits<uint64_t>::max());
  framebuffers_.clear(), views_.clear();

  const auto caps = physical.getSurfaceCapabilitiesKHR(surface);
  int fbWidth = 0, fbHeight = 0;
  glfwGetFramebufferSize(window_, &fbWidth, &fbHeight);
  builtForWidth_ = fbWidth, builtForHeight_ = fbHeight;
  extent_ = caps.currentExtent.width != std::numeric_limits<uint32_t>::max()
                ? caps.currentExtent
                : vk::Extent2D(
                      std::clamp(uint32_t(fbWidth), caps.minImageExtent.width, caps.maxImageExtent.width),
                      std::clamp(uint32_t(fbHeight), caps.minImageExtent.height, caps.maxImageExtent.height));
  // The canvas and ImGui's colours are already display-encoded bytes: a UNORM format shows them as they are.
  const auto formats = physical.getSurfaceFormatsKHR(surface);
  vk::SurfaceFormatKHR chosen = formats.front();
  for (const auto& f : formats)
    if (f.format == vk::Format::eB8G8R8A8Unorm && f.colorSpace == vk::ColorSpaceKHR::eSrgbNonlinear)
      chosen = f;
  if (chosen.format != vk::Format::eB8G8R8A8Unorm)
    throw Error("the window system offers no B8G8R8A8_UNORM swapchain format, which the viewer needs");
  format_ = chosen.format;
  using U = vk::ImageUsageFlagBits;
  const vk::ImageUsageFlags usage = U::eColorAttachment | U::eTransferDst | U::eTransferSrc;
  if ((caps.supportedUsageFlags & usage) != usage)
    throw Error("the window's swapchain images cannot be copied to and from, which the viewer needs");
  uint32_t imageCount = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount) imageCount = std::min(imageCount, caps.maxImageCount);
  vk::SwapchainCreateInfoKHR info({}, surface, imageCount, format_, chosen.colorSpace, extent_, 1, usage,
                                  vk::SharingMode::eExclusive, {}, caps.currentTransform,
                                  vk::CompositeAlphaFlagBitsKHR::eOpaque, vk::PresentModeKHR::eFifo, VK_TRUE,
                                  *swapchain_);
  swapchain_ = vk::raii::SwapchainKHR(device, info);
  context_->nameObject(*swapchain_, "viewer swapchain");
  images_ = swapchain_.getImages();

  if (!*renderPass_) {
    // The canvas is copied in first, so the pass loads it (TRANSFER_DST) and ImGui draws over it.
    const vk::AttachmentDescription color(
        {}, format_, vk::SampleCountFlagBits::e1, vk::AttachmentLoadOp::eLoad, vk::AttachmentStoreOp::eStore,
        vk::AttachmentLoadOp::eDontCare, vk::AttachmentStoreOp::eDontCare,
        vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::ePresentSrcKHR);
    const vk::AttachmentReference ref(0, vk::ImageLayout::eColorAttachmentOptimal);
    const vk::SubpassDescription subpass({}, vk::PipelineBindPoint::eGraphics, {}, ref);
    using S = vk::PipelineStageFlagBits;
    using A = vk::AccessFlagBits;
    const vk::SubpassDependency dependency(VK_SUBPASS_EXTERNAL, 0, S::eTransfer, S::eColorAttachmentOutput,
                                           A::eTransferWrite,
                                           A::eColorAttachmentRead | A::eColorAttachmentWrite);
    renderPass_ = vk::raii::RenderPass(device, vk::RenderPassCreateInfo({}, color, subpass, dependency));
    context_->nameObject(*renderPass_, "viewer render pass");
  }
  renderFinished_.clear();
  for (vk::Image image : images_) {
    views_.emplace_back(device, vk::ImageViewCreateInfo({}, image, vk::ImageViewType::e2D, format_, {},
                                                        {vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1}));
    framebuffers_.emplace_back(device, vk::FramebufferCreateInfo({}, *renderPass_, *views_.back(),
                                                                 extent_.width, extent_.height, 1));
    renderFinished_.emplace_back(device, vk::SemaphoreCreateInfo());
    const std::string index = std::to_string(views_.size() - 1);
    context_->nameObject(image, "swapchain image " + index);
    context_->nameObject(*views_.back(), "swapchain image view " + index);
    context_->nameObject(*framebuffers_.back(), "viewer framebuffer " + index);
    context_->nameObject(*renderFinished_.back(), "viewer render finished " + index);
  }
  const vk::DeviceSize bytes = vk::DeviceSize(extent_.width) * extent_.height * 4;
  upload_ = Buffer(*context_, bytes, "viewer canvas");
  readback_ = Buffer(*context_, bytes, "viewer screenshot");
  if (imguiReady_) ImGui_ImplVulkan_SetMinImageCount(2);
  needsRecreate_ = false;
}

bool ViewerWindow::beginFrame() {
  glfwPollEvents();
  if (glfwWindowShouldClose(window_)) return false;
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  while (w == 0 || h == 0) {  // minimised: nothing to draw into
    glfwWaitEvents();
    if (glfwWindowShouldClose(window_)) return false;
    glfwGetFramebufferSize(window_, &w, &h);
  }
  // Compared with the framebuffer size of the last rebuild, not with the extent: the surface may clamp it.
  if (needsRecreate_ || w != builtForWidth_ || h != builtForHeight_) createSwapchain();
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  return true;
}

std::optional<Screenshot> ViewerWindow::endFrame(std::span<const std::uint8_t> canvas, int canvasWidth,
                                                 int canvasHeight, bool readback) {
  ImGui::Render();
  const auto& device = context_->device();
  (void)device.waitForFences(*frameDone_, VK_TRUE, std::numeric_limits<uint64_t>::max());

  uint32_t index = 0;
  try {
    const auto [result, i] =
        swapchain_.acquireNextImage(std::numeric_limits<uint64_t>::max(), *imageAvailable_);
    if (result == vk::Result::eSuboptimalKHR) needsRecreate_ = true;
    index = i;
  } catch (const vk::OutOfDateKHRError&) {
    needsRecreate_ = true;
    ImGui::EndFrame();
    return std::nullopt;
  }
  device.resetFences(*frameDone_);

  // The canvas: dark grey, with the render at the top left (clipped to the window).
  const int width = int(extent_.width), height = int(extent_.height);
  std::vector<std::uint8_t> pixels(std::size_t(width) * height * 4);
  for (std::size_t p = 0; p < pixels.size(); p += 4)
    pixels[p] = pixels[p + 1] = pixels[p + 2] = kWindowGrey, pixels[p + 3] = 255;
  const int copyWidth = std::min(width, canvasWidth), copyHeight = std::min(height, canvasHeight);
  for (int y = 0; y < copyHeight; ++y)
    std::memcpy(&pixels[std::size_t(y) * width * 4], &canvas[std::size_t(y) * canvasWidth * 4],
                std::size_t(copyWidth) * 4);
  upload_.write(pixels.data(), pixels.size());

  const vk::raii::CommandBuffer& cmd = commands_[0];
  cmd.reset();
  cmd.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  const vk::ImageSubresourceRange range(vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1);
  using S = vk::PipelineStageFlagBits;
  using A = vk::AccessFlagBits;
  using L = vk::ImageLayout;
  const auto barrier = [&](L from, L to, vk::AccessFlags srcAccess, vk::AccessFlags dstAccess, S srcStage,
                           S dstStage) {
    cmd.pipelineBarrier(srcStage, dstStage, {}, {}, {},
                        vk::ImageMemoryBarrier(srcAccess, dstAccess, from, to, VK_QUEUE_FAMILY_IGNORED,
                                               VK_QUEUE_FAMILY_IGNORED, images_[index], range));
  };
  barrier(L::eUndefined, L::eTransferDstOptimal, {}, A::eTransferWrite, S::eTopOfPipe, S::eTransfer);
  const vk::BufferImageCopy region(0, 0, 0, {vk::ImageAspectFlagBits::eColor, 0, 0, 1}, {0, 0, 0},
                                   {extent_.width, extent_.height, 1});
  cmd.copyBufferToImage(upload_.handle(), images_[index], L::eTransferDstOptimal, region);
  cmd.beginRenderPass(vk::RenderPassBeginInfo(*renderPass_, *framebuffers_[index], {{0, 0}, extent_}),
                      vk::SubpassContents::eInline);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), *cmd);
  cmd.endRenderPass();
  if (readback) {
    barrier(L::ePresentSrcKHR, L::eTransferSrcOptimal, A::eColorAttachmentWrite, A::eTransferRead,
            S::eColorAttachmentOutput, S::eTransfer);
    cmd.copyImageToBuffer(images_[index], L::eTransferSrcOptimal, readback_.handle(), region);
    barrier(L::eTransferSrcOptimal, L::ePresentSrcKHR, A::eTransferRead, {}, S::eTransfer, S::eBottomOfPipe);
    // The fence alone does not make the copy visible to the host.
    cmd.pipelineBarrier(S::eTransfer, S::eHost, {}, vk::MemoryBarrier(A::eTransferWrite, A::eHostRead), {},
                        {});
  }
  cmd.end();
  const vk::PipelineStageFlags waitStage = S::eTransfer;
  const vk::CommandBuffer handle = *cmd;
  const vk::Semaphore finished = *renderFinished_[index];
  auto queueLock = context_->lockQueue();
  context_->queue().submit(vk::SubmitInfo(*imageAvailable_, waitStage, handle, finished), *frameDone_);
  try {
    const vk::SwapchainKHR swapchain = *swapchain_;
    const vk::Result result = context_->queue().presentKHR(vk::PresentInfoKHR(finished, swapchain, index));
    if (result == vk::Result::eSuboptimalKHR) needsRecreate_ = true;
  } catch (const vk::OutOfDateKHRError&) {
    needsRecreate_ = true;
  }
  queueLock.unlock();
  if (!readback) return std::nullopt;
  (void)device.waitForFences(*frameDone_, VK_TRUE, std::numeric_limits<uint64_t>::max());
  std::vector<std::uint8_t> bgra(std::size_t(width) * height * 4);
  readback_.read(bgra.data(), bgra.size());
  Screenshot shot{width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 3)};
  for (std::size_t p = 0; p < std::size_t(width) * height; ++p) {
    shot.rgb[3 * p + 0] = bgra[4 * p + 2];
    shot.rgb[3 * p + 1] = bgra[4 * p + 1];
    shot.rgb[3 * p + 2] = bgra[4 * p + 0];
  }
  return shot;
}

}  // namespace iblx::viewer
