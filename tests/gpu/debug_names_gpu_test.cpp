// Vulkan objects carry debug names (VK_EXT_debug_utils): a validation message names the kernel, set or buffer
// it is about instead of quoting a bare handle.
#include "engine/vk/compute_kernel.h"
#include "engine/vk/context.h"
#include "engine/vk/shader_compiler.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <string>

namespace iblx {

TEST_CASE("debug names: a validation message quotes the name of the kernel's descriptor set") {
  VulkanContext context({.validation = Validation::Auto});
  if (!context.validationEnabled()) {
    MESSAGE("validation layers not enabled (IBLX_VALIDATION=1 or a debug build): nothing to check");
    return;
  }
  ShaderCompiler compiler;
  const std::vector<uint32_t> spirv = compiler.compile(
      "#version 460\nlayout(local_size_x = 1) in;\n"
      "layout(set = 0, binding = 0) buffer Out { uint value[]; } result;\n"
      "void main() { result.value[0] = 1u; }\n",
      "debug-name probe");
  ComputeKernel kernel(context, spirv, KernelLayout{{1, 0, 0, 0}, 0, {}}, "debug-name probe");
  // Recorded with its buffer never bound, and never submitted: the validation layers report the unwritten
  // descriptor when the dispatch is recorded.
  vk::raii::CommandBuffers buffers(
      context.device(), vk::CommandBufferAllocateInfo(*context.commandPool(), vk::CommandBufferLevel::ePrimary, 1));
  const uint32_t before = context.validationErrorCount();
  buffers[0].begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  kernel.record(*buffers[0], 1, 1, nullptr, 0);
  buffers[0].end();
  REQUIRE(context.validationErrorCount() > before);
  const std::vector<std::string> messages = context.validationMessages();
  const bool named = std::any_of(messages.begin(), messages.end(), [](const std::string& m) {
    return m.find("debug-name probe") != std::string::npos;
  });
  INFO("messages: " << (messages.empty() ? std::string() : messages.back()));
  CHECK(named);
}

}  // namespace iblx
