// The viewer's display transform on the GPU (shaders/display.comp): the canvas of composeCompare
// (compare_view.h, its CPU reference) composed from the renderers' accumulations where they are, so no
// image is tone-mapped on the CPU every frame. The automatic exposure and the error row's scale are the
// CPU's (they are statistics of the images the viewer reads back for its convergence curves).
#pragma once

#include "engine/vk/buffer.h"
#include "engine/vk/compute_kernel.h"
#include "tools/viewer/compare_view.h"

#include <memory>
#include <vector>

namespace iblx {
class ShaderCompiler;
}

namespace iblx::viewer {

class DisplayKernel {
 public:
  DisplayKernel(const VulkanContext& context, ShaderCompiler& compiler);

  // composeCompare(frame), with A's and B's pixels read from their accumulations (null: not rendered yet;
  // frame.a and frame.b are read only for the error row's scale) and the object mask from `gbuffer`, the
  // G-buffer of frame.gbuffer on the device (read only where an image is rendered). The reference is
  // uploaded when it changes.
  CompareCanvas compose(const CompareFrame& frame, const Buffer* accumA, const Buffer* accumB,
                        const Buffer& gbuffer);

 private:
  const VulkanContext& context_;
  std::unique_ptr<ComputeKernel> kernel_;
  Buffer colormap_, placeholder_, reference_, canvas_;
  std::vector<float> uploadedReference_;  // what reference_ holds
};

}  // namespace iblx::viewer
