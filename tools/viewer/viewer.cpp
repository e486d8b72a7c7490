// `iblx view` (viewer.h): the viewer's state, its ImGui panel and the frame loop. Every control edits a copy of
// the scene and method specs; a change that the running renderer cannot absorb (method, sequence, object,
// camera, environment rotation or file) rebuilds it, and every change restarts the accumulation.
#include "tools/viewer/viewer.h"

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/io/brdf_file.h"
#include "engine/render/methods.h"
#include "engine/render/renderer.h"
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

constexpr int kPanelWidth = 360;  // the ImGui panel to the right of the image

// Everything the viewer shows, and what it was built from.
class ViewerApp {
 public:
  ViewerApp(ViewerOptions options, ViewerWindow& window) : options_(std::move(options)), window_(window) {
    loadSceneFromSpec();
  }

  // One frame: the panel, one pass, the canvas. Returns the presented image when readback is asked.
  // The pass runs before the panel is drawn, so the panel's figures describe the image shown with them; what
  // the panel changes takes effect in the next frame.
  std::optional<Screenshot> frame(bool readback) {
    if (rebuild_) rebuildRenderer();
    if (renderer_ && !paused_) {
      const PassTiming t = renderer_->runPass(options_.samplesPerPass);
      wallSeconds_ += t.wallSeconds, gpuSeconds_ += t.gpuSeconds;
      ++passes_;
    }
    updateCanvas();
    drawPanel();
    auto shot = window_.endFrame(canvas_, scene_.gbuffer.width, scene_.gbuffer.height, readback);
    if (screenshotRequested_ && !readback) screenshotRequested_ = false;
    return shot;
  }

  bool wantsScreenshot() const { return screenshotRequested_; }
  void clearScreenshotRequest() { screenshotRequested_ = false; }
  void requestScreenshot() { screenshotRequested_ = true; }
  const std::string& lastError() const { return error_; }

  // Mouse orbit and wheel zoom over the image (not over the panel).
  void handleMouse() {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureMouse) return;
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
      CameraSpec& camera = options_.scene.camera;
      camera.azimuthDeg = std::fmod(camera.azimuthDeg - 0.4 * io.MouseDelta.x + 540.0, 360.0) - 180.0;
      camera.elevationDeg = std::clamp(camera.elevationDeg + 0.4 * io.MouseDelta.y, -89.0, 89.0);
      reloadGeometry();
    }
    if (io.MouseWheel != 0.0f) {
      options_.scene.camera.zoom = std::clamp(options_.scene.camera.zoom * std::exp2(0.25 * io.MouseWheel), 0.1, 20.0);
      reloadGeometry();
    }
  }

  // A file dropped on the window: an environment map, a BRDF or an object.
  void openFile(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    SceneSpec next = options_.scene;
    if (ext == ".exr" || ext == ".hdr")
      next.envPath = path;
    else if (ext == ".brdf" || ext == ".binary" || ext == ".bparam")
      next.brdf = path.string(), next.params.clear();
    else if (ext == ".obj")
      next.object = path.string();
    else {
      error_ = path.string() + ": not an environment (.exr, .hdr), BRDF (.brdf, .binary, .bparam) or object (.obj)";
      return;
    }
    const SceneSpec previous = options_.scene;
    options_.scene = next;
    if (!loadSceneFromSpec()) options_.scene = previous, loadSceneFromSpec();
  }

 private:
  // (Re)loads the scene from options_.scene; on failure keeps the message and returns false.
  bool loadSceneFromSpec() {
    try {
      Scene scene = loadScene(options_.scene);
      scene_ = std::move(scene);
      params_ = scene_.params;
      error_.clear();
      rebuild_ = true;
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }

  // Camera changes: only the G-buffer (the environment stays loaded).
  void reloadGeometry() {
    try {
      SceneSpec spec = options_.scene;
      Scene next = makeScene(scene_.env, spec, LoadedBrdf{scene_.brdf, scene_.measured, scene_.brdfFile});
      next.params = params_;
      scene_ = std::move(next);
      rebuild_ = true;
    } catch (const std::exception& e) {
      error_ = e.what();
    }
  }

  void rebuildRenderer() {
    rebuild_ = false;
    renderer_.reset();
    try {
      scene_.envRotationDeg = options_.scene.envRotationDeg;
      method_ = resolveMethod(options_.method, *scene_.brdf);
      renderer_ = std::make_unique<Renderer>(window_.context(), compiler_, scene_, method_, options_.seed);
      renderer_->setParams(params_);
      error_.clear();
    } catch (const std::exception& e) {
      error_ = e.what();
    }
    restartCounters();
  }

  void restartCounters() { passes_ = 0, wallSeconds_ = gpuSeconds_ = 0.0; }

  void restart() {
    if (renderer_) renderer_->restart(options_.seed);
    restartCounters();
  }

  void updateCanvas() {
    const GBuffer& g = scene_.gbuffer;
    canvas_.assign(std::size_t(g.width) * g.height * 4, 0);
    std::vector<float> rgb;
    if (renderer_ && renderer_->samplesPerPixel() > 0) rgb = renderer_->meanRgb();
    for (std::size_t p = 0; p < std::size_t(g.width) * g.height; ++p) {
      std::uint8_t* out = &canvas_[4 * p];
      out[3] = 255;
      const bool object = g.pixels[p].normal.w != 0.0f;
      if (rgb.empty() || (!object && !options_.background)) {
        out[0] = out[1] = out[2] = 24;  // the window's own background
        continue;
      }
      out[2] = toDisplayByte(rgb[3 * p + 0], options_.display);  // BGRA
      out[1] = toDisplayByte(rgb[3 * p + 1], options_.display);
      out[0] = toDisplayByte(rgb[3 * p + 2], options_.display);
    }
  }

  template <typename Info>
  bool combo(const char* label, std::string& value, std::span<const Info> registry, const std::string& unset = {}) {
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
    const float x = float(std::max(scene_.gbuffer.width, window_.width() - kPanelWidth));
    ImGui::SetNextWindowPos(ImVec2(std::min(x, float(window_.width() - kPanelWidth)), 0.0f));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(window_.height())));
    ImGui::Begin("iblx", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);

    // Progress first: what a user looks at.
    const double objectPixels = double(scene_.gbuffer.objectPixelCount());
    const uint64_t spp = renderer_ ? renderer_->samplesPerPixel() : 0;
    ImGui::Text("%s", renderer_ ? method_.label().c_str() : "(no method)");
    ImGui::Text("pass %u, %llu spp, %.2f s", passes_, static_cast<unsigned long long>(spp), wallSeconds_);
    ImGui::Text("%.2f M samples/s (%.2f M/s GPU)", wallSeconds_ > 0 ? objectPixels * double(spp) / wallSeconds_ * 1e-6 : 0.0,
                gpuSeconds_ > 0 ? objectPixels * double(spp) / gpuSeconds_ * 1e-6 : 0.0);
    ImGui::Text("device: %s", window_.context().deviceName().c_str());
    if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", error_.c_str());
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
      if (info.strategy == Strategy::SingleBrdf || info.strategy == Strategy::Mis || info.strategy == Strategy::Ris)
        rebuild |= combo("BRDF technique", m.brdfSampler, brdfTechniqueRegistry(), "(default)");
      rebuild |= combo("sequence", m.sequence, sequenceRegistry());
      if (info.strategy == Strategy::Mis) {
        float fraction = float(m.misEnvFraction.value_or(0.5));
        if (ImGui::SliderFloat("env fraction", &fraction, 0.0f, 1.0f)) m.misEnvFraction = fraction, rebuild = true;
        bool power = m.misHeuristic == "power";
        if (ImGui::Checkbox("power heuristic", &power)) m.misHeuristic = power ? "power" : "balance", rebuild = true;
        if (ImGui::Checkbox("compensated env technique", &m.misCompensation)) rebuild = true;
      }
      if (info.strategy == Strategy::Ris) {
        int candidates = m.risCandidates.value_or(8);
        if (ImGui::SliderInt("candidates M", &candidates, 1, kMaxRisCandidates)) m.risCandidates = candidates, rebuild = true;
      }
      int perPass = int(options_.samplesPerPass);
      if (ImGui::SliderInt("spp per pass", &perPass, 1, 256)) options_.samplesPerPass = uint32_t(perPass), restart();
      if (rebuild) rebuild_ = true;
    }

    if (ImGui::CollapsingHeader("material", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::TextWrapped("BRDF: %s", scene_.brdf ? scene_.brdf->name.c_str() : "-");
      bool changed = false;
      if (scene_.brdf)
        for (const ParamDecl& p : scene_.brdf->params) {
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
          if (ImGui::IsItemHovered() && !p.description.empty()) ImGui::SetTooltip("%s", p.description.c_str());
        }
      if (changed && renderer_) {
        try {
          renderer_->setParams(params_);
          scene_.params = params_;
          restartCounters();
        } catch (const std::exception& e) {
          error_ = e.what();
        }
      }
    }

    if (ImGui::CollapsingHeader("scene", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::TextWrapped("environment: %s", options_.scene.envPath.empty() ? "(default sky)"
                                                                            : options_.scene.envPath.string().c_str());
      float rotation = float(options_.scene.envRotationDeg);
      if (ImGui::SliderFloat("env rotation", &rotation, -180.0f, 180.0f, "%.1f deg")) {
        options_.scene.envRotationDeg = rotation;
        rebuild_ = true;
      }
      static const char* objects[] = {"sphere", "plane", "teapot"};
      int object = 0;
      for (int k = 0; k < 3; ++k) object = options_.scene.object == objects[k] ? k : object;
      if (ImGui::Combo("object", &object, objects, 3) && options_.scene.object != objects[object]) {
        options_.scene.object = objects[object];
        reloadGeometry();
      }
      ImGui::TextDisabled("drag: orbit, wheel: zoom, drop files: .exr .hdr .brdf .binary .bparam .obj");
    }

    if (ImGui::CollapsingHeader("display", ImGuiTreeNodeFlags_DefaultOpen)) {
      float exposure = float(options_.display.exposureEV);
      if (ImGui::SliderFloat("exposure (EV)", &exposure, -10.0f, 10.0f)) options_.display.exposureEV = exposure;
      static const char* curves[] = {"clamp", "Reinhard", "ACES (fit)"};
      int curve = int(options_.display.tonemap);
      if (ImGui::Combo("tonemap", &curve, curves, 3)) options_.display.tonemap = Tonemap(curve);
      bool srgb = options_.display.gamma <= 0.0;
      if (ImGui::Checkbox("sRGB curve", &srgb)) options_.display.gamma = srgb ? 0.0 : 2.2;
      if (!srgb) {
        float gamma = float(options_.display.gamma);
        if (ImGui::SliderFloat("gamma", &gamma, 1.0f, 3.0f)) options_.display.gamma = gamma;
      }
      ImGui::Checkbox("background", &options_.background);
    }
    ImGui::End();
  }

  ViewerOptions options_;
  ViewerWindow& window_;
  ShaderCompiler compiler_;
  Scene scene_;
  ParamValues params_;
  ResolvedMethod method_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<std::uint8_t> canvas_;
  std::string error_;
  bool rebuild_ = true;
  bool paused_ = false;
  bool screenshotRequested_ = false;
  uint32_t passes_ = 0;
  double wallSeconds_ = 0.0, gpuSeconds_ = 0.0;
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
  }
  const int width = options.scene.width + kPanelWidth, height = std::max(options.scene.height, 560);
  ViewerWindow window("iblx view", width, height,
                      {options.device, options.validation ? Validation::On : Validation::Auto});
  ViewerApp app(options, window);
  if (!app.lastError().empty()) throw Error(app.lastError());
  gDropTarget = &app;
  glfwSetDropCallback(window.handle(), [](GLFWwindow*, int count, const char** paths) {
    if (gDropTarget && count > 0) gDropTarget->openFile(paths[count - 1]);
  });
  const std::filesystem::path screenshotPath = options.screenshot.empty() ? "iblx-view.png" : options.screenshot;
  uint32_t frame = 0;
  while (window.beginFrame()) {
    // Dear ImGui 1.86 indexes keys by the backend's codes (GLFW's here).
    if (!ImGui::GetIO().WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F12, false)) app.requestScreenshot();
    app.handleMouse();
    ++frame;
    const bool lastScripted = options.frames > 0 && frame >= options.frames;
    const bool readback = app.wantsScreenshot() || (lastScripted && !options.screenshot.empty());
    if (const auto shot = app.frame(readback)) {
      writeScreenshot(*shot, screenshotPath);
      app.clearScreenshotRequest();
    }
    if (lastScripted) break;
  }
  gDropTarget = nullptr;
  if (options.frames > 0 && !app.lastError().empty()) throw Error(app.lastError());
  // The scripted mode is what CI runs: a validation error there is a failure, not a line on stderr.
  if (const uint32_t errors = window.context().validationErrorCount(); options.frames > 0 && errors > 0)
    throw Error(std::to_string(errors) + " Vulkan validation error(s) during the scripted run (see above)");
  return 0;
}

}  // namespace iblx::viewer
