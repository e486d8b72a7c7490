// The viewer's model (viewer_model.h).
#include "tools/viewer/viewer_model.h"

#include "engine/scene/measured_brdfs.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/file_names.h"
#include "engine/core/setting.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/render/metrics.h"
#include "engine/render/reference.h"
#include "engine/scene/brdf_params.h"
#include "tools/viewer/sample_overlay.h"

#include <initializer_list>

namespace iblx::viewer {
namespace {

// The control (or, for what only the command line sets, the flag) that sets an engine setting, where its
// label is not the engine's name.
std::string_view settingControl(Setting setting) {
  switch (setting) {
    case Setting::EnvRotation:
      return "env rotation";
    case Setting::BrdfParam:
      return "material parameter";
    case Setting::Orbit:
      return "orbit (drag)";
    case Setting::Zoom:
      return "zoom (wheel)";
    case Setting::ImageSize:
      return "--size";
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
    default:
      return settingName(setting);  // "method", "BRDF technique", ...: the panel's own labels
  }
}

}  // namespace

std::vector<MethodInfo> viewerMethods() {
  std::vector<MethodInfo> offered;
  for (const MethodInfo& m : methodRegistry())
    if (!m.strategyInfo().measurementOnly) offered.push_back(m);
  return offered;
}

std::string errorText(const std::exception& e) {
  if (const auto* setting = dynamic_cast<const SettingError*>(&e))
    return setting->named(settingControl(setting->setting()));
  return e.what();
}

ViewerModel::ViewerModel(ViewerOptions options, const VulkanContext& context)
    : options_(std::move(options)), context_(context) {
  if (loadSceneFromSpec() && options_.reference && options_.frames == 0) startReference();
  overlayCount_ = options_.overlayCount;
  if (options_.overlayPixel) {
    overlayFollows_ = true;
    pendingPixel_ = options_.overlayPixel;
  }
}

ViewerModel::~ViewerModel() {
  for (JobBase* job : std::initializer_list<JobBase*>{referenceJob_.get(), recordJob_.get(), buildJob_.get(),
                                                      compareBuildJob_.get(), loadJob_.get()})
    if (job) job->cancel();
}

void ViewerModel::frame() {
  pollJobs();
  if (rebuild_ && !buildJob_) startBuild();
  // While a ground truth computes (minutes for a real map on lavapipe), passes compete with it for the device
  // and are discarded when it arrives (the curve starts from the first pass): a few give a picture to look
  // at, then they wait.
  const bool computing = referenceJob_ != nullptr;
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
    shownA_ = active_.renderer->meanRgb();
    if (!computing && !curves_.empty()) recordError(shownA_, active_, wallSeconds_, curves_.back());
  } else if (!active_.renderer || active_.renderer->samplesPerPixel() == 0) {
    shownA_.clear();  // restarted, or nothing built yet
  }
  if (!compare_.renderer || compare_.renderer->samplesPerPixel() == 0) shownB_.clear();
}

void ViewerModel::prepareBlocking(bool withReference) {
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

void ViewerModel::openFile(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  SceneSpec next = options_.scene;
  if (ext == ".exr" || ext == ".hdr")
    next.envPath = path;
  else if (ext == ".obj")
    next.object = path.string();
  else if (isBrdfFile(path))  // by extension, or a measured file recognised by its content
    next.brdf = path.string(), next.params.clear();
  else {
    std::string brdfs;
    for (const std::string& e : brdfFileExtensions()) brdfs.append(brdfs.empty() ? "" : ", ").append(e);
    error_ = path.string() + ": not an environment (.exr, .hdr), BRDF (" + brdfs + ") or object (.obj)";
    return;
  }
  startLoad(next, path.filename().string());
}

void ViewerModel::setCompare(std::optional<MethodSpec> compare) {
  options_.compare = std::move(compare);
  if (!comparing()) {
    retired_.retire(compareBuildJob_);
    compare_ = ActiveRenderer();
    shownB_.clear();
  }
  rebuild_ = true;
}

void ViewerModel::setSamplesPerPass(uint32_t samplesPerPass) {
  options_.samplesPerPass = samplesPerPass;
  restart();
}

void ViewerModel::setParams(ParamValues params) {
  params_ = std::move(params);
  // New values change the ground truth, not the method: the renderers keep their tables and shaders.
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
  rerecordOverlay();
}

void ViewerModel::setEnvRotation(double degrees) {
  options_.scene.envRotationDeg = degrees;
  sceneChanged();
}

void ViewerModel::setObject(const std::string& object) {
  if (options_.scene.object == object) return;
  options_.scene.object = object;
  reloadGeometry();
}

void ViewerModel::setCamera(const CameraSpec& camera) {
  options_.scene.camera = camera;
  reloadGeometry();
}

void ViewerModel::startReference() {
  if (referenceJob_) return;
  std::shared_ptr<const Scene> scene = snapshotScene();
  const VulkanContext& context = context_;
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

void ViewerModel::startRecording(int x, int y, std::size_t count) {
  overlayCount_ = count;
  if (const auto why = unrecordablePixel(scene_->gbuffer, x, y)) {
    error_ = "overlay: pixel " + std::to_string(x) + "," + std::to_string(y) + " is " + *why;
    return;
  }
  retired_.retire(recordJob_);
  std::shared_ptr<const Scene> scene = snapshotScene();
  const uint64_t generation = generation_;
  const MethodSpec spec = options_.method;
  const uint32_t seed = options_.seed, perPass = options_.samplesPerPass;
  const VulkanContext& context = context_;
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

void ViewerModel::setOverlayFollows(bool on, std::size_t count) {
  overlayFollows_ = on;
  overlayCount_ = count;
}

void ViewerModel::clearEarlierCurves() {
  if (curves_.size() > 1) curves_.erase(curves_.begin(), curves_.end() - 1);
}

void ViewerModel::restart() {
  if (active_.renderer) active_.renderer->restart(options_.seed);
  if (compare_.renderer) compare_.renderer->restart(options_.seed);
  startCurve();
}

std::span<const std::uint8_t> ViewerModel::objectMask() {
  const std::shared_ptr<const Scene>& shown = active_.scene ? active_.scene : scene_;
  if (shown != maskedScene_) {
    maskedScene_ = shown;
    objectMask_ = shown ? shown->gbuffer.objectMask() : std::vector<std::uint8_t>();
  }
  return objectMask_;
}

const GBuffer& ViewerModel::shownGBuffer() const {
  return active_.scene ? active_.scene->gbuffer : scene_->gbuffer;
}

bool ViewerModel::loadSceneFromSpec() {
  try {
    applyScene(std::make_shared<Scene>(loadScene(options_.scene)));
    return true;
  } catch (const std::exception& e) {
    error_ = errorText(e);
    return false;
  }
}

void ViewerModel::applyScene(std::shared_ptr<const Scene> scene) {
  scene_ = std::move(scene);
  params_ = scene_->params;
  recording_.reset();
  ++recordingVersion_;
  ++sceneVersion_;
  error_.clear();
  sceneChanged();
}

void ViewerModel::startLoad(const SceneSpec& spec, const std::string& name) {
  if (loadJob_) {
    error_ = "still opening the previous file; try again when it is open";
    return;
  }
  loadJob_ = std::make_unique<BackgroundJob<LoadedScene>>("opening " + name, [spec](const auto&) {
    return LoadedScene{spec, std::make_shared<Scene>(loadScene(spec))};
  });
}

void ViewerModel::reloadGeometry() {
  try {
    // options_.scene holds the rotation; the parameters live in params_ (snapshotScene).
    auto next = std::make_shared<Scene>(
        makeScene(scene_->env, options_.scene, LoadedBrdf{scene_->brdf, scene_->measured, scene_->brdfFile}));
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
    rerecordOverlay();
  } catch (const std::exception& e) {
    error_ = errorText(e);
    rebuild_ = true;
  }
}

void ViewerModel::dropReference() {
  ++generation_;
  retired_.retire(referenceJob_);
  reference_.reset();
  curves_.clear();
  compareCurve_ = {};
}

void ViewerModel::sceneChanged() {
  dropReference();
  rebuild_ = true;
}

void ViewerModel::rerecordOverlay() {
  if (overlayFollows_ && recording_) startRecording(recording_->x, recording_->y, overlayCount_);
}

std::shared_ptr<Scene> ViewerModel::snapshotScene() const {
  auto scene = std::make_shared<Scene>(*scene_);
  scene->envRotationDeg = options_.scene.envRotationDeg;
  scene->params = params_;
  return scene;
}

void ViewerModel::startBuild() {
  rebuild_ = false;
  std::shared_ptr<const Scene> scene = snapshotScene();
  buildJob_ = makeBuildJob(scene, options_.method);
  retired_.retire(compareBuildJob_);
  if (comparing()) compareBuildJob_ = makeBuildJob(scene, *options_.compare);
}

std::unique_ptr<BackgroundJob<ActiveRenderer>> ViewerModel::makeBuildJob(
    const std::shared_ptr<const Scene>& scene, const MethodSpec& spec) const {
  const uint32_t seed = options_.seed;
  const uint64_t generation = generation_;
  const VulkanContext& context = context_;
  return std::make_unique<BackgroundJob<ActiveRenderer>>(
      "building the method (tables, shaders)", [scene, spec, seed, generation, &context](const auto&) {
        ActiveRenderer next;
        next.scene = scene, next.method = resolveMethod(spec, *scene->brdf), next.generation = generation;
        ShaderCompiler compiler;
        next.renderer = std::make_unique<Renderer>(context, compiler, *scene, next.method, seed);
        // One warm-up pass here: lavapipe compiles the pipeline on first use, which would otherwise sit in
        // the first pass's time and bend the start of the curve against time (as converge's warm-up avoids).
        next.renderer->runPass(1);
        next.renderer->restart(seed);
        return next;
      });
}

void ViewerModel::pollJobs() {
  finishJob(buildJob_, error_, "", [&](ActiveRenderer result) {
    // Taken even if the scene changed meanwhile (rebuild_: a newer build follows), so the image keeps
    // moving; only a renderer of the current scene counts for the convergence plot (its generation).
    try {
      result.renderer->setParams(params_);  // sliders moved while it was being built
      if (!rebuild_) result.generation = generation_;
      active_ = std::move(result);
      error_.clear();
    } catch (const std::exception& e) {
      if (!rebuild_) error_ = errorText(e);  // else: a build for the previous BRDF, dropped
    }
    // Compare mode: B's accumulation restarts too, or it would keep the head start it took while A built.
    if (comparing())
      restart();
    else
      startCurve();
    // The overlay follows the method: its pixel is recorded again with the new one.
    if (pendingPixel_)
      startRecording(pendingPixel_->first, pendingPixel_->second, overlayCount_), pendingPixel_.reset();
    else
      rerecordOverlay();
  });
  finishJob(compareBuildJob_, error_, "compare: ", [&](ActiveRenderer result) {
    try {
      result.renderer->setParams(params_);
      if (!rebuild_) result.generation = generation_;
      compare_ = std::move(result);
    } catch (const std::exception& e) {
      if (!rebuild_) error_ = errorText(e);
    }
    restart();  // A's accumulation too: equal time from here on, for both
  });
  finishJob(loadJob_, error_, "", [&](LoadedScene result) {
    options_.scene = result.spec;
    applyScene(std::move(result.scene));
  });
  finishJob(recordJob_, error_, "overlay: ", [&](Recording result) {
    if (result.generation == generation_) {  // else a newer recording was or will be started
      recording_ = std::move(result);
      ++recordingVersion_;
    }
  });
  retired_.collect();
  finishJob(referenceJob_, error_, "ground truth: ", [&](std::vector<float> result) {
    reference_ = std::move(result);
    restart();  // the curve starts at the first pass
  });
}

void ViewerModel::startCurve() {
  // A curve covers passes from the first.
  passes_ = comparePasses_ = 0, wallSeconds_ = compareWallSeconds_ = 0.0;
  compareCurve_ = {};
  if (reference_ && compare_.renderer) compareCurve_.label = "B: " + compare_.method.label();
  if (!reference_ || !active_.renderer) return;
  const std::string label = active_.method.label();
  if (!curves_.empty() && curves_.back().label == label) curves_.pop_back();
  curves_.push_back({label, {}, {}, {}, {}});
  constexpr std::size_t kMaxCurves = 6;  // the current one and five for comparison
  if (curves_.size() > kMaxCurves) curves_.erase(curves_.begin());
}

void ViewerModel::recordError(std::span<const float> rgb, const ActiveRenderer& r, double seconds,
                              ConvergenceCurve& c) {
  if (!reference_ || c.label.empty() || !r.renderer || r.generation != referenceGeneration_) return;
  const ErrorMetrics e = compareToReference(r.scene->gbuffer, rgb, *reference_);
  c.spp.push_back(double(r.renderer->samplesPerPixel()));
  c.seconds.push_back(seconds);
  c.mse.push_back(e.mse);
  c.relMse.push_back(e.relMse);
}

}  // namespace iblx::viewer
