// Scene loading and method resolution, with the checks a user needs to hear about.
#include "engine/scene/scene.h"

#include "engine/core/assets.h"
#include "engine/core/error.h"
#include "engine/core/setting.h"
#include "engine/core/file_io.h"
#include "engine/core/join.h"
#include "engine/core/log.h"
#include "engine/io/brdf_file.h"
#include "engine/scene/analytic_brdf.h"
#include "engine/scene/measured_brdfs.h"
#include "engine/io/latlong_texel.h"
#include "engine/sampling/brdf/merl_sampling.h"
#include "engine/scene/brdf_params.h"

#include <algorithm>
#include <cmath>

#include <cstdlib>
#include <ranges>
#include <sstream>

namespace iblx {

std::filesystem::path defaultEnvPath() {
  return assetPath("default_sky.exr");
}

MeasuredBrdf::MeasuredBrdf(MerlBrdf b) : brdf(std::move(b)) {}
MeasuredBrdf::~MeasuredBrdf() = default;

const MerlThetaHData& MeasuredBrdf::thetaHTable() const {
  std::call_once(thetaHOnce_, [&] { thetaH_ = std::make_unique<MerlThetaHData>(buildMerlThetaH(brdf)); });
  return *thetaH_;
}

const MerlTableData& MeasuredBrdf::sampleTable() const {
  std::call_once(tableOnce_, [&] { table_ = std::make_unique<MerlTableData>(buildMerlTable(brdf)); });
  return *table_;
}

double MeasuredBrdf::lobeWidth() const {
  // Mean sampling weight per theta_h bin; the half-maximum angle of a GGX D is atan(0.6436 alpha)
  // ((1 + t^2 / alpha^2)^2 = 2), so a profile falling to half at theta_half acts like GGX of
  // alpha = tan(theta_half) / 0.6436, whose lobe width is 2 atan(alpha) as for the built-in ggx.
  std::vector<double> profile(kMerlThetaHBins, 0.0);
  for (int h = 0; h < kMerlThetaHBins; ++h)
    for (int d = 0; d < kMerlThetaDBins; ++d)
      for (int p = 0; p < kMerlPhiDBins; ++p) {
        profile[std::size_t(h)] += merlSamplingWeight(brdf, merlBinIndex(h, d, p));
      }
  const auto peak = std::max_element(profile.begin(), profile.end());
  if (*peak <= 0.0) return 0.0;
  for (auto it = peak; it != profile.end(); ++it)
    if (*it < 0.5 * *peak) {
      const int bin = int(it - profile.begin());
      const double u = double(bin) / kMerlThetaHBins, thetaHalf = u * u * kPi / 2.0;
      return 2.0 * std::atan(std::tan(thetaHalf) / 0.6436);
    }
  return 0.0;
}

LoadedBrdf loadBrdfArgument(const std::string& nameOrPath) {
  // Material files are recognised by their content whatever their names (materialFileFormats), then by
  // their extension, so that a damaged file is reported as its format's.
  const std::filesystem::path path(nameOrPath);
  const std::string extension = path.extension().string();
  const bool explorerName = extension == ".brdf" || extension == ".bparam";
  for (const MaterialFileFormat& format : materialFileFormats())
    if ((!explorerName || format.evenWithExplorerNames) && format.recognise(path))
      return {format.load(path), nullptr, nameOrPath};
  for (const MaterialFileFormat& format : materialFileFormats())
    if (std::ranges::find(format.extensions, extension) != format.extensions.end()) {
      if (!std::filesystem::exists(path))
        throw SettingError(Setting::Brdf, "", " " + nameOrPath + ": no such file");
      return {format.load(path), nullptr, nameOrPath};
    }
  if (const BrdfInfo* registered = findBrdfForArgument(nameOrPath)) {
    LoadedBrdf loaded;
    loaded.info =
        std::shared_ptr<const BrdfInfo>(std::shared_ptr<const BrdfInfo>(), registered);  // not owned
    if (!registered->fileExtension.empty()) {  // MERL, the one registry BRDF read from a file
      if (!std::filesystem::exists(nameOrPath))
        throw SettingError(Setting::Brdf, "", " " + nameOrPath + ": no such file");
      loaded.measured = std::make_shared<const MeasuredBrdf>(loadMerl(nameOrPath));
      loaded.file = nameOrPath;
    }
    return loaded;
  }
  const BrdfFile file = readBrdfFile(nameOrPath);
  if (file.kind == BrdfFile::Kind::Analytic) return {makeAnalyticBrdf(file), nullptr, nameOrPath};

  // A .bparam: load what it names, then take its saved values as the defaults, by name.
  const std::string source = file.bparamSource.string();
  const std::string sourceExtension = file.bparamSource.extension().string();
  if (sourceExtension == ".bparam")
    throw Error(nameOrPath + ":1: a .bparam must name a .brdf or MERL .binary file, not another .bparam");
  LoadedBrdf loaded;
  // A problem in the file it names is reported as the .bparam's, which is what the user passed.
  const auto asBparamError = [&](const Error& e) { return Error(nameOrPath + ":1: " + e.what()); };
  if (sourceExtension == ".brdf") {
    BrdfFile target;
    try {
      target = readBrdfFile(file.bparamSource);
    } catch (const Error& e) {
      throw asBparamError(e);
    }
    for (const BrdfFileParam& saved : file.params) {
      auto it = std::find_if(target.params.begin(), target.params.end(),
                             [&](const BrdfFileParam& p) { return p.decl.name == saved.decl.name; });
      if (it == target.params.end()) {
        warn(nameOrPath + ":" + std::to_string(saved.line) + ": " + source + " has no parameter '" +
             saved.decl.name + "'; its saved value is ignored");
        continue;
      }
      if (it->decl.type != saved.decl.type) {
        warn(nameOrPath + ":" + std::to_string(saved.line) + ": '" + saved.decl.name +
             "' has another type in " + source + "; its saved value is ignored");
        continue;
      }
      auto value = saved.decl.defaultValue;
      for (int c = 0; c < (it->decl.type == ParamType::Color ? 3 : 1); ++c)
        value[std::size_t(c)] = std::clamp(value[std::size_t(c)], it->decl.min, it->decl.max);
      if (value != saved.decl.defaultValue)
        warn(nameOrPath + ":" + std::to_string(saved.line) + ": the saved value of '" + saved.decl.name +
             "' is outside its range in " + source + " and is clamped");
      it->decl.defaultValue = value;
    }
    auto info = std::make_shared<BrdfInfo>(*makeAnalyticBrdf(target));
    info->name = std::filesystem::path(nameOrPath).stem().string();
    info->description = "BRDF Explorer parameters " + nameOrPath + " for " + source;
    loaded.info = std::move(info);
    loaded.file = file.bparamSource;
  } else {
    try {
      loaded = loadBrdfArgument(source);
    } catch (const Error& e) {
      throw asBparamError(e);
    }
    // A measured file's parameters (a UTIA file's colour convention) take the saved values, by name.
    auto info = std::make_shared<BrdfInfo>(*loaded.info);
    for (const BrdfFileParam& saved : file.params) {
      auto it = std::find_if(info->params.begin(), info->params.end(),
                             [&](const ParamDecl& p) { return p.name == saved.decl.name; });
      if (it == info->params.end() || it->type != saved.decl.type) {
        warn(nameOrPath + ":" + std::to_string(saved.line) + ": " + source + " has no " +
             (it == info->params.end() ? "parameter" : "parameter of that type") + " '" + saved.decl.name +
             "'; its saved value is ignored");
        continue;
      }
      for (int c = 0; c < (it->type == ParamType::Color ? 3 : 1); ++c)
        it->defaultValue[std::size_t(c)] =
            std::clamp(saved.decl.defaultValue[std::size_t(c)], it->min, it->max);
    }
    if (!file.params.empty()) loaded.info = std::move(info);
  }
  return loaded;
}

Scene makeScene(EnvImage env, const SceneSpec& spec) {
  return makeScene(std::move(env), spec, loadBrdfArgument(spec.brdf));
}

Scene makeScene(EnvImage env, const SceneSpec& spec, LoadedBrdf brdf) {
  std::string size(" ");
  size.append(std::to_string(spec.width)).append("x").append(std::to_string(spec.height));
  if (spec.width < 1 || spec.height < 1 || spec.width > 16384 || spec.height > 16384)
    throw SettingError(Setting::ImageSize, "", size + ": width and height must be in [1, 16384]");
  try {
    checkMemoryBudget("the image's per-pixel buffers", std::uint64_t(spec.width) *
                                                           std::uint64_t(spec.height) *
                                                           (sizeof(gpu::GPixel) + sizeof(gpu::AccumPixel)));
  } catch (const Error& e) {
    throw SettingError(Setting::ImageSize, "", size + ": " + e.what());
  }
  if (!std::isfinite(spec.envRotationDeg))
    throw SettingError(Setting::EnvRotation, "", " must be a finite number of degrees");
  Scene scene;
  scene.env = std::move(env);
  scene.envRotationDeg = spec.envRotationDeg;
  scene.brdf = std::move(brdf.info);
  scene.params = resolveParams(*scene.brdf, spec.params);
  scene.measured = std::move(brdf.measured);
  scene.brdfFile = std::move(brdf.file);
  scene.gbuffer = makeGBuffer(spec.object, spec.camera, spec.width, spec.height);
  return scene;
}

Scene loadScene(const SceneSpec& spec) {
  // The BRDF (and its file) first, so a bad --brdf does not wait for a large map to load.
  return loadScene(spec, loadBrdfArgument(spec.brdf));
}

Scene loadScene(const SceneSpec& spec, LoadedBrdf brdf) {
  const auto path = spec.envPath.empty() ? defaultEnvPath() : spec.envPath;
  return makeScene(loadEnvImage(path), spec, std::move(brdf));
}

std::string ResolvedMethod::techniqueLabel() const {
  // An env technique alone is its own method name; other methods name their techniques and options.
  const StrategyInfo& s = method->strategyInfo();
  std::ostringstream out;
  out << method->name;
  if (s.id == Strategy::SingleEnv) return out.str();
  out << "(";
  if (envTechnique) out << envTechnique->name << (brdfTechnique ? "+" : "");
  if (brdfTechnique) out << brdfTechnique->name;
  if (s.misWeights) out << ", " << (misPower ? "power" : "balance");
  if (misOneSample) out << ", one-sample " << misEnvFraction;
  if (misCompensation) out << ", compensated";
  if (s.risCandidates) out << ", M=" << risCandidates;
  out << ")";
  return out.str();
}

std::string ResolvedMethod::label() const {
  return techniqueLabel() + "/" + sequence->name;
}

uint32_t ResolvedMethod::drawsPerSample() const {
  return misOneSample ? 1 : method->strategyInfo().drawsPerSample;
}

ResolvedMethod resolveMethod(const MethodSpec& spec, const BrdfInfo& brdf) {
  ResolvedMethod r;
  r.method = &findMethod(spec.method);
  r.sequence = &findSequence(spec.sequence);
  if (!spec.misHeuristic.empty() && spec.misHeuristic != "balance" && spec.misHeuristic != "power")
    throw SettingError(Setting::MisHeuristic, "unknown ",
                       " '" + spec.misHeuristic + "'; valid: balance, power");
  if (spec.misEnvFraction && !(*spec.misEnvFraction >= 0.0 && *spec.misEnvFraction <= 1.0))
    throw SettingError(Setting::MisSplit, "",
                       " must be in [0, 1] (the fraction of samples given to the env technique)");
  if (spec.risCandidates && !(*spec.risCandidates >= 1 && *spec.risCandidates <= kMaxRisCandidates))
    throw SettingError(Setting::RisCandidates, "",
                       " must be in [1, " + std::to_string(kMaxRisCandidates) + "]");
  const StrategyInfo& s = r.method->strategyInfo();
  r.misPower = spec.misHeuristic == "power";
  r.misOneSample = spec.misEnvFraction.has_value() && s.misSplit;
  r.misEnvFraction = float(spec.misEnvFraction.value_or(0.5));
  r.risCandidates = uint32_t(spec.risCandidates.value_or(8));
  // Settings that the chosen method does not use, for the front end to report (a typo'd command line must
  // not mislead).
  const auto ignored = [&](bool given, Setting setting) {
    if (given) r.ignoredSettings.push_back(setting);
  };
  ignored(!spec.envSampler.empty() && !s.envTechniqueChosen, Setting::EnvSampler);
  ignored(spec.risCandidates.has_value() && !s.risCandidates, Setting::RisCandidates);
  ignored(spec.misCompensation && !s.misSplit, Setting::MisCompensation);
  r.misCompensation = spec.misCompensation && s.misSplit;
  ignored(!spec.brdfSampler.empty() && !s.usesBrdfTechnique, Setting::BrdfSampler);
  ignored(spec.misEnvFraction.has_value() && !s.misSplit, Setting::MisSplit);
  ignored(!spec.misHeuristic.empty() && !s.misWeights, Setting::MisHeuristic);
  const bool needsEnv = s.usesEnvTechnique, needsBrdf = s.usesBrdfTechnique;
  if (needsEnv)
    r.envTechnique = !r.method->envTechnique.empty()
                         ? &findEnvTechnique(r.method->envTechnique)
                         : &findEnvTechnique(spec.envSampler.empty() ? "env-cdf" : spec.envSampler);
  if (needsBrdf) {
    const std::string name = spec.brdfSampler.empty() ? brdf.bestSampler : spec.brdfSampler;
    r.brdfTechnique = &findBrdfTechnique(name);
    if (!r.brdfTechnique->appliesTo(brdf)) {
      auto applicable = brdfTechniqueRegistry() |
                        std::views::filter([&](const BrdfTechniqueInfo& t) { return t.appliesTo(brdf); });
      throw SettingError(Setting::BrdfSampler, "",
                         " " + name + " does not apply to BRDF '" + brdf.name +
                             "'; those that do: " + joinNames(applicable, &BrdfTechniqueInfo::name));
    }
  }
  return r;
}

std::vector<MethodSpec> defaultMethodSpecs(const BrdfInfo& brdf) {
  std::vector<MethodSpec> specs;
  for (const auto& m : methodRegistry()) {
    MethodSpec spec;
    spec.method = m.name;
    try {
      resolveMethod(spec, brdf);  // e.g. brdf needs a BRDF technique that applies
    } catch (const Error&) {
      continue;
    }
    specs.push_back(spec);
  }
  return specs;
}

MethodSpec parseMethodVariant(const std::string& text) {
  MethodSpec spec;
  std::size_t start = 0;
  bool first = true;
  while (start <= text.size()) {
    const auto colon = text.find(':', start);
    const std::string word =
        text.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    start = colon == std::string::npos ? text.size() + 1 : colon + 1;
    const auto invalid = [&](const std::string& problem) {
      return SettingError(Setting::Method, "", " " + text + ": " + problem);
    };
    if (word.empty()) throw invalid("empty option");
    if (first) {
      spec.method = findMethod(word).name;
      first = false;
      continue;
    }
    auto isIn = [&](auto registry) {
      return std::any_of(registry.begin(), registry.end(), [&](const auto& t) { return t.name == word; });
    };
    // `cosine` names an env and a BRDF technique: it is the BRDF technique for a method that uses no env
    // technique (brdf:cosine), or once an env technique has been named (mis:env-cdf:cosine).
    const bool env = isIn(envTechniqueRegistry()), brdf = isIn(brdfTechniqueRegistry());
    const bool brdfOnly = !findMethod(spec.method).strategyInfo().usesEnvTechnique;
    if (env && !(brdf && (brdfOnly || !spec.envSampler.empty()))) {
      spec.envSampler = word;
    } else if (brdf) {
      spec.brdfSampler = word;
    } else if (word == "balance" || word == "power") {
      spec.misHeuristic = word;
    } else if (word == "compensated") {
      spec.misCompensation = true;
    } else if (word.rfind("M=", 0) == 0) {
      char* end = nullptr;
      const long m = std::strtol(word.c_str() + 2, &end, 10);
      if (word.size() == 2 || *end || m < 1 || m > kMaxRisCandidates)
        throw invalid("'" + word + "': M must be 1-" + std::to_string(kMaxRisCandidates));
      spec.risCandidates = int(m);
    } else if (word.rfind("split=", 0) == 0) {
      char* end = nullptr;
      const double f = std::strtod(word.c_str() + 6, &end);
      if (word.size() == 6 || *end || !(f >= 0.0 && f <= 1.0))
        throw invalid("'" + word + "': split must be in [0, 1]");
      spec.misEnvFraction = f;
    } else {
      throw invalid(
          "unknown option '" + word +
          "'; options are env and BRDF technique names, balance, power, compensated, M=N and split=F");
    }
  }
  return spec;
}

}  // namespace iblx
