// The viewer's display kernel (tools/viewer/display_kernel.h) against its CPU reference, composeCompare:
// every compare view, tone curve and encoding, with and without the background and the error row, on images
// that hold zeros, tiny and huge values. Image pixels may differ by one code value (float against double at a
// rounding boundary); the error row's colours by one step of the colormap (it is computed in logarithms, so
// errors beyond float's range still land where the CPU's double puts them).
#include "tools/viewer/display_kernel.h"

#include "engine/geometry/gbuffer.h"
#include "engine/vk/context.h"
#include "engine/vk/shader_compiler.h"
#include "shaders/shared/frame_params.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

using namespace iblx;
using namespace iblx::viewer;

namespace {

std::vector<float> testImage(std::size_t pixels, unsigned seed) {
  const float special[] = {0.0f, 1e-8f, 0.0031f, 0.5f, 1.0f, 3.0f, 7.3f, 1e6f, 1e30f};
  std::vector<float> rgb(3 * pixels);
  unsigned state = seed;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    rgb[i] =
        i % 7 == 0 ? special[(state >> 8) % std::size(special)] : float(state >> 8) / float(1u << 24) * 2.0f;
  }
  return rgb;
}

Buffer accumulationOf(const VulkanContext& context, std::span<const float> rgb) {
  std::vector<gpu::AccumPixel> accum(rgb.size() / 3);
  for (std::size_t p = 0; p < accum.size(); ++p)
    accum[p].mean = {rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2], 0.0f};
  return Buffer::fromData(context, accum, "test accumulation");
}

// The largest difference of one channel between the two canvases, in the image rows and in the error row.
struct CanvasDifference {
  int image = 0, errorRow = 0;
};
CanvasDifference difference(const CompareCanvas& gpu, const CompareCanvas& cpu, int imageHeight) {
  REQUIRE(gpu.width == cpu.width);
  REQUIRE(gpu.height == cpu.height);
  REQUIRE(gpu.bgra.size() == cpu.bgra.size());
  CanvasDifference d;
  for (std::size_t i = 0; i < gpu.bgra.size(); ++i) {
    const int row = int(i / 4 / std::size_t(gpu.width));
    int& worst = row < imageHeight ? d.image : d.errorRow;
    worst = std::max(worst, std::abs(int(gpu.bgra[i]) - int(cpu.bgra[i])));
  }
  return d;
}

}  // namespace

TEST_CASE("display kernel: the GPU canvas is the CPU canvas, for every view, curve and encoding") {
  VulkanContext context;
  ShaderCompiler compiler;
  DisplayKernel kernel(context, compiler);
  const GBuffer g = makeGBuffer("sphere", CameraSpec{}, 20, 12);
  const std::size_t pixels = g.pixels.size();
  const std::vector<float> a = testImage(pixels, 1), b = testImage(pixels, 2),
                           reference = testImage(pixels, 3);
  const Buffer accumA = accumulationOf(context, a), accumB = accumulationOf(context, b);
  const Buffer gbuffer = Buffer::fromData(context, g.pixels, "test gbuffer");

  for (const Tonemap tonemap : {Tonemap::Clamp, Tonemap::Reinhard, Tonemap::Aces})
    for (const double gamma : {0.0, 2.2})
      for (const CompareView view : {CompareView::Split, CompareView::SideBySide, CompareView::Flip})
        for (const bool background : {true, false}) {
          CAPTURE(int(tonemap));
          CAPTURE(gamma);
          CAPTURE(int(view));
          CAPTURE(background);
          CompareFrame frame{&g,         a,    b,   {},  DisplayTransform{1.5, tonemap, gamma},
                             background, view, 0.3, true};
          if (view == CompareView::SideBySide) frame.reference = reference;
          const CanvasDifference d =
              difference(kernel.compose(frame, &accumA, &accumB, gbuffer), composeCompare(frame), g.height);
          CHECK(d.image <= 1);
          CHECK(d.errorRow <= 4);  // one colormap step at most
        }

  // Nothing rendered for B yet: grey where it would be, as on the CPU.
  CompareFrame single{&g, a, {}, {}, DisplayTransform{0.0, Tonemap::Aces, 0.0}, true, CompareView::Split,
                      0.5};
  CHECK(
      difference(kernel.compose(single, &accumA, nullptr, gbuffer), composeCompare(single), g.height).image <=
      1);
}
