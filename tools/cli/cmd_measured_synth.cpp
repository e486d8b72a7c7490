// `iblx measured-synth`: tabulates any BRDF (a built-in, a .brdf file, another measured file) into a measured
// format (UTIA .bin, MIT CSAIL .dat, RGL-EPFL .bsdf, ALTA data, MERL .binary) or fits it as an ALTA function
// file
// (.func), evaluating its GLSL part on the GPU at the format's grid, so tests and benchmarks have files of
// every format with known answers (the project ships no foreign measured data).
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/io/merl.h"
#include "engine/io/mit_brdf.h"
#include "engine/io/rgl_bsdf.h"
#include "engine/io/utia.h"
#include "engine/render/alta_func_synth.h"
#include "engine/render/brdf_tabulation.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

namespace iblx::cli {

namespace {

// The flags of `iblx measured-synth`.
struct MeasuredSynthOptions {
  RenderSpec render;  // --brdf, --param and the device flags
  std::string format = "utia";
  std::string out;           // empty: material and the format's extension
  RglSynthLayout rglLayout;  // the parser sets alpha 0: from the BRDF's measured lobe
  bool anisotropic = false;
  AltaParam altaParam = AltaParam::RusinThTdPd;
  AltaOutput altaOutput = AltaOutput::RgbColor;
  bool altaBinary = false;
  std::size_t altaScattered = 0;
  AltaSynthOptions fit;
};

// Declares the flags and parses `args`; none when --help was answered.
std::optional<MeasuredSynthOptions> parseMeasuredSynthOptions(const Args& args) {
  MeasuredSynthOptions options;
  ArgParser parser("measured-synth");
  parser.value(
      "--format", "NAME",
      "utia (.bin: a 6 x 48 x 6 x 48 anisotropic grid, the default), mit (.dat: 18 theta_in x 18 "
      "theta_out x 72 phi_diff x 36 phi_in bins), rgl (.bsdf: RGL-EPFL tensor file, 10 views, 32 x 32 "
      "warps), alta (.data: an ALTA data file), merl (.binary) or alta-func (.func: lambert as an exact "
      "diffuse lobe, any other BRDF as a "
      "rational function over RUSIN_TH_TD_PD fitted by linear least squares)",
      [&](const std::string& v) { options.format = v; });
  parser.value("--brdf", "NAME|FILE",
               "BRDF to tabulate: any --brdf argument, measured files included (default ggx)",
               [&](const std::string& v) { options.render.scene.brdf = v; });
  addParamFlag(parser, options.render.scene.params);
  options.rglLayout.alpha = 0.0;
  parser.toggle("--anisotropic",
                "rgl: tabulate 17 view azimuths (phi_i from -pi to pi) instead of one (an isotropic file)",
                [&] { options.anisotropic = true; });
  parser.value(
      "--rgl-alpha", "A",
      "rgl: GGX width of the file's warps (default: from the BRDF's measured lobe, 0.6 without one)",
      [&](const std::string& v) { options.rglLayout.alpha = parseDouble("--rgl-alpha", v, 1e-3, 4.0); });
  parser.value("--alta-param", "NAME",
               "alta: RUSIN_TH_TD_PD (the default, 24^3 nodes), RUSIN_TH_TD (48^2), ISOTROPIC_TV_TL_DPHI "
               "(24^3), SPHERICAL_TL_PL_TV_PV (12 x 24 x 12 x 24), or any other of ALTA's parametrisations "
               "(20,000 scattered samples)",
               [&](const std::string& v) {
                 const auto p = findAltaParam(v);
                 if (!p) {
                   std::string names;
                   for (AltaParam q : altaParams())
                     names.append(names.empty() ? "" : ", ").append(altaParamName(q));
                   throw Error("--alta-param " + v + ": valid: " + names);
                 }
                 options.altaParam = *p;
               });
  parser.value("--alta-output", "NAME",
               "alta: RGB_COLOR (the default), INV_STERADIAN (grey) or INV_STERADIAN_COSINE_FACTOR (grey, "
               "times cos theta_L)",
               [&](const std::string& v) {
                 if (v == "RGB_COLOR")
                   options.altaOutput = AltaOutput::RgbColor;
                 else if (v == "INV_STERADIAN")
                   options.altaOutput = AltaOutput::InvSteradian;
                 else if (v == "INV_STERADIAN_COSINE_FACTOR")
                   options.altaOutput = AltaOutput::InvSteradianCosine;
                 else
                   throw Error("--alta-output " + v +
                               ": valid: RGB_COLOR, INV_STERADIAN, INV_STERADIAN_COSINE_FACTOR");
               });
  parser.toggle("--alta-binary", "alta: write ALTA's binary stream instead of text",
                [&] { options.altaBinary = true; });
  parser.value("--alta-scattered", "N",
               "alta: N random direction pairs instead of the grid (scattered samples, which iblx resamples)",
               [&](const std::string& v) {
                 options.altaScattered = std::size_t(parseDouble("--alta-scattered", v, 1, 1e7));
               });
  AltaSynthOptions& fit = options.fit;
  parser.value("--fit-degree", "P,Q",
               "alta-func: total degrees of the rational function's numerator and denominator (default 5,5)",
               [&](const std::string& v) {
                 const auto comma = v.find(',');
                 try {
                   std::size_t used = 0;
                   fit.degreeP = std::stoi(v.substr(0, comma), &used);
                   if (comma == std::string::npos || used != comma) throw std::invalid_argument(v);
                   fit.degreeQ = std::stoi(v.substr(comma + 1), &used);
                   if (used != v.size() - comma - 1) throw std::invalid_argument(v);
                 } catch (const std::logic_error&) {
                   throw Error("--fit-degree " + v + ": expected two integers P,Q in [0, 10]");
                 }
                 if (fit.degreeP < 0 || fit.degreeQ < 0 || fit.degreeP > 10 || fit.degreeQ > 10)
                   throw Error("--fit-degree " + v + ": expected two integers P,Q in [0, 10]");
               });
  parser.value("--out", "FILE",
               "output file (default material.bin, .dat, .bsdf, .data, .binary or .func by format)",
               [&](const std::string& v) { options.out = v; });
  addDeviceFlags(parser, options.render);
  if (parser.parseOrShowHelp(args)) return std::nullopt;
  return options;
}

// Tabulates the scene's BRDF into `out` in one of the measured formats (not alta-func); returns the number of
// grid points per channel.
std::size_t tabulateInto(const MeasuredSynthOptions& options, const std::string& out,
                         const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene) {
  const std::string& format = options.format;
  std::size_t entries = 0;
  if (format == "utia") {
    writeUtia(out, tabulateUtia(context, compiler, scene));
    entries = kUtiaEntries;
  } else if (format == "mit") {
    const MitDims dims{18, 18, 72, 36, false};
    writeMitBrdf(out, dims, tabulateMit(context, compiler, scene, dims));
    entries = dims.bins();
  } else if (format == "rgl") {
    RglSynthLayout rglLayout = options.rglLayout;
    if (options.anisotropic) rglLayout.phiViews = 17;
    const RglTables tables = tabulateRgl(context, compiler, scene, rglLayout);
    writeRglBsdf(out, tables);
    entries = tables.rgb.values.size() / 3;
  } else if (format == "alta") {
    const AltaData data = tabulateAltaData(context, compiler, scene, options.altaParam, options.altaOutput,
                                           options.altaScattered);
    writeAltaData(out, data, options.altaBinary);
    entries = data.samples;
  } else if (format == "merl") {
    writeMerl(out, tabulateMerl(context, compiler, scene).values);
    entries = kMerlBins;
  }
  return entries;
}

int runMeasuredSynth(const MeasuredSynthOptions& options) {
  const std::string& format = options.format;
  if (format != "utia" && format != "mit" && format != "rgl" && format != "alta" && format != "merl" &&
      format != "alta-func")
    throw Error("--format " + format + ": unknown; valid: utia, mit, rgl, alta, merl, alta-func");
  const std::string extension = format == "utia"   ? ".bin"
                                : format == "mit"  ? ".dat"
                                : format == "rgl"  ? ".bsdf"
                                : format == "alta" ? ".data"
                                : format == "merl" ? ".binary"
                                                   : ".func";
  const std::string out = options.out.empty() ? "material" + extension : options.out;
  checkTableOutput(out, extension, format);
  const DeviceTableLimit tableLimit = deviceTableLimit(options.render.device);
  LoadedBrdf loaded = loadBrdfArgument(options.render.scene.brdf);
  const std::string brdfName = loaded.info->name;

  const auto start = std::chrono::steady_clock::now();
  const Scene scene = tabulationScene(options.render.scene, std::move(loaded));
  VulkanContext context(
      {options.render.device, options.render.validation ? Validation::On : Validation::Auto});
  ShaderCompiler compiler;
  if (format == "alta-func") {
    const AltaSynthOptions& fit = options.fit;
    const AltaSynthResult result = synthesizeAltaFunc(context, compiler, scene, fit);
    writeAltaFunc(out, result.func);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (result.exact)
      std::printf("wrote %s: %s as an exact ALTA diffuse lobe, %.2f s\n", out.c_str(), brdfName.c_str(),
                  seconds);
    else
      std::printf(
          "wrote %s: %s fitted by an ALTA rational function (Chebyshev, total degrees %d / %d, "
          "RUSIN_TH_TD_PD) at %zu grid points, RMS relative error %.4f, %.2f s\n",
          out.c_str(), brdfName.c_str(), fit.degreeP, fit.degreeQ, result.samples, result.rmsRelative,
          seconds);
    return 0;
  }
  const std::size_t entries = tabulateInto(options, out, context, compiler, scene);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("wrote %s: %s tabulated in the %s layout at %zu grid points per channel, %.2f s\n", out.c_str(),
              brdfName.c_str(), format.c_str(), entries, seconds);
  return 0;
}

}  // namespace

int cmdMeasuredSynth(const Args& args) {
  if (const std::optional<MeasuredSynthOptions> options = parseMeasuredSynthOptions(args))
    return runMeasuredSynth(*options);
  return 0;
}

}  // namespace iblx::cli
