// The viewer's model without a window or Dear ImGui (tools/viewer/viewer_model.h): passes, restarts and
// generations, equal time in compare mode, the cached object mask, files it cannot open, and errors in the
// viewer's words. Runs on the Vulkan device present (lavapipe without a GPU), no display needed.
#include "tools/viewer/viewer_model.h"

#include "tools/viewer/background_job.h"

#include "engine/core/error.h"
#include "engine/core/setting.h"
#include "engine/io/alta_data.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

using namespace iblx;
using namespace iblx::viewer;

namespace {

ViewerOptions smallScene() {
  ViewerOptions options;
  options.scene.width = options.scene.height = 16;
  options.scene.brdf = "lambert";
  options.method.method = "env-cdf";
  options.samplesPerPass = 2;
  return options;
}

}  // namespace

TEST_CASE("viewer jobs: one poll takes a result, reports a failure and drops a cancelled job silently") {
  auto succeeded = std::make_unique<BackgroundJob<int>>("ok", [](const auto&) { return 7; });
  auto failed =
      std::make_unique<BackgroundJob<int>>("bad", [](const auto&) -> int { throw Error("broken"); });
  std::atomic<bool> started{false};
  auto cancelled = std::make_unique<BackgroundJob<int>>("slow", [&](const auto& progress) {
    started = true;
    for (;;) {
      progress(0.5);  // throws JobCancelled once cancel() was called
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return 0;
  });
  CHECK(cancelled->status() == JobStatus::Running);
  while (!started) std::this_thread::yield();
  cancelled->cancel();
  succeeded->wait(), failed->wait(), cancelled->wait();
  CHECK(succeeded->status() == JobStatus::Succeeded);
  CHECK(failed->status() == JobStatus::Failed);
  CHECK(cancelled->status() == JobStatus::Cancelled);
  std::string error;
  int taken = 0, calls = 0;
  finishJob(succeeded, error, "A: ", [&](int v) { taken = v, ++calls; });
  CHECK(taken == 7);
  CHECK(error.empty());
  finishJob(cancelled, error, "C: ", [&](int) { ++calls; });
  CHECK(error.empty());
  finishJob(failed, error, "B: ", [&](int) { ++calls; });
  CHECK(error == "B: broken");
  CHECK(calls == 1);
  CHECK((!succeeded && !failed && !cancelled));
}

TEST_CASE("viewer: the method list offers every registry method that is not measurement-only") {
  const std::vector<MethodInfo> offered = viewerMethods();
  for (const MethodInfo& m : methodRegistry()) {
    const bool listed =
        std::any_of(offered.begin(), offered.end(), [&](const MethodInfo& o) { return o.name == m.name; });
    CHECK_MESSAGE(listed == !m.strategyInfo().measurementOnly, m.name);
  }
}

TEST_CASE("viewer model: passes accumulate; new parameters start a new generation without a rebuild") {
  VulkanContext context;
  ViewerModel model(smallScene(), context);
  REQUIRE(model.error().empty());
  model.prepareBlocking(false);
  for (int k = 0; k < 3; ++k) model.frame();
  CHECK(model.passes() == 3);
  REQUIRE(model.active().renderer);
  CHECK(model.active().renderer->samplesPerPixel() == 6);
  CHECK(model.shownA().size() == 16 * 16 * 3);
  CHECK(model.active().generation == model.generation());

  const Renderer* renderer = model.active().renderer.get();
  const uint64_t generation = model.generation();
  ParamValues params = model.params();
  params["albedo"] = {0.5, 0.5, 0.5};
  model.setParams(params);
  CHECK(model.generation() > generation);
  CHECK(model.active().renderer.get() == renderer);  // same tables and shaders
  CHECK(model.active().generation == model.generation());
  CHECK(model.passes() == 0);
  model.frame();
  CHECK(model.active().renderer->samplesPerPixel() == 2);

  // The object mask is made once per G-buffer.
  const std::span<const std::uint8_t> mask = model.objectMask();
  CHECK(model.objectMask().data() == mask.data());
  CHECK(std::size_t(std::count(mask.begin(), mask.end(), std::uint8_t(1))) ==
        model.shownGBuffer().objectPixelCount());
}

TEST_CASE("viewer model: a method change rebuilds; compare mode renders A and B at equal time") {
  VulkanContext context;
  ViewerModel model(smallScene(), context);
  model.prepareBlocking(false);
  model.options().method.method = "env-hier";
  model.methodChanged();
  model.prepareBlocking(false);
  CHECK(model.active().method.label().rfind("env-hier", 0) == 0);

  MethodSpec b = model.options().method;
  b.sequence = "sobol";
  model.setCompare(b);
  model.prepareBlocking(false);
  REQUIRE(model.compareActive().renderer);
  // Each frame runs whichever has rendered for less time (A when they are even): equal time.
  for (int k = 0; k < 8; ++k) {
    const bool bBehind = model.compareWallSeconds() < model.wallSeconds();
    const uint32_t passesA = model.passes(), passesB = model.comparePasses();
    model.frame();
    CHECK(model.passes() == passesA + (bBehind ? 0 : 1));
    CHECK(model.comparePasses() == passesB + (bBehind ? 1 : 0));
  }
  CHECK(model.passes() >= 1);
  CHECK(model.comparePasses() >= 1);
  CHECK(model.shownB().size() == 16 * 16 * 3);
  model.setCompare(std::nullopt);
  CHECK_FALSE(model.compareActive().renderer);
  CHECK(model.shownB().empty());
}

TEST_CASE("viewer model: a file it cannot open is an error naming it, and the scene stays") {
  VulkanContext context;
  ViewerModel model(smallScene(), context);
  const auto scene = model.scene();
  model.openFile("notes.txt");
  CHECK(
      model.error() ==
      "notes.txt: not an environment (.exr, .hdr), BRDF (.brdf, .bparam, .binary, .bin, .data, .alta, .dat, "
      ".bsdf, .func) or object (.obj)");
  CHECK(model.scene() == scene);
}

TEST_CASE("viewer model: a dropped measured file is recognised by its content whatever its name") {
  VulkanContext context;
  ViewerModel model(smallScene(), context);
  const auto path = std::filesystem::temp_directory_path() / "iblx-viewer-test-alta.txt";
  AltaData data;
  data.param = AltaParam::RusinThTd;
  data.samples = 4;
  data.x = {0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0};
  data.rgb.assign(12, 0.2);
  writeAltaData(path, data, false);
  model.openFile(path);
  // The file loads in the background; frames take over the loaded scene.
  for (int k = 0; k < 2000 && model.error().empty() && model.scene()->brdf->evalPart != "brdf/alta_data.glsl";
       ++k) {
    model.frame();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::filesystem::remove(path);
  CHECK(model.error().empty());
  CHECK(model.scene()->brdf->evalPart == "brdf/alta_data.glsl");
}

TEST_CASE("viewer model: engine errors name the viewer's control, or the flag only the command line sets") {
  CHECK(errorText(SettingError(Setting::MisSplit, "", " must be in [0, 1]")) ==
        "env fraction must be in [0, 1]");
  CHECK(errorText(SettingError(Setting::ImageSize, "", " 9x9: too large")) == "--size 9x9: too large");
  CHECK(errorText(Error("plain")) == "plain");
}
