// The viewer's display kernel (display_kernel.h).
#include "tools/viewer/display_kernel.h"

#include "engine/analysis/palette.h"
#include "engine/vk/shader_compiler.h"
#include "shaders/shared/display_params.h"
#include "shaders/shared/frame_params.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace iblx::viewer {

DisplayKernel::DisplayKernel(const VulkanContext& context, ShaderCompiler& compiler) : context_(context) {
  const std::vector<std::uint32_t> spirv = compiler.compile(
      "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"display.comp\"\n",
      "display");
  kernel_ = std::make_unique<ComputeKernel>(
      context, spirv, KernelLayout{{6, 0, 0, 0}, sizeof(gpu::DisplayParams), {}}, "display");
  std::array<std::uint32_t, 256> table{};
  for (std::size_t k = 0; k < table.size(); ++k) {
    const Rgb8 c = colormap(double(k) / 255.0);
    table[k] = std::uint32_t(c.r) | std::uint32_t(c.g) << 8 | std::uint32_t(c.b) << 16;
  }
  colormap_ = Buffer::fromData(context, std::span<const std::uint32_t>(table), "display colormap");
  placeholder_ = Buffer(context, sizeof(gpu::AccumPixel), "display placeholder");  // for what is not there
}

CompareCanvas DisplayKernel::compose(const CompareFrame& frame, const Buffer* accumA, const Buffer* accumB,
                                     const Buffer& gbuffer) {
  const GBuffer& g = *frame.gbuffer;
  CompareCanvas canvas;
  const bool errorRow = frame.view == CompareView::SideBySide && !frame.reference.empty();
  canvas.width = frame.view == CompareView::SideBySide ? 2 * g.width : g.width;
  canvas.height = errorRow ? 2 * g.height : g.height;
  const std::size_t pixels = std::size_t(canvas.width) * std::size_t(canvas.height);

  gpu::DisplayParams params{};
  params.width = std::uint32_t(g.width), params.height = std::uint32_t(g.height);
  params.canvasWidth = std::uint32_t(canvas.width), params.canvasHeight = std::uint32_t(canvas.height);
  params.view = std::uint32_t(frame.view);
  params.splitColumn = std::uint32_t(std::clamp(int(std::lround(frame.divider * g.width)), 0, g.width));
  params.flags = (accumA ? DISPLAY_HAS_A : 0u) | (accumB ? DISPLAY_HAS_B : 0u) |
                 (errorRow ? DISPLAY_ERROR_ROW : 0u) | (frame.background ? DISPLAY_BACKGROUND : 0u) |
                 (frame.showB ? DISPLAY_FLIP_SHOWS_B : 0u);
  params.tonemap = std::uint32_t(frame.display.tonemap);
  params.exposureScale = float(std::exp2(frame.display.exposureEV));
  params.gamma = float(frame.display.gamma);
  if (errorRow) {
    const double high = sharedErrorHigh(g, frame.a, frame.b, frame.reference).value_or(1.0);
    params.errorLog10Low = float(std::log10(high * 1e-4)), params.errorLog10High = float(std::log10(high));
    if (!std::equal(frame.reference.begin(), frame.reference.end(), uploadedReference_.begin(),
                    uploadedReference_.end())) {
      reference_ = Buffer::fromData(context_, frame.reference, "display reference");
      uploadedReference_.assign(frame.reference.begin(), frame.reference.end());
    }
  }
  if (canvas_.size() != pixels * 4) canvas_ = Buffer(context_, pixels * 4, "display canvas");
  kernel_->bindBuffers(0, {accumA ? accumA : &placeholder_, accumB ? accumB : &placeholder_, &gbuffer,
                           errorRow ? &reference_ : &placeholder_, &colormap_, &canvas_});
  context_.submitAndWait([&](vk::CommandBuffer cmd) {
    kernel_->record(cmd, std::uint32_t((pixels + 63) / 64), 1, &params, sizeof params);
    recordShaderWriteBarrier(cmd, true);
  });
  canvas.bgra = canvas_.readAll<std::uint8_t>();
  return canvas;
}

}  // namespace iblx::viewer
