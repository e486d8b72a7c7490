// `iblx view`: the desktop viewer. The object converges pass by pass in a window; method, sequence, samples
// per pass, MIS settings, BRDF parameters and display settings switch live from a Dear ImGui panel, and any
// change restarts the accumulation. A scripted mode (--frames, --screenshot) runs it unattended, e.g. under
// Xvfb.
#pragma once

#include "engine/io/image_write.h"
#include "engine/scene/scene.h"
#include "tools/viewer/compare_view.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <utility>
#include <string>

namespace iblx::viewer {

struct ViewerOptions {
  SceneSpec scene;
  MethodSpec method;
  uint32_t samplesPerPass = 4;
  uint32_t seed = 1;
  DisplaySettings display;
  bool background = true;
  std::string device;
  bool validation = false;
  // Scripted mode: with frames > 0 the viewer renders exactly that many frames (one pass each), writes the
  // screenshot (if a path is given) of the last one and exits.
  uint32_t frames = 0;
  // Compute the ground truth (or read it from the cache) at start; the scripted mode waits for it and prints
  // the final MSE and relMSE.
  bool reference = false;
  // The sample overlay: the pixel whose samples are shown (set: the overlay is on from the start) and how
  // many.
  std::optional<std::pair<int, int>> overlayPixel;
  uint32_t overlayCount = 256;
  std::filesystem::path screenshot;  // also the file name used by F12 and the menu (default iblx-view.png)
  // Compare mode: a second method B (or the same method with another sequence or setting) rendered in turn
  // with the first at equal time, shown as compareView.
  std::optional<MethodSpec> compare;
  CompareView compareView = CompareView::Split;
};

// Runs the viewer until its window is closed (or the scripted frames are done). Returns the exit code.
int runViewer(const ViewerOptions& options);

}  // namespace iblx::viewer
