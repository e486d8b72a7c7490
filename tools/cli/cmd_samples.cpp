// `iblx samples`: the samples the integrator draws for one pixel with the chosen method, as CSV (direction,
// lat-long uv, pdf, weight, technique, ...). The integrator records them itself
// (engine/render/sample_recorder.h), so they are the very samples `iblx render` averages for that pixel.
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/render/sample_recorder.h"
#include "engine/render/scene_gpu.h"
#include "engine/scene/brdf_params.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

namespace iblx::cli {

namespace {

constexpr uint32_t kMaxCount = 10'000'000;

constexpr const char* kCsvHeader =
    "index,pass,technique,dir_x,dir_y,dir_z,u,v,pdf,mis_weight,weight_r,weight_g,weight_b,radiance_r,"
    "radiance_g,radiance_b,estimate_r,estimate_g,estimate_b,seq_x,seq_y,product_node_x,product_node_y,"
    "product_node_p\n";

// "X,Y" as two integers; the range is checked against the image later.

// One CSV row. Every value is written as the shortest text that reads back as the same float: the records
// are float, and the derived values (world direction, uv) carry no more precision than that. std::to_chars
// also keeps a million rows to about a second.
class CsvRow {
 public:
  explicit CsvRow(const RecordedSample& s) {
    add(s.index);
    add(s.pass);
    text(s.technique);
    for (double v : {s.direction.x, s.direction.y, s.direction.z, s.uv.x, s.uv.y, s.pdf, s.misWeight,
                     s.weight.x, s.weight.y, s.weight.z, s.radiance.x, s.radiance.y, s.radiance.z,
                     s.estimate.x, s.estimate.y, s.estimate.z, s.point.x, s.point.y})
      add(float(v));
    if (s.productNode) {
      add(s.productNode->column());
      add(s.productNode->row());
      add(float(s.productNode->probability));
    } else {
      *end_++ = ',', *end_++ = ',', *end_++ = ',';  // three empty values
    }
    end_[-1] = '\n';  // the last separator
  }
  std::string_view view() const { return {line_, std::size_t(end_ - line_)}; }

 private:
  template <typename T>
  void add(T value) {
    end_ = std::to_chars(end_, line_ + sizeof line_, value).ptr;
    *end_++ = ',';
  }
  void text(std::string_view value) {
    end_ = std::copy(value.begin(), value.end(), end_);
    *end_++ = ',';
  }
  char line_[1024];  // 4 integers, a registry name and 19 floats of at most 15 characters each
  char* end_ = line_;
};

// The flags of `iblx samples`.
struct SamplesOptions {
  RenderSpec render;      // the scene, the method, --spp, --seed, --out and the device flags
  std::string pixelText;  // --pixel as given: checked before anything runs
  uint32_t count = 1024;
};

// Declares the flags and parses `args`; none when --help or --list-methods was answered.
std::optional<SamplesOptions> parseSamplesOptions(const Args& args) {
  SamplesOptions options;
  RenderSpec& spec = options.render;
  spec.out = "samples.csv";
  ArgParser parser("samples");
  addSceneFlags(parser, spec);
  addMethodFlags(parser, spec);
  addSampleFlags(parser, spec);
  parser.value("--pixel", "X,Y", "the pixel, in pixels of --size from the top-left corner (required)",
               [&](const std::string& v) { options.pixelText = v; });
  parser.value("--count", "N",
               "samples to write, up to 10^7 (default 1024), drawn in passes of --spp from sample 0",
               [&](const std::string& v) { options.count = parseUint("--count", v, 1, kMaxCount); });
  parser.value("--out", "FILE", "the CSV file, or - for standard output (default samples.csv)",
               [&](const std::string& v) { spec.out = v; });
  addDeviceFlags(parser, spec);
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  if (spec.listMethods) {
    printRegistry(spec);
    return std::nullopt;
  }
  return options;
}

// --out: a .csv file in a directory that exists (standard output is "-", not checked).
void checkCsvOutput(const std::string& path) {
  const std::filesystem::path out(path);
  if (out.extension() != ".csv")
    throw Error("--out " + path + ": the samples are CSV; use a .csv file name, or - for standard output");
  if (!out.parent_path().empty() && !std::filesystem::is_directory(out.parent_path()))
    throw Error("--out " + path + ": directory '" + out.parent_path().string() + "' does not exist");
}

// Writes --count samples of the recorder's pixel as CSV, in passes of --spp, to --out (atomically) or
// standard output; returns the sum of their estimates.
glm::dvec3 writeSamplesCsv(SampleRecorder& recorder, const SamplesOptions& options, bool toStdout) {
  const RenderSpec& spec = options.render;
  const uint32_t count = options.count;
  std::optional<AtomicOutput> file;
  if (!toStdout) file.emplace(spec.out);
  std::ostream& csv = toStdout ? std::cout : file->stream();
  csv << kCsvHeader;
  glm::dvec3 estimateSum(0.0);
  for (uint32_t done = 0; done < count;) {
    const uint32_t pass = std::min(spec.samplesPerPass, count - done);
    for (const RecordedSample& s : recorder.runPass(pass)) {
      csv << CsvRow(s).view();
      estimateSum += s.estimate;
    }
    done += pass;
    if (recorder.samplesPerPixel() % (64 * spec.samplesPerPass) == 0)
      progressLine("samples: " + std::to_string(done) + " of " + std::to_string(count));
  }
  endProgressLine();
  if (file) {
    file->commit();
  } else {
    csv.flush();
    if (!csv) throw Error("standard output: write failed");
  }
  return estimateSum;
}

int runSamples(const SamplesOptions& options) {
  const RenderSpec& spec = options.render;
  const std::string& pixelText = options.pixelText;
  const uint32_t count = options.count;

  // Everything a user can get wrong is checked before anything is compiled, run or written.
  if (pixelText.empty())
    throw Error("--pixel X,Y is required: the pixel whose samples are written, e.g. --pixel " +
                std::to_string(spec.scene.width / 2) + "," + std::to_string(spec.scene.height / 2));
  const auto [pixelX, pixelY] = parsePixel("--pixel", pixelText);
  const bool toStdout = spec.out == "-";
  if (!toStdout) checkCsvOutput(spec.out);
  const DeviceTableLimit tableLimit = deviceTableLimit(spec.device);
  LoadedBrdf brdf = loadBrdfArgument(spec.scene.brdf);
  resolveParams(*brdf.info, spec.scene.params);
  const ResolvedMethod method = resolveMethodAndWarn(spec.method, *brdf.info);
  VulkanContext context({spec.device, spec.validation ? Validation::On : Validation::Auto});
  const Scene scene = loadSceneFor(context, spec.scene, std::move(brdf));
  // Coordinates beyond int are outside any image; unrecordablePixel words the message.
  const int x = pixelX < 0 || pixelX >= scene.gbuffer.width ? -1 : int(pixelX);
  const int y = pixelY < 0 || pixelY >= scene.gbuffer.height ? -1 : int(pixelY);
  if (const auto problem = unrecordablePixel(scene.gbuffer, x, y))
    throw Error("--pixel " + pixelText + ": " + *problem);

  ShaderCompiler compiler;
  SampleRecorder recorder(context, compiler, scene, method, spec.seed);
  recorder.start(x, y);
  const glm::dvec3 estimateSum = writeSamplesCsv(recorder, options, toStdout);
  if (const uint32_t bad = recorder.nonFiniteSamples()) warn(nonFiniteEstimatesMessage(bad, spec.scene.brdf));

  // The records' mean and the integrator's own running mean of the pixel agree to float rounding: a check
  // the user sees on every run.
  const glm::dvec3 recordMean = estimateSum / double(count), pixelMean = recorder.pixelMean();
  const uint32_t passes = (count + spec.samplesPerPass - 1) / spec.samplesPerPass;
  std::FILE* report = toStdout ? stderr : stdout;
  std::fprintf(report,
               "%s on %s: %u samples of pixel %d,%d in %u pass%s of up to %u; mean estimate %.6g %.6g %.6g "
               "(the integrator's running mean: %.6g %.6g %.6g)\n",
               method.label().c_str(), context.deviceName().c_str(), count, x, y, passes,
               passes == 1 ? "" : "es", spec.samplesPerPass, recordMean.x, recordMean.y, recordMean.z,
               pixelMean.x, pixelMean.y, pixelMean.z);
  if (!toStdout) std::fprintf(report, "wrote %s\n", spec.out.c_str());
  return 0;
}

}  // namespace

int cmdSamples(const Args& args) {
  if (const std::optional<SamplesOptions> options = parseSamplesOptions(args)) return runSamples(*options);
  return 0;
}

}  // namespace iblx::cli
