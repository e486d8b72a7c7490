// What the viewer shows and what it was built from, without a window or Dear ImGui: the scene, the renderers
// of methods A and B, the background jobs (scene loads, renderer builds, the ground truth, a pixel's
// samples), the generations that tell current results from stale ones, the images on screen and the
// convergence curves. The panels (viewer_panels.h) change it through its actions; the loop (viewer.cpp) runs
// one frame() per window frame. Tested headless (tests/viewer/viewer_model_test.cpp).
#pragma once

#include "engine/render/renderer.h"
#include "engine/render/sample_recorder.h"
#include "tools/viewer/background_job.h"
#include "tools/viewer/convergence_curve.h"
#include "tools/viewer/viewer.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace iblx::viewer {

// A renderer and the scene and method it was built from (the renderer keeps a reference to the scene).
struct ActiveRenderer {
  std::shared_ptr<const Scene> scene;
  ResolvedMethod method;
  std::unique_ptr<Renderer> renderer;
  uint64_t generation = 0;  // of the scene and parameters it renders (ViewerModel::generation)

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

// The methods the viewer offers: every registry method but the measurement-only ones.
std::vector<MethodInfo> viewerMethods();

// The viewer's words for an engine error: a setting is named by the control that sets it.
std::string errorText(const std::exception& e);

class ViewerModel {
 public:
  // Loads the scene of options.scene on this thread; a failure is kept in error().
  ViewerModel(ViewerOptions options, const VulkanContext& context);
  ~ViewerModel();
  ViewerModel(const ViewerModel&) = delete;
  ViewerModel& operator=(const ViewerModel&) = delete;

  // One frame's work: finished background work is taken over, then one pass of A or B (whichever has
  // rendered for less time: equal time) unless paused, and the images on screen are read back.
  void frame();
  // Scripted mode: finishes the renderer builds (and the ground truth with `withReference`) before any
  // frame, so that N frames are N passes. Throws Error with the message when one fails.
  void prepareBlocking(bool withReference);

  // ---- actions (the panels', the mouse's, a dropped file's)
  // An environment (.exr, .hdr), a BRDF (any --brdf file: by extension, or a measured file recognised by its
  // content) or an object (.obj), read in the
  // background; the current scene stays until it is ready, and stays for good if the file is bad.
  void openFile(const std::filesystem::path& path);
  // The method, sequence or MIS/RIS settings of A or B changed (options().method, options().compare): a
  // rebuild of the renderers.
  void methodChanged() { rebuild_ = true; }
  void setCompare(std::optional<MethodSpec> compare);
  void setSamplesPerPass(uint32_t samplesPerPass);
  // New BRDF parameter values: the renderers keep their tables and shaders; the ground truth goes.
  void setParams(ParamValues params);
  void setEnvRotation(double degrees);
  void setObject(const std::string& object);
  void setCamera(const CameraSpec& camera);
  void startReference();
  // Records the first `count` samples of pixel (x, y) with A's method, in the background.
  void startRecording(int x, int y, std::size_t count);
  void setOverlayFollows(bool on,
                         std::size_t count);  // re-record the overlay's pixel when the method changes
  void clearEarlierCurves();
  // Restarts accumulation (of B too); the current curve restarts too (the earlier methods' curves stay).
  void restart();
  void setPaused(bool paused) { paused_ = paused; }
  void showError(std::string message) { error_ = std::move(message); }

  // ---- state
  ViewerOptions& options() { return options_; }  // display and compare-view fields change freely
  const ViewerOptions& options() const { return options_; }
  const std::shared_ptr<const Scene>& scene() const { return scene_; }
  const ParamValues& params() const { return params_; }
  bool comparing() const { return options_.compare.has_value(); }
  bool paused() const { return paused_; }
  const ActiveRenderer& active() const { return active_; }
  const ActiveRenderer& compareActive() const { return compare_; }
  // The mean images on screen (width*height*3), read back after each pass; empty: nothing rendered yet.
  std::span<const float> shownA() const { return shownA_; }
  std::span<const float> shownB() const { return shownB_; }
  // The object mask of the G-buffer A's image shows, kept until that G-buffer changes.
  std::span<const std::uint8_t> objectMask();
  const GBuffer& shownGBuffer() const;
  // The ground truth, while it belongs to the current scene and parameters.
  const std::optional<std::vector<float>>& reference() const { return reference_; }
  bool referenceMatches(const ActiveRenderer& r) const {
    return reference_ && r.generation == referenceGeneration_;
  }
  const std::vector<ConvergenceCurve>& curves() const { return curves_; }
  const ConvergenceCurve& compareCurve() const { return compareCurve_; }
  const ConvergenceCurve* currentCurve() const { return curves_.empty() ? nullptr : &curves_.back(); }
  // The newest recording of the overlay's pixel, and a count that changes whenever it does.
  const std::optional<Recording>& recording() const { return recording_; }
  uint64_t recordingVersion() const { return recordingVersion_; }
  // A count that changes whenever a new scene (environment) is applied.
  uint64_t sceneVersion() const { return sceneVersion_; }
  uint64_t generation() const { return generation_; }
  const std::string& error() const { return error_; }
  uint32_t passes() const { return passes_; }
  uint32_t comparePasses() const { return comparePasses_; }
  double wallSeconds() const { return wallSeconds_; }
  double compareWallSeconds() const { return compareWallSeconds_; }
  const VulkanContext& context() const { return context_; }
  // The jobs in flight, for progress lines (null when none).
  const BackgroundJob<LoadedScene>* loadJob() const { return loadJob_.get(); }
  const BackgroundJob<ActiveRenderer>* buildJob() const { return buildJob_.get(); }
  const BackgroundJob<ActiveRenderer>* compareBuildJob() const { return compareBuildJob_.get(); }
  const BackgroundJob<std::vector<float>>* referenceJob() const { return referenceJob_.get(); }
  const BackgroundJob<Recording>* recordJob() const { return recordJob_.get(); }

  // While a ground truth computes, A and B render this many passes each, then wait for it.
  static constexpr uint32_t kPassesWhileComputing = 16;

 private:
  bool loadSceneFromSpec();
  void applyScene(std::shared_ptr<const Scene> scene);
  void startLoad(const SceneSpec& spec, const std::string& name);
  void reloadGeometry();
  void dropReference();
  void sceneChanged();
  void rerecordOverlay();
  std::shared_ptr<Scene> snapshotScene() const;
  void startBuild();
  std::unique_ptr<BackgroundJob<ActiveRenderer>> makeBuildJob(const std::shared_ptr<const Scene>& scene,
                                                              const MethodSpec& spec) const;
  void pollJobs();
  void startCurve();
  void recordError(std::span<const float> rgb, const ActiveRenderer& r, double seconds, ConvergenceCurve& c);

  ViewerOptions options_;
  const VulkanContext& context_;
  // The scene as loaded with the current camera (never changed once made); snapshotScene adds the rotation
  // and the parameters (params_) for a new renderer or ground truth.
  std::shared_ptr<const Scene> scene_;
  ParamValues params_;
  ActiveRenderer active_, compare_;
  std::unique_ptr<BackgroundJob<ActiveRenderer>> buildJob_, compareBuildJob_;
  std::unique_ptr<BackgroundJob<std::vector<float>>> referenceJob_;
  std::unique_ptr<BackgroundJob<Recording>> recordJob_;
  std::unique_ptr<BackgroundJob<LoadedScene>> loadJob_;
  RetiredJobs retired_;
  std::optional<std::vector<float>> reference_;
  uint64_t generation_ = 0;           // counts changes of the scene or its parameters (dropReference)
  uint64_t referenceGeneration_ = 0;  // the generation reference_ (or its job) belongs to
  std::vector<ConvergenceCurve> curves_;
  ConvergenceCurve compareCurve_;
  std::optional<Recording> recording_;
  uint64_t recordingVersion_ = 0, sceneVersion_ = 0;
  std::optional<std::pair<int, int>> pendingPixel_;  // --overlay: recorded once the first renderer exists
  bool overlayFollows_ = false;
  std::size_t overlayCount_ = 256;
  std::vector<float> shownA_, shownB_;
  std::shared_ptr<const Scene> maskedScene_;  // the scene objectMask_ was made from
  std::vector<std::uint8_t> objectMask_;
  std::string error_;
  bool rebuild_ = true, paused_ = false;
  uint32_t passes_ = 0, comparePasses_ = 0;
  double wallSeconds_ = 0.0, compareWallSeconds_ = 0.0;  // the passes' record + submit + wait, summed
};

}  // namespace iblx::viewer
