// The viewer, tested without a GPU: `iblx view` runs its scripted mode under Xvfb on lavapipe and its
// screenshot is compared with a headless render of the same passes (same method, sequence, seed and spp) put
// through the same display transform. Needs xvfb-run (tools/install.sh installs it).
#include "engine/core/cache_dir.h"
#include "engine/io/image_write.h"
#include "engine/render/metrics.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/render/reference.h"
#include "tools/viewer/sample_overlay.h"
#include "engine/render/renderer.h"

#include <doctest/doctest.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace iblx;

namespace {

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * width + x)]; }
};

Png loadPng(const fs::path& path) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &png.width, &png.height, &channels, 3);
  REQUIRE_MESSAGE(data != nullptr, "cannot read " << path);
  png.rgb.assign(data, data + std::size_t(png.width) * png.height * 3);
  stbi_image_free(data);
  return png;
}

std::string viewCommand(const std::string& args) {
  return "xvfb-run -a -s '-screen 0 1280x1024x24' " + std::string(IBLX_BINARY) + " view " + args;
}

struct CommandResult {
  int status = 0;
  std::string out;
};

CommandResult run(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  REQUIRE(pipe != nullptr);
  CommandResult result;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe.get())) result.out += buffer;
  result.status = pclose(pipe.release());
  return result;
}

// Runs a command and returns its standard output; fails the test on a non-zero exit.
std::string runCapturing(const std::string& command) {
  const CommandResult result = run(command);
  REQUIRE_MESSAGE(result.status == 0, "failed: " << command << "\n" << result.out);
  return result.out;
}

// Runs `iblx view ARGS --frames N --screenshot OUT` under Xvfb and returns the screenshot.
Png viewerScreenshot(const std::string& args, uint32_t frames, const std::string& name) {
  const fs::path out = fs::temp_directory_path() / ("iblx_viewer_test_" + name + ".png");
  fs::remove(out);
  runCapturing(viewCommand(args + " --frames " + std::to_string(frames) + " --screenshot " + out.string()));
  return loadPng(out);
}

// The same passes rendered headless, in display bytes (RGB, top row first).
std::vector<unsigned char> headless(const SceneSpec& sceneSpec, const MethodSpec& methodSpec, uint32_t passes,
                                    uint32_t spp, const DisplaySettings& display) {
  const Scene scene = loadScene(sceneSpec);
  VulkanContext context;
  ShaderCompiler compiler;
  Renderer renderer(context, compiler, scene, resolveMethod(methodSpec, *scene.brdf), 1);
  for (uint32_t p = 0; p < passes; ++p) renderer.runPass(spp);
  const std::vector<float> rgb = renderer.meanRgb();
  // As render's PNG: the automatic exposure of this image's object pixels.
  const DisplayTransform transform = resolveDisplay(display, rgb, scene.gbuffer.objectMask());
  std::vector<unsigned char> bytes(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) bytes[i] = toDisplayByte(rgb[i], transform);
  return bytes;
}

struct Difference {
  int maxDifference = 0;
  double meanObject = 0.0;  // mean code value over object pixels (to see that there is an image at all)
};

Difference compareObjectRegion(const Png& shot, const std::vector<unsigned char>& expected,
                               const Scene& scene) {
  Difference d;
  std::size_t count = 0;
  for (int y = 0; y < scene.gbuffer.height; ++y)
    for (int x = 0; x < scene.gbuffer.width; ++x) {
      const std::size_t p = std::size_t(y) * scene.gbuffer.width + x;
      if (scene.gbuffer.pixels[p].normal.w == 0.0f) continue;
      for (int c = 0; c < 3; ++c) {
        d.maxDifference =
            std::max(d.maxDifference, std::abs(int(shot.at(x, y)[c]) - int(expected[3 * p + c])));
        d.meanObject += shot.at(x, y)[c];
      }
      ++count;
    }
  d.meanObject /= double(3 * count);
  return d;
}

}  // namespace

TEST_CASE("viewer: the scripted screenshot shows the same passes as a headless render") {
  SceneSpec scene;
  scene.width = scene.height = 64;
  struct Run {
    std::string args;
    MethodSpec method;
    DisplaySettings display;
  };
  std::vector<Run> runs;
  runs.push_back({"", MethodSpec{}, DisplaySettings{}});  // the default: automatic exposure, ACES
  MethodSpec hierSobol;
  hierSobol.method = "env-hier", hierSobol.sequence = "sobol";
  runs.push_back({"--method env-hier --seq sobol --auto-exposure off --exposure 1.5 --tonemap reinhard",
                  hierSobol,
                  DisplaySettings{.autoExposure = false, .exposureEV = 1.5, .tonemap = Tonemap::Reinhard}});
  for (const Run& run : runs) {
    CAPTURE(run.args);
    const uint32_t frames = 6, spp = 4;
    const Png shot = viewerScreenshot("--size 64x64 --spp 4 " + run.args, frames, "same");
    CHECK(shot.width >= 64);
    CHECK(shot.height >= 64);
    const Scene loaded = loadScene(scene);
    const Difference d =
        compareObjectRegion(shot, headless(scene, run.method, frames, spp, run.display), loaded);
    CHECK(d.maxDifference <= 1);
    CHECK(d.meanObject > 20.0);  // an image, not the window's grey
    // A different number of passes is a different image: the comparison can tell.
    const Difference other =
        compareObjectRegion(shot, headless(scene, run.method, frames + 3, spp, run.display), loaded);
    CHECK(other.maxDifference > 1);
  }
}

TEST_CASE("viewer: --no-background shows the window's grey around the object") {
  const Png shot = viewerScreenshot("--size 64x64 --no-background", 2, "nobg");
  CHECK(shot.at(0, 0)[0] == 24);
  CHECK(shot.at(0, 0)[1] == 24);
  CHECK(shot.at(0, 0)[2] == 24);
  CHECK(shot.at(32, 32)[0] != 24);  // the sphere's centre
  const Png withBackground = viewerScreenshot("--size 64x64", 2, "bg");
  CHECK(withBackground.at(0, 0)[0] != 24);
}

TEST_CASE("viewer: --reference prints the error of the shown passes against the ground truth") {
  const std::string out = runCapturing(viewCommand("--size 32x32 --method env-cdf --frames 5 --reference"));
  double mse = -1.0, relMse = -1.0;
  const std::size_t at = out.find("MSE ");
  REQUIRE_MESSAGE(at != std::string::npos, out);
  REQUIRE(std::sscanf(out.c_str() + at, "MSE %lf, relMSE %lf", &mse, &relMse) == 2);
  CHECK(out.find("5 passes, 20 spp") != std::string::npos);

  SceneSpec spec;
  spec.width = spec.height = 32;
  const Scene scene = loadScene(spec);
  VulkanContext context;
  ShaderCompiler compiler;
  MethodSpec method;
  method.method = "env-cdf";
  Renderer renderer(context, compiler, scene, resolveMethod(method, *scene.brdf), 1);
  for (int p = 0; p < 5; ++p) renderer.runPass(4);
  const ReferenceImage reference = cachedReference(context, compiler, scene, defaultCacheDir());
  const ErrorMetrics expected = compareToReference(scene.gbuffer, renderer.meanRgb(), reference.rgb);
  CHECK(mse == doctest::Approx(expected.mse).epsilon(1e-6));
  CHECK(relMse == doctest::Approx(expected.relMse).epsilon(1e-6));
  CHECK(mse > 0.0);
}

namespace {

// Pixels of the screenshot below the image (the analysis window) within 40 code values of a colour.
int countNear(const Png& shot, int top, unsigned char r, unsigned char g, unsigned char b) {
  int n = 0;
  for (int y = top; y < shot.height; ++y)
    for (int x = 0; x < shot.width; ++x) {
      const unsigned char* p = shot.at(x, y);
      n += std::abs(p[0] - r) < 40 && std::abs(p[1] - g) < 40 && std::abs(p[2] - b) < 40 ? 1 : 0;
    }
  return n;
}

}  // namespace

TEST_CASE(
    "viewer: the sample overlay draws the picked pixel's samples, one colour per technique, and product "
    "nodes") {
  // MIS draws with both techniques: env-cdf's points are orange, ggx-vndf's blue (techniqueColor 0 and 1).
  const Png overlay = viewerScreenshot("--size 64x64 --overlay 32,24 --overlay-count 512", 2, "overlay");
  const Png plain = viewerScreenshot("--size 64x64", 2, "plain");
  const int orange = countNear(overlay, 64, 255, 110, 80), blue = countNear(overlay, 64, 80, 200, 255);
  CAPTURE(orange);
  CAPTURE(blue);
  CHECK(orange > 100);
  CHECK(blue > 100);
  CHECK(countNear(plain, 64, 255, 110, 80) < 10);
  CHECK(countNear(plain, 64, 80, 200, 255) < 10);
  // A single technique shows one colour only.
  const Png single =
      viewerScreenshot("--size 64x64 --method brdf --overlay 32,24 --overlay-count 512", 2, "single");
  CHECK(countNear(single, 64, 255, 110, 80) > 100);
  CHECK(countNear(single, 64, 80, 200, 255) < 10);
  // `product` also shows the nodes its table chose: blocks of texels outlined on the map and shaded on the
  // table panel, the most probable in kProductNodeColor. MIS chooses no node.
  const Png product =
      viewerScreenshot("--size 64x64 --method product --overlay 32,24 --overlay-count 512", 2, "product");
  const int magenta = countNear(product, 64, 255, 60, 230);
  CAPTURE(magenta);
  CHECK(magenta > 60);
  CHECK(countNear(overlay, 64, 255, 60, 230) < 10);
  // A lobe narrower than a node (alpha 0.05): the table is refined and the draws choose split nodes'
  // children, drawn at their own (smaller) size, so fewer pixels are magenta but some are.
  const Png refined = viewerScreenshot(
      "--size 64x64 --method product --param roughness=0.05 --overlay 32,24 --overlay-count 512", 2,
      "refined");
  const int refinedMagenta = countNear(refined, 64, 255, 60, 230);
  CAPTURE(refinedMagenta);
  CHECK(refinedMagenta > 4);
}

TEST_CASE("viewer: an overlay pixel off the object is refused with the reason") {
  const CommandResult result = run(viewCommand("--size 64x64 --overlay 0,0 --frames 1") + " 2>&1");
  CHECK(result.status != 0);
  CHECK(result.out.find("overlay: pixel 0,0 is background") != std::string::npos);
}

TEST_CASE("sample overlay: the lobe on the disc peaks at the mirror direction, and Lambert's is cos") {
  using viewer::SampleOverlay;
  constexpr int kGrid = SampleOverlay::kLobeGrid;
  VulkanContext context;
  ShaderCompiler compiler;
  SceneSpec spec;
  spec.width = spec.height = 64;
  spec.params = {{"roughness", "0.05"}, {"metallic", "1"}};
  const Scene ggx = loadScene(spec);
  const auto evaluateOn = [&](const Scene& scene) {
    return [&](std::span<const glm::dvec3> wi, std::span<const glm::dvec3> wo) {
      return evaluateBrdf(context, compiler, scene, wi, wo);
    };
  };
  // Off both axes, so that a flip of either disc axis would show.
  for (const auto& [px, py] : {std::pair(32, 32), std::pair(44, 20), std::pair(20, 50), std::pair(54, 40)}) {
    CAPTURE(px);
    CAPTURE(py);
    const gpu::GPixel& pixel = ggx.gbuffer.pixels[std::size_t(py) * 64 + px];
    REQUIRE(pixel.normal.w != 0.0f);
    const std::vector<double> lobe = SampleOverlay::lobeOnDisc(pixel, evaluateOn(ggx));
    const auto peak = std::size_t(std::max_element(lobe.begin(), lobe.end()) - lobe.begin());
    // The mirror direction in the pixel's frame (normal, tangent, n x t), placed as lobeOnDisc places cells.
    const glm::dvec3 n(pixel.normal.x, pixel.normal.y, pixel.normal.z),
        t(pixel.tangent.x, pixel.tangent.y, pixel.tangent.z);
    const glm::dvec3 wo(pixel.view.x, pixel.view.y, pixel.view.z), mirror = 2.0 * glm::dot(n, wo) * n - wo;
    const double mx = glm::dot(mirror, t), my = glm::dot(mirror, glm::cross(n, t));
    const int i = int((mx + 1.0) / 2.0 * kGrid), j = int((1.0 - my) / 2.0 * kGrid);
    CAPTURE(i);
    CAPTURE(j);
    CHECK(std::abs(i - kGrid / 2) + std::abs(j - kGrid / 2) > (px == 32 ? -1 : 4));  // not at the centre
    CHECK(std::abs(int(peak % kGrid) - i) <= 1);
    CHECK(std::abs(int(peak / kGrid) - j) <= 1);
  }
  spec.brdf = "lambert";
  spec.params.clear();
  const Scene lambert = loadScene(spec);
  const gpu::GPixel& pixel = lambert.gbuffer.pixels[std::size_t(32) * 64 + 32];
  const std::vector<double> lobe = SampleOverlay::lobeOnDisc(pixel, evaluateOn(lambert));
  // Cell (i, j) has its centre at disc radius r: f cos = rho/pi sqrt(1 - r^2).
  const auto at = [&](int i, int j) { return lobe[std::size_t(j) * kGrid + i]; };
  const auto radius = [&](int i, int j) {
    const double x = 2.0 * (i + 0.5) / kGrid - 1.0, y = 1.0 - 2.0 * (j + 0.5) / kGrid;
    return std::sqrt(x * x + y * y);
  };
  const int c = kGrid / 2, e = kGrid - 5;
  CHECK(at(c, c) / at(e, c) == doctest::Approx(std::sqrt(1.0 - std::pow(radius(c, c), 2)) /
                                               std::sqrt(1.0 - std::pow(radius(e, c), 2)))
                                   .epsilon(1e-4));
  CHECK(at(0, 0) == -1.0);  // outside the disc
}

namespace {

std::vector<float> headlessRgb(const SceneSpec& sceneSpec, const MethodSpec& methodSpec, uint32_t passes,
                               uint32_t spp) {
  const Scene scene = loadScene(sceneSpec);
  VulkanContext context;
  ShaderCompiler compiler;
  Renderer renderer(context, compiler, scene, resolveMethod(methodSpec, *scene.brdf), 1);
  for (uint32_t p = 0; p < passes; ++p) renderer.runPass(spp);
  return renderer.meanRgb();
}

// "...: N passes" on the line that starts with `prefix`.
uint32_t passesOn(const std::string& out, const std::string& prefix) {
  const std::size_t line = prefix.empty() ? 0 : out.find("\n" + prefix);
  REQUIRE_MESSAGE(line != std::string::npos, out);
  const std::size_t end = out.find('\n', line + 1);
  const std::string text = out.substr(line, end - line);
  const std::size_t at = text.rfind(": ", text.find(" passes"));
  REQUIRE_MESSAGE(at != std::string::npos, text);
  return uint32_t(std::stoul(text.substr(at + 2)));
}

}  // namespace

TEST_CASE("viewer: compare mode renders A and B in turn and shows each where it belongs") {
  SceneSpec scene;
  scene.width = scene.height = 64;
  const Scene loaded = loadScene(scene);
  MethodSpec a, b;
  b.method = "env-hier", b.sequence = "sobol";
  for (const std::string view : {"split", "side"}) {
    CAPTURE(view);
    const fs::path shotPath = fs::temp_directory_path() / ("iblx_viewer_test_compare_" + view + ".png");
    fs::remove(shotPath);
    const std::string out = runCapturing(
        viewCommand("--size 64x64 --spp 4 --compare env-hier --compare-seq sobol --compare-view " + view +
                    " --frames 12 --screenshot " + shotPath.string()));
    const uint32_t passesA = passesOn(out, "mis"), passesB = passesOn(out, "B: ");
    CHECK(passesA + passesB == 12);  // one pass per frame
    CHECK(passesA >= 2);             // both ran: equal time, not one after the other
    CHECK(passesB >= 2);
    const Png shot = loadPng(shotPath);
    const std::vector<float> rgbA = headlessRgb(scene, a, passesA, 4),
                             rgbB = headlessRgb(scene, b, passesB, 4);
    // One display transform for both: A's, as for a single view.
    const DisplayTransform display = resolveDisplay(DisplaySettings{}, rgbA, loaded.gbuffer.objectMask());
    int worstA = 0, worstB = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const std::size_t p = std::size_t(y) * 64 + x;
        if (loaded.gbuffer.pixels[p].normal.w == 0.0f) continue;
        // split: A left of the divider at column 32 (drawn white), B right of it; side: A | B.
        const bool isA = view == "split" ? x < 31 : true;
        const bool isB = view == "split" ? x > 32 : true;
        for (int c = 0; c < 3; ++c) {
          if (isA)
            worstA = std::max(worstA,
                              std::abs(int(shot.at(x, y)[c]) - int(toDisplayByte(rgbA[3 * p + c], display))));
          const int bx = view == "side" ? x + 64 : x;
          if (isB)
            worstB = std::max(
                worstB, std::abs(int(shot.at(bx, y)[c]) - int(toDisplayByte(rgbB[3 * p + c], display))));
        }
      }
    CHECK(worstA <= 1);
    CHECK(worstB <= 1);
    if (view == "split") CHECK(shot.at(32, 32)[0] == 255);  // the divider
  }
}
