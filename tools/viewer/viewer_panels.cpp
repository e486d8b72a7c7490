// The viewer's panels (viewer_panels.h).
#include "tools/viewer/viewer_panels.h"

#include "engine/scene/measured_brdfs.h"

#include "engine/geometry/gbuffer.h"
#include "engine/io/image_write.h"
#include "engine/scene/methods.h"
#include "tools/viewer/compare_view.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

namespace iblx::viewer {
namespace {

template <typename T>
void jobLine(const BackgroundJob<T>* job) {
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

// A registry entry chosen by name, with its description as the tooltip; `unset` offers "(default)".
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

bool powerHeuristicCheckbox(MethodSpec& m) {
  bool power = m.misHeuristic == "power";
  if (!ImGui::Checkbox("power heuristic", &power)) return false;
  m.misHeuristic = power ? "power" : "balance";
  return true;
}

}  // namespace

ViewerPanels::ViewerPanels(const ViewerOptions& options)
    : overlayOn_(options.overlayPixel.has_value()), overlayCount_(int(options.overlayCount)) {}

void ViewerPanels::handleInput(ViewerModel& model) {
  const ImGuiIO& io = ImGui::GetIO();
  if (model.comparing() && !io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F, false))
    flipShowB_ = !flipShowB_;
  if (io.WantCaptureMouse) return;
  const GBuffer& g = model.scene()->gbuffer;
  // A click without a drag (or a right click) on the image picks the overlay's pixel.
  const bool click =
      (ImGui::IsMouseReleased(ImGuiMouseButton_Left) && io.MouseDragMaxDistanceSqr[0] < 9.0f) ||
      ImGui::IsMouseClicked(ImGuiMouseButton_Right);
  if (click && overlayOn_) {
    const int x = int(io.MousePos.x), y = int(io.MousePos.y);
    if (x >= 0 && y >= 0 && x < g.width && y < g.height)
      model.startRecording(x, y, std::size_t(overlayCount_));
  }
  // Split view: a drag that starts on the divider moves it instead of the camera.
  if (model.comparing() && model.options().compareView == CompareView::Split) {
    const double dividerX = divider_ * g.width;
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left))
      draggingDivider_ = std::abs(io.MousePos.x - dividerX) < 6.0 && io.MousePos.y < g.height;
    if (draggingDivider_ && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
      divider_ = std::clamp(double(io.MousePos.x) / g.width, 0.0, 1.0);
      return;
    }
  }
  CameraSpec camera = model.options().scene.camera;
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
    camera.azimuthDeg = std::fmod(camera.azimuthDeg - 0.4 * io.MouseDelta.x + 540.0, 360.0) - 180.0;
    camera.elevationDeg = std::clamp(camera.elevationDeg + 0.4 * io.MouseDelta.y, -89.0, 89.0);
    model.setCamera(camera);
  }
  if (io.MouseWheel != 0.0f) {
    camera.zoom = std::clamp(camera.zoom * std::exp2(0.25 * io.MouseWheel), 0.1, 20.0);
    model.setCamera(camera);
  }
}

void ViewerPanels::draw(ViewerModel& model, const PanelLayout& layout, double shownExposureEV) {
  model.setOverlayFollows(overlayOn_, std::size_t(overlayCount_));
  syncOverlay(model);
  drawSidePanel(model, layout, shownExposureEV);
  drawAnalysisWindow(model, layout);
}

void ViewerPanels::syncOverlay(const ViewerModel& model) {
  if (model.sceneVersion() != overlaySceneVersion_) {
    overlaySceneVersion_ = model.sceneVersion();
    overlay_.setEnvironment(model.scene()->env);
  }
  if (model.recordingVersion() != overlayRecordingVersion_) {
    overlayRecordingVersion_ = model.recordingVersion();
    if (const auto& r = model.recording())
      overlay_.setSamples(r->x, r->y, r->pixel, r->samples, r->methodLabel, r->lobe);
    else
      overlay_.clear();
  }
}

void ViewerPanels::drawSidePanel(ViewerModel& model, const PanelLayout& layout, double shownExposureEV) {
  const float x = float(
      std::max(std::max(layout.canvasWidth, model.scene()->gbuffer.width), layout.windowWidth - kPanelWidth));
  ImGui::SetNextWindowPos(ImVec2(std::min(x, float(layout.windowWidth - kPanelWidth)), 0.0f));
  ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(layout.windowHeight)));
  ImGui::Begin("iblx", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);

  // Progress first: what a user looks at.
  const ActiveRenderer& a = model.active();
  const Renderer* renderer = a.renderer.get();
  const double objectPixels = a.scene ? double(a.scene->gbuffer.objectPixelCount()) : 0.0;
  const uint64_t spp = renderer ? renderer->samplesPerPixel() : 0;
  ImGui::Text("%s", renderer ? a.method.label().c_str() : "(no method yet)");
  ImGui::Text("pass %u, %llu spp, %.2f s", model.passes(), static_cast<unsigned long long>(spp),
              model.wallSeconds());
  // Wall clock only: once the device also draws the window, lavapipe's timestamps around a dispatch no longer
  // enclose its work (measured: 22 us for passes of 18 ms after the first frame), so a GPU figure would lie.
  ImGui::Text("%.2f M samples/s (wall, pass by pass)",
              model.wallSeconds() > 0 ? objectPixels * double(spp) / model.wallSeconds() * 1e-6 : 0.0);
  if (model.comparing()) {
    const ActiveRenderer& b = model.compareActive();
    const uint64_t sppB = b.renderer ? b.renderer->samplesPerPixel() : 0;
    ImGui::Text("B: %s", b.renderer ? b.method.label().c_str() : "(building)");
    ImGui::Text("B: pass %u, %llu spp, %.2f s", model.comparePasses(), static_cast<unsigned long long>(sppB),
                model.compareWallSeconds());
  }
  ImGui::Text("device: %s", model.context().deviceName().c_str());
  if (!model.error().empty())
    ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", model.error().c_str());
  jobLine(model.loadJob());
  jobLine(model.buildJob());
  jobLine(model.compareBuildJob());
  if (model.referenceJob()) ImGui::TextDisabled("after 16 passes, passes wait for the ground truth (below)");
  bool paused = model.paused();
  if (ImGui::Checkbox("pause", &paused)) model.setPaused(paused);
  ImGui::SameLine();
  if (ImGui::Button("restart")) model.restart();
  ImGui::SameLine();
  if (ImGui::Button("screenshot (F12)")) screenshotRequested_ = true;

  drawMethodSection(model);
  drawCompareSection(model);
  drawMaterialSection(model);
  drawSceneSection(model);
  drawDisplaySection(model, shownExposureEV);
  ImGui::End();
}

void ViewerPanels::drawMethodSection(ViewerModel& model) {
  if (!ImGui::CollapsingHeader("method", ImGuiTreeNodeFlags_DefaultOpen)) return;
  MethodSpec& m = model.options().method;
  bool rebuild = combo<MethodInfo>("method", m.method, viewerMethods());
  const StrategyInfo& strategy = findMethod(m.method).strategyInfo();
  if (strategy.envTechniqueChosen)
    rebuild |= combo("env technique", m.envSampler, envTechniqueRegistry(), "(default)");
  if (strategy.usesBrdfTechnique)
    rebuild |= combo("BRDF technique", m.brdfSampler, brdfTechniqueRegistry(), "(default)");
  rebuild |= combo("sequence", m.sequence, sequenceRegistry());
  if (strategy.misSplit) {
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
  }
  if (strategy.misWeights) rebuild |= powerHeuristicCheckbox(m);
  if (strategy.misSplit && ImGui::Checkbox("compensated env technique", &m.misCompensation)) rebuild = true;
  if (strategy.risCandidates) {
    int candidates = m.risCandidates.value_or(8);
    if (ImGui::SliderInt("candidates M", &candidates, 1, kMaxRisCandidates))
      m.risCandidates = candidates, rebuild = true;
  }
  int perPass = int(model.options().samplesPerPass);
  if (ImGui::SliderInt("spp per pass", &perPass, 1, 256)) model.setSamplesPerPass(uint32_t(perPass));
  if (rebuild) model.methodChanged();
}

void ViewerPanels::drawCompareSection(ViewerModel& model) {
  if (!ImGui::CollapsingHeader("compare", model.comparing() ? ImGuiTreeNodeFlags_DefaultOpen : 0)) return;
  bool on = model.comparing();
  if (ImGui::Checkbox("compare with B (equal time)", &on)) {
    std::optional<MethodSpec> b;
    if (on) {
      b = model.options().method;
      b->sequence = model.options().method.sequence == "random" ? "sobol" : "random";
    }
    model.setCompare(std::move(b));
  }
  if (!model.comparing()) return;
  MethodSpec& b = *model.options().compare;
  bool rebuild = combo("B method", b.method, methodRegistry());
  rebuild |= combo("B sequence", b.sequence, sequenceRegistry());
  if (rebuild) b.envSampler.clear(), b.brdfSampler.clear(), model.methodChanged();
  CompareView& compareView = model.options().compareView;
  int view = int(compareView);
  for (int k = 0; k < 3; ++k) {
    if (k > 0) ImGui::SameLine();
    ImGui::RadioButton(kCompareViewNames[k], &view, k);
  }
  compareView = CompareView(view);
  if (compareView == CompareView::Split) {
    float divider = float(divider_);
    if (ImGui::SliderFloat("divider", &divider, 0.0f, 1.0f)) divider_ = divider;
    ImGui::TextDisabled("A left, B right; or drag the white line");
  } else if (compareView == CompareView::Flip) {
    if (ImGui::Button(flipShowB_ ? "showing B: flip (F)" : "showing A: flip (F)")) flipShowB_ = !flipShowB_;
  } else {
    ImGui::TextDisabled(model.reference() ? "A | B; below: their error against the ground truth"
                                          : "A | B; compute the ground truth for their error maps");
  }
}

void ViewerPanels::drawMaterialSection(ViewerModel& model) {
  if (!ImGui::CollapsingHeader("material", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const std::shared_ptr<const Scene>& scene = model.scene();
  ImGui::TextWrapped("BRDF: %s", scene->brdf ? scene->brdf->name.c_str() : "-");
  if (!scene->brdf) return;
  ParamValues params = model.params();
  bool changed = false;
  for (const ParamDecl& p : scene->brdf->params) {
    auto& v = params[p.name];
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
  if (changed) model.setParams(std::move(params));
}

void ViewerPanels::drawSceneSection(ViewerModel& model) {
  if (!ImGui::CollapsingHeader("scene", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const SceneSpec& spec = model.options().scene;
  ImGui::TextWrapped("environment: %s",
                     spec.envPath.empty() ? "(default sky)" : spec.envPath.string().c_str());
  float rotation = float(spec.envRotationDeg);
  if (ImGui::SliderFloat("env rotation", &rotation, -180.0f, 180.0f, "%.1f deg"))
    model.setEnvRotation(rotation);
  const int objectCount = int(std::size(kObjectNames));
  int object = 0;
  for (int k = 0; k < objectCount; ++k) object = spec.object == kObjectNames[k] ? k : object;
  if (ImGui::Combo("object", &object, kObjectNames, objectCount)) model.setObject(kObjectNames[object]);
  if (ImGui::Button("open environment...")) browser_.open("environment map", {".exr", ".hdr"});
  ImGui::SameLine();
  if (ImGui::Button("open BRDF...")) browser_.open("BRDF", brdfFileExtensions());
  ImGui::SameLine();
  if (ImGui::Button("open OBJ...")) browser_.open("object", {".obj"});
  if (const auto file = browser_.draw()) model.openFile(*file);
  ImGui::TextDisabled("drag: orbit, wheel: zoom, or drop files on the window");
}

void ViewerPanels::drawDisplaySection(ViewerModel& model, double shownExposureEV) {
  if (!ImGui::CollapsingHeader("display", ImGuiTreeNodeFlags_DefaultOpen)) return;
  DisplaySettings& display = model.options().display;
  ImGui::Checkbox("auto exposure", &display.autoExposure);
  ImGui::SameLine();
  ImGui::TextDisabled("(%+.2f EV shown)", shownExposureEV);
  float exposure = float(display.exposureEV);
  if (ImGui::SliderFloat(display.autoExposure ? "EV offset" : "exposure (EV)", &exposure, -10.0f, 10.0f))
    display.exposureEV = exposure;
  int curve = int(display.tonemap);
  if (ImGui::Combo("tonemap", &curve, kTonemapNames, int(std::size(kTonemapNames))))
    display.tonemap = Tonemap(curve);
  bool srgb = display.gamma <= 0.0;
  if (ImGui::Checkbox("sRGB curve", &srgb)) display.gamma = srgb ? 0.0 : 2.2;
  if (!srgb) {
    float gamma = float(display.gamma);
    if (ImGui::SliderFloat("gamma", &gamma, 1.0f, 3.0f)) display.gamma = gamma;
  }
  ImGui::Checkbox("background", &model.options().background);
}

void ViewerPanels::drawAnalysisWindow(ViewerModel& model, const PanelLayout& layout) {
  const float top = float(std::max(layout.canvasHeight, model.scene()->gbuffer.height)) + 4.0f;
  ImGui::SetNextWindowPos(ImVec2(0.0f, top));
  ImGui::SetNextWindowSize(
      ImVec2(float(layout.windowWidth - kPanelWidth), std::max(120.0f, float(layout.windowHeight) - top)));
  ImGui::Begin("analysis", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoTitleBar);
  if (ImGui::BeginTabBar("tabs")) {
    const ImGuiTabItemFlags selectSamples =
        (overlayOn_ && !samplesTabShown_) ? ImGuiTabItemFlags_SetSelected : 0;
    if (ImGui::BeginTabItem("convergence")) {
      if (!model.reference() && !model.referenceJob()) {
        if (ImGui::Button("compute the ground truth")) model.startReference();
        ImGui::SameLine();
        ImGui::TextDisabled("(cached on disk)");
      }
      jobLine(model.referenceJob());
      if (model.reference()) {
        std::vector<ConvergenceCurve> curves = model.curves();
        if (model.comparing() && !model.compareCurve().spp.empty())
          curves.insert(curves.end() - (curves.empty() ? 0 : 1), model.compareCurve());  // A's stays last
        drawConvergencePlot(curves, plot_);
        if (model.curves().size() > 1 && ImGui::Button("clear earlier curves")) model.clearEarlierCurves();
      }
      ImGui::EndTabItem();
    }
    if (ImGui::BeginTabItem("samples", nullptr, selectSamples)) {
      samplesTabShown_ = true;
      drawSamplesTab(model);
      ImGui::EndTabItem();
    }
    ImGui::EndTabBar();
  }
  ImGui::End();
}

void ViewerPanels::drawSamplesTab(ViewerModel& model) {
  ImGui::Checkbox("overlay: click a pixel of the object", &overlayOn_);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120.0f);
  ImGui::SliderInt("samples", &overlayCount_, 16, 4096, "%d", ImGuiSliderFlags_Logarithmic);
  jobLine(model.recordJob());
  if (overlay_.empty()) {
    ImGui::TextDisabled("no pixel picked yet");
    return;
  }
  ImGui::Text("pixel %d,%d: the first %zu samples of %s", overlay_.pixelX(), overlay_.pixelY(),
              overlay_.sampleCount(), overlay_.methodLabel().c_str());
  ImGui::SameLine();
  if (ImGui::SmallButton("record again"))
    model.startRecording(overlay_.pixelX(), overlay_.pixelY(), std::size_t(overlayCount_));
  const float available = ImGui::GetContentRegionAvail().x;
  const float side = std::min(160.0f, 0.3f * available);
  const float beside = side + 16.0f + (overlay_.hasProductNodes() ? side + 12.0f : 0.0f);
  overlay_.draw(std::min(available - beside, 2.0f * (ImGui::GetContentRegionAvail().y - 76.0f)), side);
}

}  // namespace iblx::viewer
