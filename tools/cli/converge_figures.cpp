// The PNG figures of `iblx converge` (tools/cli/converge_figures.h), drawn by engine/analysis
// (loglog_plot.h, heat_map.h).
#include "tools/cli/converge_figures.h"

#include "engine/analysis/heat_map.h"
#include "engine/analysis/loglog_plot.h"
#include "engine/analysis/palette.h"
#include "engine/io/image_write.h"
#include "engine/render/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace iblx::cli {
namespace {

struct Curve {
  std::vector<double> x, y, low, high;
};

// The mean over seeds at each point index that every seed reached, and the seeds' min and max.
Curve seedCurve(const std::vector<const ConvergenceRun*>& runs, bool timeAxis, bool relative) {
  std::size_t points = SIZE_MAX;
  for (const auto* run : runs) points = std::min(points, run->points.size());
  Curve c;
  for (std::size_t i = 0; i < points; ++i) {
    double x = 0, y = 0, low = INFINITY, high = 0;
    for (const auto* run : runs) {
      const auto& p = run->points[i];
      const double e = relative ? p.relMse : p.mse;
      x += timeAxis ? p.wallSeconds : double(p.spp);
      y += e;
      low = std::min(low, e);
      high = std::max(high, e);
    }
    c.x.push_back(x / double(runs.size()));
    c.y.push_back(y / double(runs.size()));
    c.low.push_back(low);
    c.high.push_back(high);
  }
  return c;
}

std::string slug(const std::string& text) {
  std::string s;
  for (char ch : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '.' || ch == '=';
    if (keep)
      s += ch;
    else if (!s.empty() && s.back() != '_')
      s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  return s;
}

}  // namespace

std::vector<std::string> writeConvergencePlots(const std::filesystem::path& dir,
                                               const std::string& sceneTitle,
                                               std::span<const ConvergenceRun> runs,
                                               const ReferenceNoise& noise) {
  // Groups in first-seen order; a method keeps its colour across sequences, later sequences are dashed.
  std::vector<std::pair<std::string, std::string>> order;
  std::map<std::pair<std::string, std::string>, std::vector<const ConvergenceRun*>> groups;
  std::vector<std::string> methods, sequences;
  for (const auto& run : runs) {
    if (run.points.empty()) continue;
    const auto key = std::pair{run.method, run.sequence};
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&run);
    if (std::find(methods.begin(), methods.end(), run.method) == methods.end()) methods.push_back(run.method);
    if (std::find(sequences.begin(), sequences.end(), run.sequence) == sequences.end())
      sequences.push_back(run.sequence);
  }
  std::vector<std::string> written;
  for (const bool relative : {false, true})
    for (const bool timeAxis : {false, true}) {
      LogLogPlot plot;
      const std::string error = relative ? "relMSE" : "MSE";
      plot.title = error + (timeAxis ? " vs time, " : " vs spp, ") + sceneTitle;
      plot.xLabel = timeAxis ? "seconds of rendering" : "samples per pixel";
      plot.yLabel = error + " over object pixels";
      plot.guideSlope = -1.0;
      for (const auto& key : order) {
        const Curve c = seedCurve(groups[key], timeAxis, relative);
        PlotSeries s;
        s.label = key.first + "/" + key.second;
        s.x = c.x;
        s.y = c.y;
        if (groups[key].size() > 1) s.yLow = c.low, s.yHigh = c.high;
        const auto methodIndex =
            std::size_t(std::find(methods.begin(), methods.end(), key.first) - methods.begin());
        s.color = paletteColor(methodIndex);
        s.dashed = key.second != sequences.front();
        plot.series.push_back(std::move(s));
      }
      if (const double floor = relative ? noise.relMse : noise.mse; floor > 0.0) {
        double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
        for (const auto& s : plot.series)
          for (double x : s.x)
            if (x > 0.0 && std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
        if (hi > 0.0) {
          PlotSeries s;
          s.label = "reference noise";
          s.x = {lo, hi};
          s.y = {floor, floor};
          s.color = {150, 150, 150};
          s.dashed = true;
          plot.series.push_back(std::move(s));
        }
      }
      const std::string name =
          std::string(relative ? "relmse" : "mse") + (timeAxis ? "_vs_time.png" : "_vs_spp.png");
      // More than 6 series put the legend outside the axes: the figure widens so the axes keep their size.
      drawLogLogPlot(plot, plot.series.size() > 6 ? 1450 : 1000, 640).writePng(dir / name);
      written.push_back(name);
    }
  return written;
}

std::string imageCaption(const ConvergenceImage& image) {
  char text[256];
  std::snprintf(text, sizeof text, "%s/%s at %llu spp, %.2f s", image.method.c_str(), image.sequence.c_str(),
                static_cast<unsigned long long>(image.point.spp), image.point.wallSeconds);
  return text;
}

std::vector<std::string> writeFinalImages(const std::filesystem::path& dir, const GBuffer& gbuffer,
                                          std::span<const ConvergenceImage> images,
                                          std::span<const float> reference) {
  const DisplayTransform display = resolveDisplay(DisplaySettings{}, reference, gbuffer.objectMask());
  std::vector<std::string> written = {"reference.png"};
  writePng(dir / written.front(), gbuffer.width, gbuffer.height, reference, display);
  for (std::size_t i = 0; i < images.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "final-%02zu-", i + 1);
    const std::string file = name + slug(images[i].method + "-" + images[i].sequence) + ".png";
    writePng(dir / file, gbuffer.width, gbuffer.height, images[i].rgb, display);
    written.push_back(file);
  }
  return written;
}

std::vector<std::string> writeErrorHeatMaps(const std::filesystem::path& dir, const GBuffer& gbuffer,
                                            std::span<const ConvergenceImage> images,
                                            std::span<const float> reference) {
  std::vector<std::vector<double>> errors;
  std::vector<double> all;
  for (const auto& image : images) {
    errors.push_back(relativeSquaredErrorPerPixel(gbuffer, image.rgb, reference));
    for (double e : errors.back())
      if (std::isfinite(e) && e > 0) all.push_back(e);
  }
  // One scale for all maps: from the 99.5th percentile over every method down four decades.
  double high = 1.0;
  if (!all.empty()) {
    const auto k = std::size_t(0.995 * double(all.size() - 1));
    std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(k), all.end());
    high = all[k];
  }
  std::vector<std::string> written;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const auto& image = images[i];
    HeatMap map;
    map.title = imageCaption(image);
    map.width = gbuffer.width;
    map.height = gbuffer.height;
    map.values = errors[i];
    map.low = high * 1e-4;
    map.high = high;
    map.logScale = true;
    map.unit = "(x - r)^2 / (r^2 + 0.01)";
    char name[32];
    std::snprintf(name, sizeof name, "heat-%02zu-", i + 1);
    const std::string file = name + slug(image.method + "-" + image.sequence) + ".png";
    drawHeatMap(map).writePng(dir / file);
    written.push_back(file);
  }
  return written;
}

}  // namespace iblx::cli
