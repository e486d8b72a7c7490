// Scene loading, method resolution (with the checks a user needs to hear about) and GPU upload.
#include "engine/render/scene.h"

#include "engine/core/assets.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/io/brdf_file.h"
#include "engine/render/analytic_brdf.h"
#include "engine/sampling/latlong_texel.h"
#include "engine/sampling/merl_sampling.h"

#include <algorithm>
#include <cmath>

#include <cstdlib>
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
  if (const BrdfInfo* registered = findBrdfForArgument(nameOrPath)) {
    LoadedBrdf loaded;
    loaded.info =
        std::shared_ptr<const BrdfInfo>(std::shared_ptr<const BrdfInfo>(), registered);  // not owned
    if (!registered->fileExtension.empty()) {  // MERL, the one registry BRDF read from a file
      if (!std::filesystem::exists(nameOrPath)) throw Error("--brdf " + nameOrPath + ": no such file");
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
    for (const BrdfFileParam& saved : file.params)
      warn(nameOrPath + ":" + std::to_string(saved.line) + ": " + source + " has no parameters; '" +
           saved.decl.name + "' is ignored");
  }
  return loaded;
}

Scene makeScene(EnvImage env, const SceneSpec& spec) {
  return makeScene(std::move(env), spec, loadBrdfArgument(spec.brdf));
}

Scene makeScene(EnvImage env, const SceneSpec& spec, LoadedBrdf brdf) {
  if (spec.width < 1 || spec.height < 1 || spec.width > 16384 || spec.height > 16384)
    throw Error("--size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                ": width and height must be in [1, 16384]");
  checkMemoryBudget("--size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                        ": the image's per-pixel buffers",
                    std::uint64_t(spec.width) * std::uint64_t(spec.height) *
                        (sizeof(gpu::GPixel) + sizeof(gpu::AccumPixel)));
  if (!std::isfinite(spec.envRotationDeg)) throw Error("--env-rotation must be a finite number of degrees");
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
  std::ostringstream s;
  s << method->name;
  if (method->strategy == Strategy::Mis) {
    s << "(" << envTechnique->name << "+" << brdfTechnique->name << ", " << (misPower ? "power" : "balance");
    if (misOneSample) s << ", one-sample " << misEnvFraction;
    s << (misCompensation ? ", compensated" : "") << ")";
  } else if (method->strategy == Strategy::SingleBrdf) {
    s << "(" << brdfTechnique->name << ")";
  } else if (method->strategy == Strategy::Ris) {
    s << "(" << envTechnique->name << ", M=" << risCandidates << ")";
  } else if (method->strategy == Strategy::Product || method->strategy == Strategy::ProductWarp) {
    s << "(" << envTechnique->name << ")";
  } else if (method->strategy == Strategy::ProductMis) {
    s << "(" << envTechnique->name << "+" << brdfTechnique->name << ", " << (misPower ? "power" : "balance")
      << ")";
  }
  return s.str();
}

std::string ResolvedMethod::label() const {
  return techniqueLabel() + "/" + sequence->name;
}

uint32_t ResolvedMethod::drawsPerSample() const {
  const bool twoSample =
      (method->strategy == Strategy::Mis && !misOneSample) || method->strategy == Strategy::ProductMis;
  return twoSample ? 2 : 1;
}

ResolvedMethod resolveMethod(const MethodSpec& spec, const BrdfInfo& brdf) {
  ResolvedMethod r;
  r.method = &findMethod(spec.method);
  r.sequence = &findSequence(spec.sequence);
  if (!spec.misHeuristic.empty() && spec.misHeuristic != "balance" && spec.misHeuristic != "power")
    throw Error("unknown --mis-heuristic '" + spec.misHeuristic + "'; valid: balance, power");
  if (spec.misEnvFraction && !(*spec.misEnvFraction >= 0.0 && *spec.misEnvFraction <= 1.0))
    throw Error("--mis-split must be in [0, 1] (the fraction of samples given to the env technique)");
  if (spec.risCandidates && !(*spec.risCandidates >= 1 && *spec.risCandidates <= kMaxRisCandidates))
    throw Error("--ris-candidates must be in [1, " + std::to_string(kMaxRisCandidates) + "]");
  r.misPower = spec.misHeuristic == "power";
  r.misOneSample = spec.misEnvFraction.has_value() && r.method->strategy == Strategy::Mis;
  r.misEnvFraction = float(spec.misEnvFraction.value_or(0.5));
  r.risCandidates = uint32_t(spec.risCandidates.value_or(8));
  const bool isMis = r.method->strategy == Strategy::Mis, isRis = r.method->strategy == Strategy::Ris;
  const bool isProductMis = r.method->strategy == Strategy::ProductMis;
  const bool needsEnv = r.method->strategy != Strategy::SingleBrdf;
  const bool needsBrdf = r.method->strategy == Strategy::SingleBrdf || isMis || isProductMis;
  // Flags that the chosen method does not use are reported, so a typo'd command line cannot mislead.
  auto ignored = [&](bool given, const char* flag) {
    if (given) warn(std::string(flag) + " is ignored by --method " + r.method->name);
  };
  ignored(!spec.envSampler.empty() && !isMis && !isRis, "--env-sampler");
  ignored(spec.risCandidates.has_value() && !isRis, "--ris-candidates");
  ignored(spec.misCompensation && !isMis, "--mis-compensation");
  r.misCompensation = spec.misCompensation && isMis;
  ignored(!spec.brdfSampler.empty() && !needsBrdf, "--brdf-sampler");
  ignored(spec.misEnvFraction.has_value() && !isMis, "--mis-split");
  ignored(!spec.misHeuristic.empty() && !isMis && !isProductMis, "--mis-heuristic");
  if (needsEnv)
    r.envTechnique = !r.method->envTechnique.empty()
                         ? &findEnvTechnique(r.method->envTechnique)
                         : &findEnvTechnique(spec.envSampler.empty() ? "env-cdf" : spec.envSampler);
  if (needsBrdf) {
    const std::string name = spec.brdfSampler.empty() ? brdf.bestSampler : spec.brdfSampler;
    r.brdfTechnique = &findBrdfTechnique(name);
    if (!r.brdfTechnique->appliesTo(brdf))
      throw Error("--brdf-sampler " + name + " does not apply to BRDF '" + brdf.name +
                  "' (see --list-methods)");
  }
  return r;
}

void checkImageFitsDevice(const VulkanContext& context, int width, int height) {
  const std::uint64_t pixels = std::uint64_t(std::max(width, 0)) * std::uint64_t(std::max(height, 0));
  const std::uint64_t largest = context.limits().maxStorageBufferRange;
  const std::uint64_t bytesPerPixel = std::max(sizeof(gpu::GPixel), sizeof(gpu::AccumPixel));
  if (pixels * bytesPerPixel <= largest) return;
  const int side = int(std::sqrt(double(largest / bytesPerPixel)));
  throw DeviceLimitError("--size " + std::to_string(width) + "x" + std::to_string(height) +
                         ": the G-buffer needs " + formatBytes(pixels * sizeof(gpu::GPixel)) +
                         ", more than this device's largest storage " + "buffer (" + formatBytes(largest) +
                         "); images up to about " + std::to_string(side) + "x" + std::to_string(side) +
                         " pixels fit");
}

SceneGpu uploadScene(const VulkanContext& context, const Scene& scene) {
  const auto& g = scene.gbuffer;
  const std::size_t pixels = g.pixels.size();
  std::vector<float> rows = envRowTable(scene.env.width, scene.env.height);
  std::vector<float> params = packParams(*scene.brdf, scene.params);
  SceneGpu gpu{Buffer::fromData(context, g.pixels, "gbuffer"),
               Buffer(context, pixels * sizeof(gpu::AccumPixel), "accumulation"),
               Buffer::fromData(context, rows, "environment row table", 4),
               Buffer(context, sizeof(gpu::KernelStats), "kernel stats"),
               Buffer::fromData(context, params, "brdf parameters")};
  const std::size_t texels = std::size_t(scene.env.width) * std::size_t(scene.env.height);
  const std::size_t bytesPerTexel = 3 * sizeof(float);
  // Each chunk is one buffer, read as a table: it must fit both limits.
  const std::size_t chunkBytes = std::min<std::size_t>(
      context.limits().maxStorageBufferRange, std::size_t(context.limits().maxTexelBufferElements) * 4);
  gpu.envTexelsPerChunk = std::min<std::size_t>(texels, chunkBytes / bytesPerTexel);
  const std::size_t chunks = (texels + gpu.envTexelsPerChunk - 1) / gpu.envTexelsPerChunk;
  if (chunks > kMaxEnvRadianceChunks)
    throw DeviceLimitError("the environment map's " + std::to_string(texels * bytesPerTexel >> 20) +
                           " MiB of radiance need " + std::to_string(chunks) + " buffers on this device (" +
                           std::to_string(chunkBytes >> 20) + " MiB each), more than " +
                           std::to_string(kMaxEnvRadianceChunks) + "; use a smaller map");
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t first = c * gpu.envTexelsPerChunk,
                      count = std::min(gpu.envTexelsPerChunk, texels - first);
    const std::span<const float> chunk(scene.env.rgb.data() + 3 * first, 3 * count);
    gpu.envRgb.push_back(Buffer::fromData(
        context, chunk, chunks == 1 ? "environment radiance" : "environment radiance " + std::to_string(c)));
  }
  if (scene.brdf->data) gpu.brdfData = uploadTables(context, scene.brdf->data(scene));
  gpu.accum.fill(0);
  gpu.stats.fill(0);
  return gpu;
}

std::vector<Buffer> uploadTables(const VulkanContext& context, const TechniqueData& data) {
  std::vector<Buffer> buffers;
  for (std::size_t i = 0; i < data.buffers.size(); ++i)
    buffers.push_back(Buffer::fromData(context, data.buffers[i], data.names[i], data.elementWords[i]));
  return buffers;
}

std::array<const Buffer*, 8> SceneGpu::frameSet() const {
  auto chunk = [&](std::size_t c) { return c < envRgb.size() ? &envRgb[c] : &envRgb[0]; };
  return {&gbuffer, &accum, &envRgb[0], &envRows, &stats, chunk(1), chunk(2), chunk(3)};
}

std::vector<std::pair<std::string, std::string>> SceneGpu::envDefines() const {
  if (envRgb.size() <= 1) return {};
  return {{"ENV_RADIANCE_CHUNKS", std::to_string(envRgb.size())},
          {"ENV_TEXELS_PER_CHUNK", std::to_string(envTexelsPerChunk) + "u"}};
}

std::vector<const Buffer*> SceneGpu::brdfSet(std::span<const Buffer> techniqueBuffers) const {
  std::vector<const Buffer*> set{&brdfParams};
  for (const auto& b : brdfData) set.push_back(&b);
  for (const auto& b : techniqueBuffers) set.push_back(&b);
  return set;
}

}  // namespace iblx
