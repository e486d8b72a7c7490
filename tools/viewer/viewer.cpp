// `iblx view` (viewer.h): the viewer's state, its ImGui panel and the frame loop. Every control edits a copy
// of the scene and method specs; a change that the running renderer cannot absorb (method, sequence, object,
// camera, environment rotation or file) rebuilds it, and every change restarts the accumulation.
#include "tools/viewer/viewer.h"

#include "engine/core/error.h"
#include "engine/core/file_names.h"
#include "engine/core/setting.h"
#include "engine/core/cache_dir.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/scene/brdf_params.h"
#include "engine/scene/methods.h"
#include "engine/render/metrics.h"
#include "engine/render/reference.h"
#include "engine/render/renderer.h"
#include "tools/viewer/background_job.h"
#include "tools/viewer/compare_view.h"
#include "tools/viewer/convergence_plot.h"
#include "tools/viewer/file_browser.h"
#include "tools/viewer/sample_overlay.h"
#include "tools/viewer/window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

namespace iblx::viewer {

namespace {

// The control (or, for what only the command line sets, the flag) that sets an engine setting: how the viewer
// words a SettingError.
std::string_view settingControl(Setting setting) {
  switch (setting) {
    case Setting::Environment:
      return "environment";
    case Setting::EnvRotation:
      return "env rotation";
    case Setting::Brdf:
      return "BRDF";
    case Setting::BrdfParam:
      return "material parameter";
    case Setting::Object:
      return "object";
    case Setting::Orbit:
      return "orbit (drag)";
    case Setting::Zoom:
      return "zoom (wheel)";
    case Setting::ImageSize:
      return "--size";
    case Setting::Method:
      return "method";
    case Setting::EnvSampler:
      return "env technique";
    case Setting::BrdfSampler:
      return "BRDF technique";
    case Setting::Sequence:
      return "sequence";
    case Setting::MisHeuristic:
      return "power heuristic";
    case Setting::MisSplit:
      return "env fraction";
    case Setting::RisCandidates:
      return "candidates M";
    case Setting::MisCompensation:
      return "compensated env technique";
    case Setting::Device:
      return "--device";
  }
  return settingName(setting);
}

std::string errorText(const std::exception& e) {
  if (const auto* setting = dynamic_cast<const SettingError*>(&e))
    return setting->named(settingControl(setting->setting()));
  return e.what();
}

constexpr int kPanelWidth = 360;  // the ImGui panel to the right of the image

// A renderer and the scene and method it was built from (the renderer keeps a reference to the scene).
struct ActiveRenderer {
  std::shared_ptr<const Scene> scene;
  ResolvedMethod method;
  std::unique_ptr<Renderer> renderer;
  uint64_t generation = 0;  // of the scene and parameters it renders (ViewerApp::generation_)

  // The renderer holds a reference to the scene: it goes first.
  ActiveRenderer& operator=(ActiveRenderer&& other) noexcept {
    renderer = std::move(other.renderer);
    scene = std::move(other.scene);
    method = other.method;
    generation = other.generation;
    return *this;
  }
  ActiveRenderer() = default;
  ActiveRenderer(ActiveRenderer&&) noexcept = default;
};

// One pixel's samples for the overlay, recorded by the method's own integrator
// (engine/render/sample_recorder.h).
struct Recording {
  uint64_t generation = 0;
  int x = 0, y = 0;
  gpu::GPixel pixel{};
  std::vector<RecordedSample> samples;
  std::string methodLabel;
  std::vector<double> lobe;  // f cos over the hemisphere disc (SampleOverlay::lobeOnDisc)
};

// A scene read in the background, with the spec it was read from.
struct LoadedScene {
  SceneSpec spec;  // what was read
  std::shared_ptr<Scene> scene;
};

// Everything the viewer shows, and what it was built from.
class ViewerApp {
 public:
  ViewerApp(ViewerOptions options, ViewerWindow& window) : options_(std::move(options)), window_(window) {
    if (loadSceneFromSpec() && options_.reference && options_.frames == 0) startReference();
    overlayCount_ = int(options_.overlayCount);
    if (options_.overlayPixel) {
      overlayOn_ = true;
      pendingPixel_ = options_.overlayPixel;
    }
  }
  ~ViewerApp() {
    for (JobBase* job : std::initializer_list<JobBase*>{
             referenceJob_.get(), recordJob_.get(), buildJob_.get(), compareBuildJob_.get(), loadJob_.get()})
      if (job) job->cancel();
  }

  // One frame: finished background work is taken over, one pass runs, the panel and the canvas are drawn.
  // The pass runs before the panel, so the panel's figures describe the image shown with them; what the panel
  // changes takes effect in the next frame. Returns the presented image when readback is asked.
  std::optional<Screenshot> frame(bool readback) {
    pollJobs();
    if (rebuild_ && !buildJob_) startBuild();
    // While a ground truth computes (minutes for a real map on lavapipe), passes compete with it for the
    // device and are discarded when it arrives (the curve starts from the first pass): a few give a picture
    // to look at, then they wait.
    constexpr uint32_t kPassesWhileComputing = 16;
    const bool computing = referenceJob_ != nullptr;
    // Compare mode: one pass per frame for whichever of A and B has rendered for less time (equal time).
    const bool runB = comparing() && compare_.renderer && compareWallSeconds_ < wallSeconds_;
    if (runB && !paused_ && !(computing && comparePasses_ >= kPassesWhileComputing)) {
      compareWallSeconds_ += compare_.renderer->runPass(options_.samplesPerPass).wallSeconds;
      ++comparePasses_;
      shownB_ = compare_.renderer->meanRgb();
      if (!computing) recordError(shownB_, compare_, compareWallSeconds_, compareCurve_);
    } else if (!runB && active_.renderer && !paused_ && !(computing && passes_ >= kPassesWhileComputing)) {
      const PassTiming t = active_.renderer->runPass(options_.samplesPerPass);
      wallSeconds_ += t.wallSeconds;
      ++passes_;
      // Read back only after a pass: paused or waiting, the image has not changed.
      shown_ = active_.renderer->meanRgb();
      if (!computing && !curves_.empty()) recordError(shown_, active_, wallSeconds_, curves_.back());
    } else if (!active_.renderer || active_.renderer->samplesPerPixel() == 0) {
      shown_.clear();  // restarted, or nothing built yet
    }
    if (!compare_.renderer || compare_.renderer->samplesPerPixel() == 0) shownB_.clear();
    updateCanvas(shown_);
    drawPanel();
    return window_.endFrame(canvas_, canvasWidth_, canvasHeight_, readback);
  }

  // Scripted mode: finishes the renderer build (and the ground truth with --reference) before any frame, so
  // that N frames are N passes.
  void prepareBlocking(bool withReference) {
    if (withReference) startReference();
    startBuild();
    if (buildJob_) buildJob_->wait();
    if (compareBuildJob_) compareBuildJob_->wait();
    if (referenceJob_) referenceJob_->wait();
    pollJobs();
    if (withReference && !reference_) throw Error("ground truth: " + error_);
    if (!error_.empty()) throw Error(error_);
    if (recordJob_) recordJob_->wait();
    pollJobs();
    if (!error_.empty()) throw Error(error_);
  }

  uint32_t passes() const { return passes_ + comparePasses_; }  // A's and B's: one per frame
  uint32_t comparePasses() const { return comparePasses_; }
  const ActiveRenderer& compareActive() const { return compare_; }
  bool wantsScreenshot() const { return screenshotRequested_; }
  void clearScreenshotRequest() { screenshotRequested_ = false; }
  void requestScreenshot() { screenshotRequested_ = true; }
  const std::string& lastError() const { return error_; }
  void showError(std::string message) { error_ = std::move(message); }
  const ActiveRenderer& active() const { return active_; }
  const ConvergenceCurve* currentCurve() const { return curves_.empty() ? nullptr : &curves_.back(); }

  // Mouse orbit and wheel zoom over the image (not over the panel).
  void handleMouse() {
    const ImGuiIO& io = ImGui::GetIO();
    if (comparing() && !io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F, false))
      flipShowB_ = !flipShowB_;
    if (io.WantCaptureMouse) return;
    // A click without a drag (or a right click) on the image picks the overlay's pixel.
    const bool click =
        (ImGui::IsMouseReleased(ImGuiMouseButton_Left) && io.MouseDragMaxDistanceSqr[0] < 9.0f) ||
        ImGui::IsMouseClicked(ImGuiMouseButton_Right);
    if (click && overlayOn_) {
      const int x = int(io.MousePos.x), y = int(io.MousePos.y);
      if (x >= 0 && y >= 0 && x < scene_->gbuffer.width && y < scene_->gbuffer.height) startRecording(x, y);
    }
    // Split view: a drag that starts on the divider moves it instead of the camera.
    if (comparing() && options_.compareView == CompareView::Split) {
      const double dividerX = divider_ * scene_->gbuffer.width;
      if (ImGui::IsMouseClicked(ImGuiMouseButton_Left))
        draggingDivider_ = std::abs(io.MousePos.x - dividerX) < 6.0 && io.MousePos.y < scene_->gbuffer.height;
      if (draggingDivider_ && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
        divider_ = std::clamp(double(io.MousePos.x) / scene_->gbuffer.width, 0.0, 1.0);
        return;
      }
    }
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
      CameraSpec& camera = options_.scene.camera;
      camera.azimuthDeg = std::fmod(camera.azimuthDeg - 0.4 * io.MouseDelta.x + 540.0, 360.0) - 180.0;
      camera.elevationDeg = std::clamp(camera.elevationDeg + 0.4 * io.MouseDelta.y, -89.0, 89.0);
      reloadGeometry();
    }
    if (io.MouseWheel != 0.0f) {
      options_.scene.camera.zoom =
          std::clamp(options_.scene.camera.zoom * std::exp2(0.25 * io.MouseWheel), 0.1, 20.0);
      reloadGeometry();
    }
  }

  // A file dropped on the window: an environment map, a BRDF or an object.
  void openFile(const std::filesystem::path& path) {
    const std::string ext = lowerExtension(path);
    SceneSpec next = options_.scene;
    if (ext == ".exr" || ext == ".hdr")
      next.envPath = path;
    else if (ext == ".brdf" || ext == ".binary" || ext == ".bparam")
      next.brdf = path.string(), next.params.clear();
    else if (ext == ".obj")
      next.object = path.string();
    else {
      error_ = path.string() +
               ": not an environment (.exr, .hdr), BRDF (.brdf, .binary, .bparam) or object (.obj)";
      return;
    }
    startLoad(next, path.filename().string());
  }

 private:
  // Loads the scene from options_.scene on this thread (at start, before the window shows anything); on
  // failure keeps the message and returns false.
  bool loadSceneFromSpec() {
    try {
      applyScene(std::make_shared<Scene>(loadScene(options_.scene)));
      return true;
    } catch (const std::exception& e) {
      error_ = errorText(e);
      return false;
    }
  }

  void applyScene(std::shared_ptr<const Scene> scene) {
    scene_ = std::move(scene);
    params_ = scene_->params;
    overlay_.setEnvironment(scene_->env);
    overlay_.clear();
    error_.clear();
    sceneChanged();
  }

  // A file opened from the UI: read in the background (a large EXR or MERL file takes a while); the current
  // scene stays until it is ready, and stays for good if the file is bad.
  void startLoad(const SceneSpec& spec, const std::string& name) {
    if (loadJob_) {
      error_ = "still opening the previous file; try again when it is open";
      return;
    }
    loadJob_ = std::make_unique<BackgroundJob<LoadedScene>>("opening " + name, [spec](const auto&) {
      return LoadedScene{spec, std::make_shared<Scene>(loadScene(spec))};
    });
  }

  // Camera and object changes: only the G-buffer (the environment stays loaded).
  void reloadGeometry() {
    try {
      // options_.scene holds the rotation; the parameters live in params_ (snapshotScene).
      auto next = std::make_shared<Scene>(makeScene(
          scene_->env, options_.scene, LoadedBrdf{scene_->brdf, scene_->measured, scene_->brdfFile}));
      // The running renderer takes the new G-buffer when it renders this scene's environment and BRDF and no
      // rebuild is pending: no tables, no compile, so orbiting stays smooth. Otherwise a rebuild.
      bool current = active_.renderer && !buildJob_ && !rebuild_ && active_.generation == generation_;
      dropReference();
      if (current && comparing() && !(compare_.renderer && !compareBuildJob_)) current = false;
      if (current) {
        active_.renderer->setView(*next);  // scenes are not changed once made, so both may share this one
        active_.scene = next;
        active_.generation = generation_;
        if (comparing()) {
          compare_.renderer->setView(*next);
          compare_.scene = next;
          compare_.generation = generation_;
        }
      }
      scene_ = std::move(next);
      if (!current) {
        rebuild_ = true;
        return;
      }
      restart();
      if (overlayOn_ && !overlay_.empty()) startRecording(overlay_.pixelX(), overlay_.pixelY());
    } catch (const std::exception& e) {
      error_ = errorText(e);
      rebuild_ = true;
    }
  }

  // What the ground truth depends on changed: it and every curve measured against it go.
  void dropReference() {
    ++generation_;
    retired_.retire(referenceJob_);
    reference_.reset();
    curves_.clear();
    compareCurve_ = {};
  }
  void sceneChanged() {
    dropReference();
    rebuild_ = true;
  }

  // Records the first overlayCount_ samples of pixel (x, y) with the current method, in the background.
  void startRecording(int x, int y) {
    if (const auto why = unrecordablePixel(scene_->gbuffer, x, y)) {
      error_ = "overlay: pixel " + std::to_string(x) + "," + std::to_string(y) + " is " + *why;
      return;
    }
    retired_.retire(recordJob_);
    std::shared_ptr<const Scene> scene = snapshotScene();
    const uint64_t generation = generation_;
    const MethodSpec spec = options_.method;
    const uint32_t seed = options_.seed, perPass = options_.samplesPerPass;
    const std::size_t count = std::size_t(overlayCount_);
    const VulkanContext& context = window_.context();
    recordJob_ = std::make_unique<BackgroundJob<Recording>>(
        "recording the pixel's samples", [scene, spec, seed, perPass, count, x, y, generation,
                                          &context](const std::function<void(double)>& progress) {
          ShaderCompiler compiler;
          const ResolvedMethod method = resolveMethod(spec, *scene->brdf);
          SampleRecorder recorder(context, compiler, *scene, method, seed);
          recorder.start(x, y);
          Recording r;
          r.generation = generation, r.x = x, r.y = y, r.methodLabel = method.label();
          r.pixel = scene->gbuffer.pixels[std::size_t(y) * scene->gbuffer.width + x];
          r.lobe = SampleOverlay::lobeOnDisc(
              r.pixel, [&](std::span<const glm::dvec3> wi, std::span<const glm::dvec3> wo) {
                return evaluateBrdf(context, compiler, *scene, wi, wo);
              });
          while (r.samples.size() < count) {
            for (RecordedSample& sample : recorder.runPass(perPass))
              if (r.samples.size() < count) r.samples.push_back(std::move(sample));
            progress(double(r.samples.size()) / double(count));
          }
          return r;
        });
  }

  // The scene as the next renderer or ground truth sees it.
  std::shared_ptr<Scene> snapshotScene() const {
    auto scene = std::make_shared<Scene>(*scene_);
    scene->envRotationDeg = options_.scene.envRotationDeg;
    scene->params = params_;
    return scene;
  }

  bool comparing() const { return options_.compare.has_value(); }

  void startBuild() {
    rebuild_ = false;
    std::shared_ptr<const Scene> scene = snapshotScene();
    buildJob_ = makeBuildJob(scene, options_.method);
    retired_.retire(compareBuildJob_);
    if (comparing()) compareBuildJob_ = makeBuildJob(scene, *options_.compare);
  }

  std::unique_ptr<BackgroundJob<ActiveRenderer>> makeBuildJob(const std::shared_ptr<const Scene>& scene,
                                                              const MethodSpec& spec) {
    const uint32_t seed = options_.seed;
    const uint64_t generation = generation_;
    const VulkanContext& context = window_.context();
    return std::make_unique<BackgroundJob<ActiveRenderer>>(
        "building the method (tables, shaders)", [scene, spec, seed, generation, &context](const auto&) {
          ActiveRenderer next;
          next.scene = scene, next.method = resolveMethod(spec, *scene->brdf), next.generation = generation;
          ShaderCompiler compiler;
          next.renderer = std::make_unique<Renderer>(context, compiler, *scene, next.method, seed);
          // One warm-up pass here: lavapipe compiles the pipeline on first use, which would otherwise sit in
          // the first pass's time and bend the start of the curve against time (as converge's warm-up
          // avoids).
          next.renderer->runPass(1);
          next.renderer->restart(seed);
          return next;
        });
  }

  void startReference() {
    if (referenceJob_) return;
    std::shared_ptr<const Scene> scene = snapshotScene();
    const VulkanContext& context = window_.context();
    referenceGeneration_ = generation_;  // dropReference() retires this job when the scene changes
    referenceJob_ = std::make_unique<BackgroundJob<std::vector<float>>>(
        "ground truth", [scene, &context](const std::function<void(double)>& progress) {
          ShaderCompiler compiler;
          ReferenceOptions options;
          options.progress = progress;
          options.maxWorkPerDispatch = 2e7;  // about 0.1 s per dispatch on lavapipe: frames keep coming
          return cachedReference(context, compiler, *scene, defaultCacheDir(), options).rgb;
        });
  }

  void pollJobs() {
    if (buildJob_ && buildJob_->done()) {
      if (auto& result = buildJob_->result()) {
        // Taken even if the scene changed meanwhile (rebuild_: a newer build follows), so the image keeps
        // moving; only a renderer of the current scene counts for the convergence plot (its generation).
        try {
          result->renderer->setParams(params_);  // sliders moved while it was being built
          if (!rebuild_) result->generation = generation_;
          active_ = std::move(*result);
          error_.clear();
        } catch (const std::exception& e) {
          if (!rebuild_) error_ = errorText(e);  // else: a build for the previous BRDF, dropped
        }
        // Compare mode: B's accumulation restarts too, or it would keep the head start it took while A built.
        if (comparing()) restart();
        else startCurve();
        // The overlay follows the method: its pixel is recorded again with the new one.
        if (pendingPixel_)
          startRecording(pendingPixel_->first, pendingPixel_->second), pendingPixel_.reset();
        else if (overlayOn_ && !overlay_.empty())
          startRecording(overlay_.pixelX(), overlay_.pixelY());
      } else {
        error_ = buildJob_->error();
      }
      buildJob_.reset();
    }
    if (compareBuildJob_ && compareBuildJob_->done()) {
      if (auto& result = compareBuildJob_->result()) {
        try {
          result->renderer->setParams(params_);
          if (!rebuild_) result->generation = generation_;
          compare_ = std::move(*result);
        } catch (const std::exception& e) {
          if (!rebuild_) error_ = errorText(e);
        }
        restart();  // A's accumulation too: equal time from here on, for both
      } else if (compareBuildJob_->error() != "cancelled") {
        error_ = "compare: " + compareBuildJob_->error();
      }
      compareBuildJob_.reset();
    }
    if (loadJob_ && loadJob_->done()) {
      if (auto& result = loadJob_->result()) {
        options_.scene = result->spec;
        applyScene(std::move(result->scene));
      } else {
        error_ = loadJob_->error();
      }
      loadJob_.reset();
    }
    if (recordJob_ && recordJob_->done()) {
      if (auto& result = recordJob_->result()) {
        if (result->generation == generation_)  // else a newer recording was or will be started
          overlay_.setSamples(result->x, result->y, result->pixel, std::move(result->samples),
                              std::move(result->methodLabel), std::move(result->lobe));
      } else if (recordJob_->error() != "cancelled")
        error_ = "overlay: " + recordJob_->error();
      recordJob_.reset();
    }
    retired_.collect();
    if (referenceJob_ && referenceJob_->done()) {
      if (auto& result = referenceJob_->result()) {
        reference_ = std::move(*result);
        restart();  // the curve starts at the first pass
      } else if (referenceJob_->error() != "cancelled") {
        error_ = "ground truth: " + referenceJob_->error();
      }
      referenceJob_.reset();
    }
  }

  void restartCounters() { passes_ = comparePasses_ = 0, wallSeconds_ = compareWallSeconds_ = 0.0; }

  // Restarts accumulation (of B too); the current curve restarts too (the earlier methods' curves stay).
  void restart() {
    if (active_.renderer) active_.renderer->restart(options_.seed);
    if (compare_.renderer) compare_.renderer->restart(options_.seed);
    startCurve();
  }

  // Also restarts the counters: a curve covers passes from the first.
  void startCurve() {
    restartCounters();
    compareCurve_ = {};
    if (reference_ && compare_.renderer) compareCurve_.label = "B: " + compare_.method.label();
    if (!reference_ || !active_.renderer) return;
    const std::string label = active_.method.label();
    if (!curves_.empty() && curves_.back().label == label) curves_.pop_back();
    curves_.push_back({label, {}, {}, {}, {}});
    constexpr std::size_t kMaxCurves = 6;  // the current one and five for comparison
    if (curves_.size() > kMaxCurves) curves_.erase(curves_.begin());
  }

  void recordError(std::span<const float> rgb, const ActiveRenderer& r, double seconds, ConvergenceCurve& c) {
    if (!reference_ || c.label.empty() || !r.renderer || r.generation != referenceGeneration_) return;
    const ErrorMetrics e = compareToReference(r.scene->gbuffer, rgb, *reference_);
    c.spp.push_back(double(r.renderer->samplesPerPixel()));
    c.seconds.push_back(seconds);
    c.mse.push_back(e.mse);
    c.relMse.push_back(e.relMse);
  }

  void updateCanvas(std::span<const float> rgb) {
    const GBuffer& g = active_.scene ? active_.scene->gbuffer : scene_->gbuffer;
    // The same transform as render's PNG of the same image: the automatic exposure reads the object pixels.
    // In compare mode A's transform serves both, so that their brightness compares.
    const DisplayTransform display = resolveDisplay(options_.display, rgb, g.objectMask());
    shownExposureEV_ = display.exposureEV;
    // One image, or A and B composed: the same per-pixel loop (tools/viewer/compare_view.h) either way.
    const bool sameScene =
        comparing() && compare_.scene && compare_.scene->gbuffer.pixels.size() == g.pixels.size();
    CompareFrame frame{&g,
                       rgb,
                       sameScene ? std::span<const float>(shownB_) : std::span<const float>(),
                       {},
                       display,
                       options_.background,
                       comparing() ? options_.compareView : CompareView::Flip,
                       divider_,
                       comparing() && flipShowB_};
    if (comparing() && reference_ && active_.generation == referenceGeneration_ &&
        compare_.generation == referenceGeneration_)
      frame.reference = *reference_;
    CompareCanvas canvas = composeCompare(frame);
    canvas_ = std::move(canvas.bgra);
    canvasWidth_ = canvas.width, canvasHeight_ = canvas.height;
  }

  template <typename T>
  void jobLine(const std::unique_ptr<BackgroundJob<T>>& job) {
    if (!job) return;
    // Work that reports no fraction (a renderer build) shows its running time instead of a stuck 0 %.
    const double f = job->progress();
    char text[128];
    if (f > 0.0)
      std::snprintf(text, sizeof text, "%s %d%%", job->what().c_str(), int(100.0 * f));
    else
      std::snprintf(text, sizeof text, "%s (%.1f s)", job->what().c_str(), job->secondsRunning());
    ImGui::ProgressBar(f > 0.0 ? float(f) : float(std::fmod(job->secondsRunning(), 1.0)), ImVec2(-1.0f, 0.0f),
                       text);
  }

  template <typename Info>
  bool combo(const char* label, std::string& value, std::span<const Info> registry,
             const std::string& unset = {}) {
    bool changed = false;
    const std::string shown = value.empty() ? unset : value;
    if (ImGui::BeginCombo(label, shown.c_str())) {
      if (!unset.empty() && ImGui::Selectable(unset.c_str(), value.empty())) value.clear(), changed = true;
      for (const Info& info : registry) {
        if (ImGui::Selectable(info.name.c_str(), info.name == value)) value = info.name, changed = true;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", info.description.c_str());
      }
      ImGui::EndCombo();
    }
    return changed;
  }

  void drawPanel() {
    const float x =
        float(std::max(std::max(canvasWidth_, scene_->gbuffer.width), window_.width() - kPanelWidth));
    ImGui::SetNextWindowPos(ImVec2(std::min(x, float(window_.width() - kPanelWidth)), 0.0f));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(window_.height())));
    ImGui::Begin("iblx", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);

    // Progress first: what a user looks at.
    const Renderer* renderer = active_.renderer.get();
    const double objectPixels = active_.scene ? double(active_.scene->gbuffer.objectPixelCount()) : 0.0;
    const uint64_t spp = renderer ? renderer->samplesPerPixel() : 0;
    ImGui::Text("%s", renderer ? active_.method.label().c_str() : "(no method yet)");
    ImGui::Text("pass %u, %llu spp, %.2f s", passes_, static_cast<unsigned long long>(spp), wallSeconds_);
    // Wall clock only: once the device also draws the window, lavapipe's timestamps around a dispatch no
    // longer enclose its work (measured: 22 us for passes of 18 ms after the first frame), so a GPU figure
    // would lie.
    ImGui::Text("%.2f M samples/s (wall, pass by pass)",
                wallSeconds_ > 0 ? objectPixels * double(spp) / wallSeconds_ * 1e-6 : 0.0);
    if (comparing()) {
      const uint64_t sppB = compare_.renderer ? compare_.renderer->samplesPerPixel() : 0;
      ImGui::Text("B: %s", compare_.renderer ? compare_.method.label().c_str() : "(building)");
      ImGui::Text("B: pass %u, %llu spp, %.2f s", comparePasses_, static_cast<unsigned long long>(sppB),
                  compareWallSeconds_);
    }
    ImGui::Text("device: %s", window_.context().deviceName().c_str());
    if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", error_.c_str());
    jobLine(loadJob_);
    jobLine(buildJob_);
    jobLine(compareBuildJob_);
    if (referenceJob_) ImGui::TextDisabled("after 16 passes, passes wait for the ground truth (below)");
    ImGui::Checkbox("pause", &paused_);
    ImGui::SameLine();
    if (ImGui::Button("restart")) restart();
    ImGui::SameLine();
    if (ImGui::Button("screenshot (F12)")) screenshotRequested_ = true;

    if (ImGui::CollapsingHeader("method", ImGuiTreeNodeFlags_DefaultOpen)) {
      MethodSpec& m = options_.method;
      bool rebuild = combo("method", m.method, methodRegistry());
      const MethodInfo& info = findMethod(m.method);
      if (info.strategy == Strategy::Mis || info.strategy == Strategy::Ris)
        rebuild |= combo("env technique", m.envSampler, envTechniqueRegistry(), "(default)");
      if (info.strategy == Strategy::SingleBrdf || info.strategy == Strategy::Mis ||
          info.strategy == Strategy::Ris || info.strategy == Strategy::ProductMis)
        rebuild |= combo("BRDF technique", m.brdfSampler, brdfTechniqueRegistry(), "(default)");
      rebuild |= combo("sequence", m.sequence, sequenceRegistry());
      if (info.strategy == Strategy::Mis) {
        bool oneSample = m.misEnvFraction.has_value();
        if (ImGui::Checkbox("one-sample MIS", &oneSample)) {
          m.misEnvFraction = oneSample ? std::optional<double>(0.5) : std::nullopt;
          rebuild = true;
        }
        if (oneSample) {
          float fraction = float(m.misEnvFraction.value_or(0.5));
          if (ImGui::SliderFloat("env fraction", &fraction, 0.0f, 1.0f))
            m.misEnvFraction = fraction, rebuild = true;
        }
        bool power = m.misHeuristic == "power";
        if (ImGui::Checkbox("power heuristic", &power))
          m.misHeuristic = power ? "power" : "balance", rebuild = true;
        if (ImGui::Checkbox("compensated env technique", &m.misCompensation)) rebuild = true;
      }
      if (info.strategy == Strategy::ProductMis) {
        bool power = m.misHeuristic == "power";
        if (ImGui::Checkbox("power heuristic", &power))
          m.misHeuristic = power ? "power" : "balance", rebuild = true;
      }
      if (info.strategy == Strategy::Ris) {
        int candidates = m.risCandidates.value_or(8);
        if (ImGui::SliderInt("candidates M", &candidates, 1, kMaxRisCandidates))
          m.risCandidates = candidates, rebuild = true;
      }
      int perPass = int(options_.samplesPerPass);
      if (ImGui::SliderInt("spp per pass", &perPass, 1, 256))
        options_.samplesPerPass = uint32_t(perPass), restart();
      if (rebuild) rebuild_ = true;
    }

    if (ImGui::CollapsingHeader("compare", comparing() ? ImGuiTreeNodeFlags_DefaultOpen : 0)) {
      bool on = comparing();
      if (ImGui::Checkbox("compare with B (equal time)", &on)) {
        if (on) {
          options_.compare = options_.method;
          options_.compare->sequence = options_.method.sequence == "random" ? "sobol" : "random";
        } else {
          options_.compare.reset();
          retired_.retire(compareBuildJob_);
          compare_ = ActiveRenderer();
          shownB_.clear();
        }
        rebuild_ = true;
      }
      if (comparing()) {
        MethodSpec& b = *options_.compare;
        bool rebuild = combo("B method", b.method, methodRegistry());
        rebuild |= combo("B sequence", b.sequence, sequenceRegistry());
        if (rebuild) b.envSampler.clear(), b.brdfSampler.clear(), rebuild_ = true;
        int view = int(options_.compareView);
        for (int k = 0; k < 3; ++k) {
          if (k > 0) ImGui::SameLine();
          ImGui::RadioButton(kCompareViewNames[k], &view, k);
        }
        options_.compareView = CompareView(view);
        if (options_.compareView == CompareView::Split) {
          float divider = float(divider_);
          if (ImGui::SliderFloat("divider", &divider, 0.0f, 1.0f)) divider_ = divider;
          ImGui::TextDisabled("A left, B right; or drag the white line");
        } else if (options_.compareView == CompareView::Flip) {
          if (ImGui::Button(flipShowB_ ? "showing B: flip (F)" : "showing A: flip (F)"))
            flipShowB_ = !flipShowB_;
        } else {
          ImGui::TextDisabled(reference_ ? "A | B; below: their error against the ground truth"
                                         : "A | B; compute the ground truth for their error maps");
        }
      }
    }

    if (ImGui::CollapsingHeader("material", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::TextWrapped("BRDF: %s", scene_->brdf ? scene_->brdf->name.c_str() : "-");
      bool changed = false;
      if (scene_->brdf)
        for (const ParamDecl& p : scene_->brdf->params) {
          auto& v = params_[p.name];
          if (p.type == ParamType::Bool) {
            bool on = v[0] != 0.0;
            if (ImGui::Checkbox(p.name.c_str(), &on)) v[0] = on ? 1.0 : 0.0, changed = true;
          } else if (p.type == ParamType::Color) {
            float c[3] = {float(v[0]), float(v[1]), float(v[2])};
            if (ImGui::ColorEdit3(p.name.c_str(), c, ImGuiColorEditFlags_Float)) {
              for (int k = 0; k < 3; ++k) v[std::size_t(k)] = std::clamp(double(c[k]), p.min, p.max);
              changed = true;
            }
          } else {
            float f = float(v[0]);
            if (ImGui::SliderFloat(p.name.c_str(), &f, float(p.min), float(p.max))) v[0] = f, changed = true;
          }
          if (ImGui::IsItemHovered() && !p.description.empty())
            ImGui::SetTooltip("%s", p.description.c_str());
        }
      if (changed) {
        // New values change the ground truth, not the method: the renderer keeps its tables and shaders.
        const bool wasCurrent = active_.renderer && active_.generation == generation_;
        const bool compareWasCurrent = compare_.renderer && compare_.generation == generation_;
        dropReference();
        try {
          if (active_.renderer) active_.renderer->setParams(params_);
          if (wasCurrent) active_.generation = generation_;
          if (compare_.renderer) compare_.renderer->setParams(params_);  // B shows the same material
          if (compareWasCurrent) compare_.generation = generation_;
        } catch (const std::exception& e) {
          error_ = errorText(e);
        }
        restart();
        if (overlayOn_ && !overlay_.empty()) startRecording(overlay_.pixelX(), overlay_.pixelY());
      }
    }

    if (ImGui::CollapsingHeader("scene", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::TextWrapped("environment: %s", options_.scene.envPath.empty()
                                                ? "(default sky)"
                                                : options_.scene.envPath.string().c_str());
      float rotation = float(options_.scene.envRotationDeg);
      if (ImGui::SliderFloat("env rotation", &rotation, -180.0f, 180.0f, "%.1f deg")) {
        options_.scene.envRotationDeg = rotation;
        sceneChanged();
      }
      const int objectCount = int(std::size(kObjectNames));
      int object = 0;
      for (int k = 0; k < objectCount; ++k) object = options_.scene.object == kObjectNames[k] ? k : object;
      if (ImGui::Combo("object", &object, kObjectNames, objectCount) && options_.scene.object != kObjectNames[object]) {
        options_.scene.object = kObjectNames[object];
        reloadGeometry();
      }
      if (ImGui::Button("open environment...")) browser_.open("environment map", {".exr", ".hdr"});
      ImGui::SameLine();
      if (ImGui::Button("open BRDF...")) browser_.open("BRDF", {".brdf", ".binary", ".bparam"});
      ImGui::SameLine();
      if (ImGui::Button("open OBJ...")) browser_.open("object", {".obj"});
      if (const auto file = browser_.draw()) openFile(*file);
      ImGui::TextDisabled("drag: orbit, wheel: zoom, or drop files on the window");
    }

    if (ImGui::CollapsingHeader("display", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::Checkbox("auto exposure", &options_.display.autoExposure);
      ImGui::SameLine();
      ImGui::TextDisabled("(%+.2f EV shown)", shownExposureEV_);
      float exposure = float(options_.display.exposureEV);
      if (ImGui::SliderFloat(options_.display.autoExposure ? "EV offset" : "exposure (EV)", &exposure, -10.0f,
                             10.0f))
        options_.display.exposureEV = exposure;
      int curve = int(options_.display.tonemap);
      if (ImGui::Combo("tonemap", &curve, kTonemapNames, int(std::size(kTonemapNames))))
        options_.display.tonemap = Tonemap(curve);
      bool srgb = options_.display.gamma <= 0.0;
      if (ImGui::Checkbox("sRGB curve", &srgb)) options_.display.gamma = srgb ? 0.0 : 2.2;
      if (!srgb) {
        float gamma = float(options_.display.gamma);
        if (ImGui::SliderFloat("gamma", &gamma, 1.0f, 3.0f)) options_.display.gamma = gamma;
      }
      ImGui::Checkbox("background", &options_.background);
    }
    ImGui::End();
    drawConvergenceWindow();
  }

  // Below the image: the convergence plot once a ground truth exists.
  void drawConvergenceWindow() {
    const float top = float(std::max(canvasHeight_, scene_->gbuffer.height)) + 4.0f;
    ImGui::SetNextWindowPos(ImVec2(0.0f, top));
    ImGui::SetNextWindowSize(
        ImVec2(float(window_.width() - kPanelWidth), std::max(120.0f, float(window_.height()) - top)));
    ImGui::Begin("analysis", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoTitleBar);
    if (ImGui::BeginTabBar("tabs")) {
      const ImGuiTabItemFlags selectSamples =
          (overlayOn_ && !samplesTabShown_) ? ImGuiTabItemFlags_SetSelected : 0;
      if (ImGui::BeginTabItem("convergence")) {
        if (!reference_ && !referenceJob_) {
          if (ImGui::Button("compute the ground truth")) startReference();
          ImGui::SameLine();
          ImGui::TextDisabled("(cached on disk)");
        }
        jobLine(referenceJob_);
        if (reference_) {
          if (comparing() && !compareCurve_.spp.empty()) {
            std::vector<ConvergenceCurve> both = curves_;
            both.insert(both.end() - (both.empty() ? 0 : 1), compareCurve_);  // A's stays the current (last)
            drawConvergencePlot(both, plot_);
          } else {
            drawConvergencePlot(curves_, plot_);
          }
          if (curves_.size() > 1 && ImGui::Button("clear earlier curves"))
            curves_.erase(curves_.begin(), curves_.end() - 1);
        }
        ImGui::EndTabItem();
      }
      if (ImGui::BeginTabItem("samples", nullptr, selectSamples)) {
        samplesTabShown_ = true;
        drawSamplesTab();
        ImGui::EndTabItem();
      }
      ImGui::EndTabBar();
    }
    ImGui::End();
  }

  void drawSamplesTab() {
    ImGui::Checkbox("overlay: click a pixel of the object", &overlayOn_);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(120.0f);
    ImGui::SliderInt("samples", &overlayCount_, 16, 4096, "%d", ImGuiSliderFlags_Logarithmic);
    jobLine(recordJob_);
    if (overlay_.empty()) {
      ImGui::TextDisabled("no pixel picked yet");
      return;
    }
    ImGui::Text("pixel %d,%d: the first %zu samples of %s", overlay_.pixelX(), overlay_.pixelY(),
                overlay_.sampleCount(), overlay_.methodLabel().c_str());
    ImGui::SameLine();
    if (ImGui::SmallButton("record again")) startRecording(overlay_.pixelX(), overlay_.pixelY());
    const float available = ImGui::GetContentRegionAvail().x;
    const float side = std::min(160.0f, 0.3f * available);
    overlay_.draw(std::min(available - side - 16.0f, 2.0f * (ImGui::GetContentRegionAvail().y - 60.0f)),
                  side);
  }

  ViewerOptions options_;
  ViewerWindow& window_;
  // The scene as loaded with the current camera (never changed once made); snapshotScene adds the rotation
  // and the parameters (params_) for a new renderer or ground truth.
  std::shared_ptr<const Scene> scene_;
  ParamValues params_;
  ActiveRenderer active_;
  std::unique_ptr<BackgroundJob<ActiveRenderer>> buildJob_;
  std::unique_ptr<BackgroundJob<std::vector<float>>> referenceJob_;
  std::optional<std::vector<float>> reference_;
  uint64_t generation_ = 0;           // counts changes of the scene or its parameters (dropReference)
  uint64_t referenceGeneration_ = 0;  // the generation reference_ (or its job) belongs to
  RetiredJobs retired_;
  std::vector<ConvergenceCurve> curves_;
  FileBrowser browser_;
  SampleOverlay overlay_;
  std::unique_ptr<BackgroundJob<Recording>> recordJob_;
  std::unique_ptr<BackgroundJob<LoadedScene>> loadJob_;
  std::optional<std::pair<int, int>> pendingPixel_;  // --overlay: recorded once the first renderer exists
  bool overlayOn_ = false, samplesTabShown_ = false;
  int overlayCount_ = 256;
  std::vector<float> shown_;  // the mean image on screen (read back after each pass)
  std::vector<std::uint8_t> canvas_;
  int canvasWidth_ = 0, canvasHeight_ = 0;
  // Compare mode: B, its build, its counters, its image and its curve; the split view's divider.
  ActiveRenderer compare_;
  std::unique_ptr<BackgroundJob<ActiveRenderer>> compareBuildJob_;
  uint32_t comparePasses_ = 0;
  double compareWallSeconds_ = 0.0;
  std::vector<float> shownB_;
  ConvergenceCurve compareCurve_;
  double divider_ = 0.5;
  bool draggingDivider_ = false, flipShowB_ = false;
  double shownExposureEV_ = 0.0;  // the exposure the last canvas was drawn with (automatic + compensation)
  std::string error_;
  bool rebuild_ = true;
  bool paused_ = false;
  bool screenshotRequested_ = false;
  PlotSettings plot_;
  uint32_t passes_ = 0;
  double wallSeconds_ = 0.0;  // the passes' record + submit + wait, summed
};

ViewerApp* gDropTarget = nullptr;  // GLFW's drop callback has no user pointer of ours to spare

void writeScreenshot(const Screenshot& shot, const std::filesystem::path& path) {
  writePngRgb8(path, shot.width, shot.height, shot.rgb);
  std::printf("wrote %s (%dx%d)\n", path.string().c_str(), shot.width, shot.height);
}

}  // namespace

int runViewer(const ViewerOptions& options) {
  // Validate everything a user can get wrong before a window opens.
  {
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
  ViewerApp app(options, window);
  if (!app.lastError().empty()) throw Error(app.lastError());
  const bool scripted = options.frames > 0;
  if (scripted) app.prepareBlocking(options.reference);
  gDropTarget = &app;
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
      app.requestScreenshot();
    app.handleMouse();
    const bool lastScripted = scripted && app.passes() + 1 >= options.frames;
    const bool wantShot = !options.screenshot.empty() && lastScripted;
    if (const auto shot = app.frame(app.wantsScreenshot() || wantShot)) {
      try {
        writeScreenshot(*shot, screenshotPath);
        screenshotWritten = true;
      } catch (const std::exception& e) {
        if (scripted) throw;
        app.showError(errorText(e));  // an unwritable directory is no reason to close the viewer
      }
      app.clearScreenshotRequest();
    }
    // A scripted run ends with its screenshot; a frame lost to a swapchain rebuild is simply drawn again.
    if (lastScripted && (!wantShot || screenshotWritten)) break;
    if (scripted && frames > options.frames + 100)
      throw Error("the window system presented no frame to read the screenshot from");
  }
  gDropTarget = nullptr;
  if (scripted) {
    if (!app.lastError().empty()) throw Error(app.lastError());
    const ActiveRenderer& active = app.active();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - loopStart).count();
    std::printf("%s: %u passes, %llu spp, %u frames in %.2f s (%.1f frames/s)", active.method.label().c_str(),
                app.passes() - app.comparePasses(),
                static_cast<unsigned long long>(active.renderer ? active.renderer->samplesPerPixel() : 0),
                frames, seconds, seconds > 0.0 ? frames / seconds : 0.0);
    if (const ConvergenceCurve* curve = app.currentCurve(); curve && !curve->mse.empty())
      std::printf(", MSE %.9g, relMSE %.9g", curve->mse.back(), curve->relMse.back());
    std::printf("\n");
    if (const ActiveRenderer& b = app.compareActive(); b.renderer)
      std::printf("B: %s: %u passes, %llu spp\n", b.method.label().c_str(), app.comparePasses(),
                  static_cast<unsigned long long>(b.renderer->samplesPerPixel()));
    // The scripted mode is what CI runs: a validation error there is a failure, not a line on stderr.
    if (const uint32_t errors = window.context().validationErrorCount(); errors > 0)
      throw Error(std::to_string(errors) + " Vulkan validation error(s) during the scripted run (see above)");
  }
  return 0;
}

}  // namespace iblx::viewer
