// `iblx view`: the desktop viewer's flags (the scene, method and display flags of `iblx render`, plus the
// scripted mode used by CI under Xvfb); the viewer itself is tools/viewer/.
#include "engine/core/error.h"
#include "engine/render/convergence_runner.h"
#include "engine/scene/methods.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"
#include "tools/viewer/viewer.h"

#include <cstdio>
#include <optional>
#include <string>

namespace iblx::cli {

namespace {

// Declares the flags and parses `args` into the viewer's options; none when --help or --list-methods was
// answered.
std::optional<viewer::ViewerOptions> parseViewOptions(const Args& args) {
  RenderSpec spec;
  spec.samplesPerPass = 4;
  viewer::ViewerOptions options;
  ArgParser parser("view");
  addSceneFlags(parser, spec);
  addMethodFlags(parser, spec);
  parser.value("--spp", "N", "samples per pixel per pass, i.e. per frame, up to 4096 (default 4)",
               [&](const std::string& v) { spec.samplesPerPass = parseUint("--spp", v, 1, 4096); });
  parser.value("--seed", "N", "seed of the sample sequences (default 1)",
               [&](const std::string& v) { spec.seed = parseUint("--seed", v, 0, 0xffffffffu); });
  addDisplayFlags(parser, options.display);
  parser.toggle("--no-background", "show the background in grey instead of the environment",
                [&] { options.background = false; });
  parser.value("--frames", "N", "scripted mode: render N frames (one pass each), then exit",
               [&](const std::string& v) { options.frames = parseUint("--frames", v, 1, 1u << 20); });
  parser.value("--screenshot", "FILE.png",
               "PNG of the window after the last scripted frame; also where F12 and the panel's button write "
               "(default iblx-view.png)",
               [&](const std::string& v) {
                 checkImagePath("--screenshot", v);
                 options.screenshot = v;
               });
  parser.toggle(
      "--reference",
      "compute the ground truth (or read it from the cache) at start, for the convergence panel; in "
      "scripted mode before the first frame, and the final MSE and relMSE are printed",
      [&] { options.reference = true; });
  parser.value(
      "--overlay", "X,Y",
      "show the samples of pixel X,Y (image coordinates) on the environment map and the hemisphere",
      [&](const std::string& v) {
        const auto [x, y] = parsePixel("--overlay", v);
        if (x < 0 || y < 0 || x >= (1 << 16) || y >= (1 << 16))
          throw Error("--overlay " + v + ": outside any image (coordinates from 0 at the top-left corner)");
        options.overlayPixel = std::pair(int(x), int(y));
      });
  parser.value(
      "--overlay-count", "N", "samples shown by the overlay (16-4096, default 256)",
      [&](const std::string& v) { options.overlayCount = parseUint("--overlay-count", v, 16, 4096); });
  std::string compareSequence;
  parser.value("--compare", "METHOD[:OPTION]...",
               "compare mode: also render this method (words as converge --method), in turn at equal time",
               [&](const std::string& v) { options.compare = parseMethodVariant(v); });
  parser.value("--compare-seq", "NAME", "compare mode: B's sequence (default: the same as --seq)",
               [&](const std::string& v) {
                 (void)findSequence(v);
                 compareSequence = v;
               });
  parser.value("--compare-view", "split|side|flip",
               "compare mode: split (default: A left, B right of a divider), side (A | B, error maps below "
               "with --reference) or flip",
               [&](const std::string& v) {
                 for (std::size_t i = 0; i < std::size(viewer::kCompareViewNames); ++i)
                   if (v == viewer::kCompareViewNames[i]) {
                     options.compareView = viewer::CompareView(i);
                     return;
                   }
                 throw Error("--compare-view " + v + ": expected split, side or flip");
               });
  addDeviceFlags(parser, spec);
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (!compareSequence.empty() && !options.compare)
    throw Error("--compare-seq " + compareSequence + ": needs --compare METHOD");
  if (options.compare)
    options.compare->sequence = compareSequence.empty() ? spec.method.sequence : compareSequence;
  if (spec.listMethods) {
    printRegistry(spec);
    return std::nullopt;
  }
  options.scene = spec.scene;
  options.method = spec.method;
  options.samplesPerPass = spec.samplesPerPass;
  options.seed = spec.seed;
  options.device = spec.device;
  options.validation = spec.validation;
  return options;
}

int runView(const viewer::ViewerOptions& options) {
  if (!options.screenshot.empty() && options.screenshot.extension() != ".png")
    throw Error("--screenshot " + options.screenshot.string() + ": the file name must end in .png");
  if (options.overlayPixel) {
    const auto [x, y] = *options.overlayPixel;
    if (x >= options.scene.width || y >= options.scene.height)
      throw Error("--overlay " + std::to_string(x) + "," + std::to_string(y) + ": outside the " +
                  std::to_string(options.scene.width) + "x" + std::to_string(options.scene.height) +
                  " image");
  }
  return viewer::runViewer(options);
}

}  // namespace

int cmdView(const Args& args) {
  if (const std::optional<viewer::ViewerOptions> options = parseViewOptions(args)) return runView(*options);
  return 0;
}

}  // namespace iblx::cli
