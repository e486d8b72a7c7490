// Flag parsing for all subcommands.
#include "tools/cli/cli_options.h"

#include "engine/io/env_image.h"

#include "engine/core/error.h"
#include "engine/core/file_names.h"
#include "engine/core/log.h"
#include "tools/cli/registry_listing.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace iblx::cli {

void ArgParser::value(const std::string& flag, const std::string& metavar, const std::string& help,
                      std::function<void(const std::string&)> apply) {
  options_.push_back({flag, metavar, help, std::move(apply), true});
}

void ArgParser::toggle(const std::string& flag, const std::string& help, std::function<void()> apply) {
  options_.push_back({flag, "", help, [apply](const std::string&) { apply(); }, false});
}

void ArgParser::parse(const std::vector<std::string>& args) const {
  for (size_t i = 0; i < args.size(); ++i) {
    std::string flag = args[i], text;
    bool inlineValue = false;
    if (auto eq = flag.find('='); flag.rfind("--", 0) == 0 && eq != std::string::npos) {
      text = flag.substr(eq + 1);
      flag = flag.substr(0, eq);
      inlineValue = true;
    }
    const Option* option = nullptr;
    for (const auto& o : options_)
      if (o.flag == flag) option = &o;
    if (!option) {
      if (flag.rfind("-", 0) != 0)
        throw Error("iblx " + command_ + ": unexpected argument '" + flag + "' (see iblx " + command_ +
                    " --help)");
      throw Error("iblx " + command_ + ": unknown flag '" + flag + "' (see iblx " + command_ + " --help)");
    }
    if (option->takesValue && !inlineValue) {
      if (i + 1 >= args.size()) throw Error(flag + " needs a value (" + option->metavar + ")");
      text = args[++i];
    } else if (!option->takesValue && inlineValue) {
      throw Error(flag + " takes no value");
    }
    option->apply(text);
  }
}

bool ArgParser::parseOrShowHelp(const std::vector<std::string>& args) {
  bool help = false;
  toggle("--help", "show this help", [&] { help = true; });
  parse(args);
  if (help) std::fputs(usage().c_str(), stdout);
  return help;
}

std::string ArgParser::usage() const {
  std::ostringstream s;
  s << "usage: iblx " << command_ << " [flags]\n";
  for (const auto& o : options_) {
    std::string left = o.flag + (o.takesValue ? " " + o.metavar : "");
    s << "  " << left << std::string(left.size() < 26 ? 26 - left.size() : 1, ' ') << o.help << "\n";
  }
  return s.str();
}

uint32_t parseUint(const std::string& flag, const std::string& text, uint32_t min, uint32_t max) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0)
    throw Error(flag + " " + text + ": not an integer");
  if (v < min || v > max)
    throw Error(flag + " " + text + ": out of range [" + std::to_string(min) + ", " + std::to_string(max) +
                "]");
  return uint32_t(v);
}

double parseDouble(const std::string& flag, const std::string& text, double min, double max) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw Error(flag + " " + text + ": not a number");
  if (v < min || v > max) {
    std::ostringstream s;
    s << flag << " " << text << ": out of range [" << min << ", " << max << "]";
    throw Error(s.str());
  }
  return v;
}

void parseSize(const std::string& flag, const std::string& text, int& width, int& height) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw Error(flag + " " + text + ": expected WIDTHxHEIGHT, e.g. 256x256");
  width = int(parseUint(flag, text.substr(0, x), 1, 16384));
  height = int(parseUint(flag, text.substr(x + 1), 1, 16384));
}

void addParamFlag(ArgParser& p, std::vector<std::pair<std::string, std::string>>& params) {
  p.value("--param", "NAME=VALUE", "BRDF parameter, repeatable; colors as r,g,b", [&](const std::string& v) {
    const auto eq = v.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("--param " + v + ": expected NAME=VALUE");
    params.emplace_back(v.substr(0, eq), v.substr(eq + 1));
  });
}

void addSceneFlags(ArgParser& p, RenderSpec& s) {
  p.value("--env", "FILE", ".exr or .hdr lat-long map (default: assets/default_sky.exr)",
          [&](const std::string& v) { s.scene.envPath = v; });
  p.value("--env-rotation", "DEG", "rotation of the environment about +Y", [&](const std::string& v) {
    s.scene.envRotationDeg = parseDouble("--env-rotation", v, -1e6, 1e6);
  });
  p.value(
      "--brdf", "NAME|FILE",
      "built-in BRDF (lambert | ggx, default ggx), a BRDF Explorer .brdf / .bparam file, or a measured or "
      "fitted material: MERL .binary, UTIA .bin, MIT .dat, RGL-EPFL .bsdf, ALTA data or ALTA function file",
      [&](const std::string& v) { s.scene.brdf = v; });
  addParamFlag(p, s.scene.params);
  p.value("--object", "NAME|FILE", objectNameList() + " (default sphere), or an .obj file",
          [&](const std::string& v) { s.scene.object = v; });
  p.value("--orbit", "AZ,EL",
          "camera orbit in degrees: azimuth about +Y, then elevation towards +Y in [-90, 90] (default 0,0)",
          [&](const std::string& v) {
            const auto comma = v.find(',');
            if (comma == std::string::npos || v.find(',', comma + 1) != std::string::npos)
              throw Error("--orbit " + v + ": expected AZ,EL in degrees, e.g. 30,20");
            s.scene.camera.azimuthDeg = parseDouble("--orbit azimuth", v.substr(0, comma), -1e6, 1e6);
            s.scene.camera.elevationDeg = parseDouble("--orbit elevation", v.substr(comma + 1), -90, 90);
          });
  p.value("--zoom", "F", "camera zoom > 0: the image half-height covers 1/F world units (default 1)",
          [&](const std::string& v) {
            s.scene.camera.zoom = parseDouble("--zoom", v, 0, 1e6);
            if (!(s.scene.camera.zoom > 0)) throw Error("--zoom " + v + ": must be > 0");
          });
  p.value("--size", "WxH", "image size (default 256x256)",
          [&](const std::string& v) { parseSize("--size", v, s.scene.width, s.scene.height); });
}

void addMethodFlags(ArgParser& p, RenderSpec& s) {
  p.value("--method", "NAME", "sampling method (default mis; see --list-methods)",
          [&](const std::string& v) { s.method.method = v; });
  p.value("--env-sampler", "NAME", "env technique used by mis and ris (default env-cdf)",
          [&](const std::string& v) { s.method.envSampler = v; });
  p.value("--brdf-sampler", "NAME", "BRDF technique used by brdf and mis (default: the BRDF's best)",
          [&](const std::string& v) { s.method.brdfSampler = v; });
  p.value("--seq", "NAME", "random | sobol | cp-shared (default sobol)",
          [&](const std::string& v) { s.method.sequence = v; });
  p.value("--mis-heuristic", "NAME", "balance | power (default balance)",
          [&](const std::string& v) { s.method.misHeuristic = v; });
  p.value(
      "--mis-split", "F",
      "one-sample MIS with this fraction of samples given to the env technique (default: two-sample MIS, one "
      "direction from each technique per sample)",
      [&](const std::string& v) { s.method.misEnvFraction = parseDouble("--mis-split", v, 0.0, 1.0); });
  p.toggle(
      "--mis-compensation",
      "mis: the env technique samples max(p - mean(p), 0) (Karlik et al. 2019), leaving flat regions to the "
      "BRDF technique",
      [&] { s.method.misCompensation = true; });
  p.value("--ris-candidates", "M", "candidates per sample of ris (1-64, default 8)",
          [&](const std::string& v) {
            s.method.risCandidates = int(parseUint("--ris-candidates", v, 1, kMaxRisCandidates));
          });
  p.toggle("--list-methods", "print the registry (methods, techniques, sequences, BRDFs) and exit",
           [&] { s.listMethods = true; });
}

void addSampleFlags(ArgParser& p, RenderSpec& s) {
  // One pass is one dispatch: the cap keeps a dispatch far from GPU watchdog limits at any image size.
  p.value("--spp", "N", "samples per pixel per pass, up to 4096 (default 32)",
          [&](const std::string& v) { s.samplesPerPass = parseUint("--spp", v, 1, 4096); });
  p.value("--seed", "N", "seed of the sample sequence (default 1)",
          [&](const std::string& v) { s.seed = parseUint("--seed", v, 0, 0xffffffffu); });
}

void addDisplayFlags(ArgParser& p, DisplaySettings& display) {
  p.value(
      "--exposure", "EV",
      "exposure in stops: added to the automatic exposure, or the whole exposure with --auto-exposure off "
      "(default 0)",
      [&](const std::string& v) { display.exposureEV = parseDouble("--exposure", v, -64, 64); });
  p.value("--auto-exposure", "on|off",
          "on (default): expose the object's log-average luminance to middle grey (0.18)",
          [&](const std::string& v) {
            if (v != "on" && v != "off") throw Error("--auto-exposure " + v + ": expected on or off");
            display.autoExposure = v == "on";
          });
  p.value("--tonemap", "CURVE", "aces (default, filmic), reinhard or clamp", [&](const std::string& v) {
    for (std::size_t i = 0; i < std::size(kTonemapNames); ++i)
      if (v == kTonemapNames[i]) {
        display.tonemap = Tonemap(i);
        return;
      }
    throw Error("--tonemap " + v + ": expected aces, reinhard or clamp");
  });
  p.value("--gamma", "G", "display gamma instead of the sRGB curve (1 to 3)",
          [&](const std::string& v) { display.gamma = parseDouble("--gamma", v, 1, 3); });
}

void addRunFlags(ArgParser& p, RenderSpec& s) {
  addSampleFlags(p, s);
  p.value("--passes", "N", "number of passes (default 32)",
          [&](const std::string& v) { s.passes = parseUint("--passes", v, 1, 1u << 24); });
  p.value("--time", "S", "run passes until S seconds of wall time have passed (instead of --passes)",
          [&](const std::string& v) { s.timeBudgetSeconds = parseDouble("--time", v, 1e-3, 1e7); });
  p.value("--out", "FILE", "output image: .exr (linear float) or .png (tonemapped)",
          [&](const std::string& v) { s.out = v; });
  addDisplayFlags(p, s.display);
  p.toggle("--reference", "also compute the ground truth and report the error against it",
           [&] { s.reference = true; });
  p.value("--reference-file", "FILE",
          "like --reference, with the ground truth read from an EXR of `iblx reference`",
          [&](const std::string& v) { s.referenceFile = v; });
  p.toggle("--json", "print one JSON object with the run's figures", [&] { s.json = true; });
}

std::string_view settingFlag(Setting setting) {
  switch (setting) {
    case Setting::Environment:
      return "--env";
    case Setting::EnvRotation:
      return "--env-rotation";
    case Setting::Brdf:
      return "--brdf";
    case Setting::BrdfParam:
      return "--param";
    case Setting::Object:
      return "--object";
    case Setting::Orbit:
      return "--orbit";
    case Setting::Zoom:
      return "--zoom";
    case Setting::ImageSize:
      return "--size";
    case Setting::Method:
      return "--method";
    case Setting::EnvSampler:
      return "--env-sampler";
    case Setting::BrdfSampler:
      return "--brdf-sampler";
    case Setting::Sequence:
      return "--seq";
    case Setting::MisHeuristic:
      return "--mis-heuristic";
    case Setting::MisSplit:
      return "--mis-split";
    case Setting::RisCandidates:
      return "--ris-candidates";
    case Setting::MisCompensation:
      return "--mis-compensation";
    case Setting::Device:
      return "--device";
  }
  return settingName(setting);
}

ResolvedMethod resolveMethodAndWarn(const MethodSpec& spec, const BrdfInfo& brdf) {
  ResolvedMethod method = resolveMethod(spec, brdf);
  for (Setting ignored : method.ignoredSettings)
    warn(std::string(settingFlag(ignored)) + " is ignored by --method " + method.method->name);
  return method;
}

void printRegistry(const RenderSpec& spec) {
  std::fputs(describeRegistry().c_str(), stdout);
  if (spec.scene.brdf == SceneSpec{}.brdf) return;
  // A BRDF made from a file (a .brdf, a .bparam, a UTIA file) is not in the listing above: it follows.
  const LoadedBrdf loaded = loadBrdfArgument(spec.scene.brdf);
  const auto registry = brdfRegistry();
  if (std::any_of(registry.begin(), registry.end(),
                  [&](const BrdfInfo& b) { return &b == loaded.info.get(); }))
    return;
  std::printf("--brdf %s:\n", spec.scene.brdf.c_str());
  std::fputs(describeBrdf(*loaded.info).c_str(), stdout);
}

std::pair<long long, long long> parsePixel(const std::string& flag, const std::string& text) {
  const auto comma = text.find(',');
  auto integer = [&](const std::string& part, long long& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtoll(part.c_str(), &end, 10);
    return !part.empty() && end == part.c_str() + part.size() && errno == 0;
  };
  long long x = 0, y = 0;
  if (comma == std::string::npos || !integer(text.substr(0, comma), x) || !integer(text.substr(comma + 1), y))
    throw Error(flag + " " + text + ": expected X,Y in whole pixels from the top-left corner, e.g. 128,96");
  return {x, y};
}

void addDeviceFlags(ArgParser& p, RenderSpec& s) {
  p.value("--device", "INDEX|NAME", "Vulkan device (default: $IBLX_DEVICE, else discrete > integrated > CPU)",
          [&](const std::string& v) { s.device = v; });
  p.toggle("--validation", "enable the Vulkan validation layers", [&] { s.validation = true; });
}

}  // namespace iblx::cli
