// The viewer's loop (viewer.h): the window, the model (viewer_model.h) and the panels (viewer_panels.h), one
// frame at a time; the canvas composed from the model's images; the scripted mode's screenshot and summary.
#include "tools/viewer/viewer.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/vk/context.h"
#include "engine/scene/brdf_params.h"
#include "engine/vk/shader_compiler.h"
#include "tools/viewer/compare_view.h"
#include "tools/viewer/display_kernel.h"
#include "tools/viewer/viewer_model.h"
#include "tools/viewer/viewer_panels.h"
#include "tools/viewer/window.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace iblx::viewer {
namespace {

// The canvas of this frame: A's image (or A and B composed) through the display transform, on the GPU from
// the renderers' accumulations, with the exposure it was drawn with.
struct Canvas {
  CompareCanvas pixels;
  double exposureEV = 0.0;
};

Canvas composeCanvas(ViewerModel& model, const ViewerPanels& panels, DisplayKernel& display) {
  const ViewerOptions& options = model.options();
  const GBuffer& g = model.shownGBuffer();
  const std::span<const float> a = model.shownA();
  // The same transform as render's PNG of the same image: the automatic exposure reads the object pixels. In
  // compare mode A's transform serves both, so that their brightness compares.
  const DisplayTransform transform = resolveDisplay(options.display, a, model.objectMask());
  const bool comparing = model.comparing();
  const ActiveRenderer& activeA = model.active();
  const ActiveRenderer& activeB = model.compareActive();
  const bool sameScene =
      comparing && activeB.scene && activeB.scene->gbuffer.pixels.size() == g.pixels.size();
  const bool showsB = sameScene && !model.shownB().empty();
  CompareFrame frame{&g,
                     a,
                     showsB ? model.shownB() : std::span<const float>(),
                     {},
                     transform,
                     options.background,
                     comparing ? options.compareView : CompareView::Flip,
                     panels.divider(),
                     comparing && panels.flipShowsB()};
  if (comparing && model.referenceMatches(activeA) && model.referenceMatches(activeB))
    frame.reference = *model.reference();
  const Renderer* gbufferOwner = activeA.renderer ? activeA.renderer.get() : activeB.renderer.get();
  const Buffer* accumA = !a.empty() && activeA.renderer ? &activeA.renderer->accumulation() : nullptr;
  const Buffer* accumB = showsB ? &activeB.renderer->accumulation() : nullptr;
  if (!gbufferOwner) return {composeCompare(frame), transform.exposureEV};  // nothing rendered yet
  return {display.compose(frame, accumA, accumB, gbufferOwner->gbufferBuffer()), transform.exposureEV};
}

ViewerModel* gDropTarget = nullptr;  // GLFW's drop callback has no user pointer of ours to spare

void writeScreenshot(const Screenshot& shot, const std::filesystem::path& path) {
  writePngRgb8(path, shot.width, shot.height, shot.rgb);
  std::printf("wrote %s (%dx%d)\n", path.string().c_str(), shot.width, shot.height);
}

}  // namespace

int runViewer(const ViewerOptions& options) {
  // Validate everything a user can get wrong before a window opens.
  {
    const DeviceTableLimit tableLimit = deviceTableLimit(options.device);
    const LoadedBrdf brdf = loadBrdfArgument(options.scene.brdf);
    (void)resolveParams(*brdf.info, options.scene.params);
    (void)resolveMethod(options.method, *brdf.info);
    if (options.compare) (void)resolveMethod(*options.compare, *brdf.info);
  }
  // The image at the top left, the convergence plot under it, the panel on the right.
  const bool sideBySide = options.compare && options.compareView == CompareView::SideBySide;
  const int canvasWidth = sideBySide ? 2 * options.scene.width : options.scene.width;
  const int canvasHeight = sideBySide ? 2 * options.scene.height : options.scene.height;
  const int width = std::max(canvasWidth, 520) + kPanelWidth;
  const int height = std::max(canvasHeight + 320, 720);
  ViewerWindow window("iblx view", width, height,
                      {options.device, options.validation ? Validation::On : Validation::Auto});
  ViewerModel model(options, window.context());
  if (!model.error().empty()) throw Error(model.error());
  ViewerPanels panels(options);
  ShaderCompiler compiler;
  DisplayKernel display(window.context(), compiler);
  const bool scripted = options.frames > 0;
  if (scripted) model.prepareBlocking(options.reference);
  gDropTarget = &model;
  glfwSetDropCallback(window.handle(), [](GLFWwindow*, int count, const char** paths) {
    if (gDropTarget && count > 0) gDropTarget->openFile(paths[count - 1]);
  });
  const std::filesystem::path screenshotPath =
      options.screenshot.empty() ? "iblx-view.png" : options.screenshot;
  const auto loopStart = std::chrono::steady_clock::now();
  uint32_t frames = 0;
  bool screenshotWritten = false;
  while (window.beginFrame()) {
    ++frames;
    // Dear ImGui 1.86 indexes keys by the backend's codes (GLFW's here).
    if (!ImGui::GetIO().WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F12, false))
      panels.requestScreenshot();
    panels.handleInput(model);
    const bool lastScripted = scripted && model.passes() + model.comparePasses() + 1 >= options.frames;
    const bool wantShot = !options.screenshot.empty() && lastScripted;
    // The pass runs before the panels, so their figures describe the image shown with them; what the panels
    // change takes effect in the next frame.
    model.frame();
    const Canvas canvas = composeCanvas(model, panels, display);
    panels.draw(model, {window.width(), window.height(), canvas.pixels.width, canvas.pixels.height},
                canvas.exposureEV);
    if (const auto shot = window.endFrame(canvas.pixels.bgra, canvas.pixels.width, canvas.pixels.height,
                                          panels.wantsScreenshot() || wantShot)) {
      try {
        writeScreenshot(*shot, screenshotPath);
        screenshotWritten = true;
      } catch (const std::exception& e) {
        if (scripted) throw;
        model.showError(errorText(e));  // an unwritable directory is no reason to close the viewer
      }
      panels.clearScreenshotRequest();
    }
    // A scripted run ends with its screenshot; a frame lost to a swapchain rebuild is simply drawn again.
    if (lastScripted && (!wantShot || screenshotWritten)) break;
    if (scripted && frames > options.frames + 100)
      throw Error("the window system presented no frame to read the screenshot from");
  }
  gDropTarget = nullptr;
  if (scripted) {
    if (!model.error().empty()) throw Error(model.error());
    const ActiveRenderer& active = model.active();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - loopStart).count();
    std::printf("%s: %u passes, %llu spp, %u frames in %.2f s (%.1f frames/s)", active.method.label().c_str(),
                model.passes(),
                static_cast<unsigned long long>(active.renderer ? active.renderer->samplesPerPixel() : 0),
                frames, seconds, seconds > 0.0 ? frames / seconds : 0.0);
    if (const ConvergenceCurve* curve = model.currentCurve(); curve && !curve->mse.empty())
      std::printf(", MSE %.9g, relMSE %.9g", curve->mse.back(), curve->relMse.back());
    std::printf("\n");
    if (const ActiveRenderer& b = model.compareActive(); b.renderer)
      std::printf("B: %s: %u passes, %llu spp\n", b.method.label().c_str(), model.comparePasses(),
                  static_cast<unsigned long long>(b.renderer->samplesPerPixel()));
    // The scripted mode is what CI runs: a validation error there is a failure, not a line on stderr.
    if (const uint32_t errors = window.context().validationErrorCount(); errors > 0)
      throw Error(std::to_string(errors) + " Vulkan validation error(s) during the scripted run (see above)");
  }
  return 0;
}

}  // namespace iblx::viewer
