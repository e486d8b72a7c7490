// The viewer's Dear ImGui panels over its model (viewer_model.h): the side panel (progress, method, compare,
// material, scene, display), the analysis window under the image (convergence plot, sample overlay), and the
// mouse over the image (orbit, zoom, the overlay's pixel, the split view's divider). What only the UI needs
// (the divider, the flip, the overlay's drawing, the plot's toggles, the file browser) lives here.
#pragma once

#include "tools/viewer/convergence_plot.h"
#include "tools/viewer/file_browser.h"
#include "tools/viewer/sample_overlay.h"
#include "tools/viewer/viewer_model.h"

#include <cstdint>

namespace iblx::viewer {

inline constexpr int kPanelWidth = 360;  // the side panel, to the right of the image

// Where the panels go: the window's size and the canvas (the image, or A and B composed) at its top left.
struct PanelLayout {
  int windowWidth = 0, windowHeight = 0;
  int canvasWidth = 0, canvasHeight = 0;
};

class ViewerPanels {
 public:
  explicit ViewerPanels(const ViewerOptions& options);

  // Keys and the mouse over the image (not over the panels): F flips A and B, a click picks the overlay's
  // pixel, a drag orbits (or moves the split view's divider), the wheel zooms.
  void handleInput(ViewerModel& model);
  // The side panel and the analysis window; `shownExposureEV` is the exposure the canvas was drawn with.
  void draw(ViewerModel& model, const PanelLayout& layout, double shownExposureEV);

  double divider() const { return divider_; }     // split view: the fraction of the width showing A
  bool flipShowsB() const { return flipShowB_; }  // flip view: whether B is shown
  bool wantsScreenshot() const { return screenshotRequested_; }
  void requestScreenshot() { screenshotRequested_ = true; }
  void clearScreenshotRequest() { screenshotRequested_ = false; }

 private:
  void drawSidePanel(ViewerModel& model, const PanelLayout& layout, double shownExposureEV);
  void drawMethodSection(ViewerModel& model);
  void drawCompareSection(ViewerModel& model);
  void drawMaterialSection(ViewerModel& model);
  void drawSceneSection(ViewerModel& model);
  void drawDisplaySection(ViewerModel& model, double shownExposureEV);
  void drawAnalysisWindow(ViewerModel& model, const PanelLayout& layout);
  void drawSamplesTab(ViewerModel& model);
  void syncOverlay(const ViewerModel& model);

  double divider_ = 0.5;
  bool draggingDivider_ = false, flipShowB_ = false;
  bool screenshotRequested_ = false;
  bool overlayOn_ = false, samplesTabShown_ = false;
  int overlayCount_ = 256;
  PlotSettings plot_;
  FileBrowser browser_;
  SampleOverlay overlay_;
  uint64_t overlaySceneVersion_ = ~uint64_t(0), overlayRecordingVersion_ = ~uint64_t(0);
};

}  // namespace iblx::viewer
