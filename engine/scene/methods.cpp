// The registry lists. Each line is one BRDF, technique, sequence or method; nothing else names them.
#include "engine/scene/methods.h"

#include "engine/core/setting.h"
#include "engine/core/join.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/sampling/env/env_hier.h"
#include "engine/sampling/env/env_ot_maps.h"
#include "engine/sampling/env/env_ot.h"
#include "engine/sampling/env/env_ot_diagnostics.h"
#include "engine/sampling/product/env_ot_product.h"
#include "engine/sampling/product/env_hier_product.h"
#include "engine/sampling/brdf/merl_sampling.h"
#include "engine/scene/measured_brdfs.h"
#include "engine/scene/scene.h"

#include <cmath>
#include <filesystem>
#include <memory>

namespace iblx {
namespace {

TechniqueData noData(const EnvImage&) {
  return {};
}

double ggxLobeWidth(const Scene& scene, const GpuServices&) {
  return 2.0 * std::atan(scene.params.at("roughness")[0]);
}

TechniqueData makeMerlData(const Scene& scene) {
  return merlBrdfTechniqueData(scene.measured->brdf);
}

TechniqueData makeMerlThetaH(const Scene& scene, const GpuServices&) {
  return merlThetaHTechniqueData(scene.measured->thetaHTable());
}

TechniqueData makeMerlTable(const Scene& scene, const GpuServices&) {
  return halfVectorTableTechniqueData(scene.measured->sampleTable());
}

TechniqueData makeBrdfTab(const Scene& scene, const GpuServices& gpu) {
  return halfVectorTableTechniqueData(*gpu.tabulateBrdf(scene));
}

const BrdfInfo kBrdfs[] = {
    {"lambert",
     "diffuse: f = albedo / pi",
     "brdf/lambert.glsl",
     {{"albedo", ParamType::Color, 0.0, 1.0, {0.8, 0.8, 0.8}, "diffuse reflectance"}},
     "cosine",
     [](const Scene&, const GpuServices&) { return 0.0; }},
    {"ggx",
     "metallic-roughness GGX microfacet (Walter 2007) + Lambert diffuse",
     "brdf/ggx.glsl",
     {{"color", ParamType::Color, 0.0, 1.0, {0.95, 0.64, 0.54}, "base color (diffuse albedo, metal F0)"},
      {"roughness", ParamType::Float, 1e-3, 1.0, {0.25, 0, 0}, "GGX alpha"},
      {"metallic", ParamType::Float, 0.0, 1.0, {1.0, 0, 0}, "0 dielectric (F0 = 0.04), 1 metal"}},
     "ggx-vndf",
     ggxLobeWidth},
    {"merl",
     "MERL measured isotropic BRDF read from a .binary file, nearest bin as MERL's reference code",
     "brdf/merl.glsl",
     {},
     "merl-table",
     [](const Scene& scene, const GpuServices&) { return scene.measured->lobeWidth(); },
     ".binary",
     makeMerlData},
};

// A CPU twin's pdf, the twin kept alive by the function.
template <typename Sampler>
std::function<double(glm::dvec3)> pdfOf(Sampler sampler) {
  auto shared = std::make_shared<const Sampler>(std::move(sampler));
  return [shared](glm::dvec3 w) { return shared->pdf(w); };
}

std::function<double(glm::dvec3)> envOtMapsPdf(const EnvImage& image,
                                               double (*pdf)(const EnvOtSamplerMaps&, glm::dvec3)) {
  auto maps = std::make_shared<const EnvOtSamplerMaps>(envOtSamplerMaps(image));
  return [maps, pdf](glm::dvec3 w) { return pdf(*maps, w); };
}

const EnvTechniqueInfo kEnvTechniques[] = {
    {"uniform", "uniform directions on the sphere (baseline)", "env_technique/uniform.glsl", noData},
    {"cosine", "cosine-weighted hemisphere around the normal (baseline)", "env_technique/cosine.glsl",
     noData},
    {"env-cdf", "marginal/conditional CDF over texels", "env_technique/env_cdf.glsl", envCdfTechniqueData,
     [](const EnvImage& image) { return pdfOf(EnvCdfSampler(buildEnvCdf(image))); }},
    {"env-hier", "hierarchical 2x2 mip-pyramid warp", "env_technique/env_hier.glsl",
     [](const EnvImage& image) { return envHierTechniqueData(image); },
     [](const EnvImage& image) { return pdfOf(EnvHierSampler(buildEnvHier(image))); }},
    {"env-ot", "optimal-transport grid made texel-exact: rows, cells, then texel pieces by CDF",
     "env_technique/env_ot.glsl", [](const EnvImage& image) { return envOtTechniqueData(image); },
     [](const EnvImage& image) { return pdfOf(EnvOtSampler(buildEnvOt(image))); }},
    {"env-ot-inv", "optimal-transport map, tabulated inverse: one bilinear lookup per sample",
     "env_technique/env_ot_inv.glsl", envOtInvTechniqueData,
     [](const EnvImage& image) { return envOtMapsPdf(image, envOtInvPdf); }, EvaluatedOtMap::Inverse},
    {"env-ot-fwd", "optimal-transport forward quad mesh inverted per sample (quadtree point location)",
     "env_technique/env_ot_fwd.glsl", envOtFwdTechniqueData,
     [](const EnvImage& image) { return envOtMapsPdf(image, envOtFwdPdf); }, EvaluatedOtMap::Forward},
};

bool isBrdf(const BrdfInfo& brdf, const char* name) {
  return brdf.name == name && brdf.evalSource.empty();  // a .brdf file may be called "ggx" too
}

const BrdfTechniqueInfo kBrdfTechniques[] = {
    {"cosine", "cosine-weighted hemisphere", "brdf_technique/cosine.glsl", "any BRDF", nullptr, nullptr},
    {"ggx-vndf", "GGX visible normals (Heitz 2018) + cosine for the diffuse lobe",
     "brdf_technique/ggx_vndf.glsl", "ggx", [](const BrdfInfo& b) { return isBrdf(b, "ggx"); }, nullptr},
    {"merl-thetah", "1D inverse CDF over MERL's theta_h bins, phi_h uniform (baseline)",
     "brdf_technique/merl_thetah.glsl", "merl", [](const BrdfInfo& b) { return isBrdf(b, "merl"); },
     makeMerlThetaH},
    {"merl-table", "per-theta_o 2D tables of f cos over the half vector (sqrt-warped theta_h x phi_h)",
     "brdf_technique/half_vector_table.glsl", "merl", [](const BrdfInfo& b) { return isBrdf(b, "merl"); },
     makeMerlTable},
    {"brdf-tab",
     "merl-table's tables of f cos over the half vector, tabulated on the GPU from the compiled BRDF",
     "brdf_technique/half_vector_table.glsl", "any BRDF", nullptr, makeBrdfTab},
    {"isfunc",
     "the file's own sampling routine: a .brdf file's sampleBRDF and pdfBRDF (its ::begin isFunc section) or "
     "an ALTA function's closed-form lobes",
     "brdf_technique/isfunc.glsl",
     ".brdf files whose isFunc defines sampleBRDF and pdfBRDF; ALTA function files without a rational "
     "function",
     [](const BrdfInfo& b) { return b.hasSampleHook; }, nullptr},
    {"rgl-vndf", "the .bsdf file's own luminance and VNDF warps (Dupuy & Jakob 2018)",
     "brdf_technique/rgl_vndf.glsl", "RGL-EPFL .bsdf files", isRglBrdf, nullptr},
};

const SequenceInfo kSequences[] = {
    {"random", "independent uniform points (PCG hash)", "sequence/random.glsl"},
    {"sobol", "Owen-scrambled Sobol (randomized QMC, Burley 2020)", "sequence/sobol.glsl"},
    {"cp-shared", "one shared Sobol point set, Cranley-Patterson-shifted per pixel",
     "sequence/cp_shared.glsl"},
};

const StrategyInfo kStrategies[] = {
    {.id = Strategy::SingleEnv,
     .name = "single-env",
     .description = "one env technique alone",
     .part = "strategy/single_env.glsl",
     .usesEnvTechnique = true},
    {.id = Strategy::SingleBrdf,
     .name = "single-brdf",
     .description = "one BRDF technique alone",
     .part = "strategy/single_brdf.glsl",
     .usesBrdfTechnique = true},
    {.id = Strategy::Mis,
     .name = "mis",
     .description = "multiple importance sampling of an env and a BRDF technique (Veach 1995)",
     .part = "strategy/mis.glsl",
     .usesEnvTechnique = true,
     .envTechniqueChosen = true,
     .usesBrdfTechnique = true,
     .misWeights = true,
     .misSplit = true,
     .drawsPerSample = 2},
    {.id = Strategy::Ris,
     .name = "ris",
     .description = "resampled importance sampling of env candidates by f cos (Talbot 2005)",
     .part = "strategy/ris.glsl",
     .usesEnvTechnique = true,
     .envTechniqueChosen = true,
     .risCandidates = true},
    {.id = Strategy::Product,
     .name = "product",
     .description = "env x f cos per pixel over a level of env-hier's pyramid",
     .part = "strategy/product.glsl",
     .usesEnvTechnique = true,
     .buildsProductTable = true},
    {.id = Strategy::ProductMis,
     .name = "product-mis",
     .description = "the product under two-sample MIS with a BRDF technique",
     .part = "strategy/product_mis.glsl",
     .usesEnvTechnique = true,
     .usesBrdfTechnique = true,
     .misWeights = true,
     .drawsPerSample = 2,
     .buildsProductTable = true},
    {.id = Strategy::ProductWarp,
     .name = "product-warp",
     .description = "warp composition: f cos per pixel over an env technique's unit square (Hart 2020)",
     .part = "strategy/product_warp.glsl",
     .usesEnvTechnique = true,
     .buildsProductTable = true},
};

// The methods beyond one env technique alone; those come first, one per entry of kEnvTechniques (methods()).
const MethodInfo kCombinedMethods[] = {
    {"brdf", "the BRDF technique alone", Strategy::SingleBrdf, ""},
    {"mis", "two-sample MIS of the env and BRDF techniques (one-sample with a MIS split)", Strategy::Mis, ""},
    {"ris", "RIS: candidates from the env technique resampled by f cos (Talbot 2005)", Strategy::Ris, ""},
    {"product", "env x f cos per pixel over env-hier's pyramid, finished in its texel tables",
     Strategy::Product, "env-hier", envHierProductTechniqueData},
    {"product-mis", "two-sample MIS of 'product' and the BRDF technique", Strategy::ProductMis, "env-hier",
     envHierProductTechniqueData},
    {"product-warp", "warp composition (Hart 2020): per pixel, f cos tabulated over env-hier's unit square",
     Strategy::ProductWarp, "env-hier", envHierProductTechniqueData},
    {"product-warp-ot", "warp composition (Hart 2020) over env-ot's unit square", Strategy::ProductWarp,
     "env-ot", [](const EnvImage& image) { return envOtProductTechniqueData(image); }},
};

// Every env technique alone, in kEnvTechniques' order, then kCombinedMethods: a new env technique is a
// method by itself.
const std::vector<MethodInfo>& methods() {
  static const std::vector<MethodInfo> list = [] {
    std::vector<MethodInfo> all;
    for (const EnvTechniqueInfo& t : kEnvTechniques)
      all.push_back({t.name, "env technique '" + t.name + "' alone", Strategy::SingleEnv, t.name, nullptr});
    all.insert(all.end(), std::begin(kCombinedMethods), std::end(kCombinedMethods));
    return all;
  }();
  return list;
}

template <typename T>
const T& findIn(std::span<const T> list, const std::string& name, Setting setting) {
  for (const auto& item : list)
    if (item.name == name) return item;
  throw SettingError(setting, "unknown ", " '" + name + "'; valid: " + joinNames(list, &T::name));
}

}  // namespace

std::span<const BrdfInfo> brdfRegistry() {
  return kBrdfs;
}
std::span<const EnvTechniqueInfo> envTechniqueRegistry() {
  return kEnvTechniques;
}
std::span<const BrdfTechniqueInfo> brdfTechniqueRegistry() {
  return kBrdfTechniques;
}
std::span<const SequenceInfo> sequenceRegistry() {
  return kSequences;
}
std::span<const MethodInfo> methodRegistry() {
  return methods();
}

std::span<const StrategyInfo> strategyRegistry() {
  return kStrategies;
}

const StrategyInfo& findStrategy(Strategy id) {
  for (const StrategyInfo& s : kStrategies)
    if (s.id == id) return s;
  throw Error("findStrategy: a strategy without a registry entry");
}

const StrategyInfo& MethodInfo::strategyInfo() const {
  return findStrategy(strategy);
}

const BrdfInfo& findBrdf(const std::string& name) {
  return findIn(brdfRegistry(), name, Setting::Brdf);
}

const BrdfInfo* findBrdfForArgument(const std::string& nameOrPath) {
  const std::string extension = std::filesystem::path(nameOrPath).extension().string();
  if (extension == ".brdf" || extension == ".bparam") return nullptr;
  for (const auto& b : brdfRegistry())
    if (!b.fileExtension.empty() && extension == b.fileExtension) return &b;
  std::string valid;
  for (const auto& b : brdfRegistry())
    if (b.fileExtension.empty()) {
      if (b.name == nameOrPath) return &b;
      valid += (valid.empty() ? "" : ", ") + b.name;
    }
  for (const auto& b : brdfRegistry())
    if (!b.fileExtension.empty() && b.name == nameOrPath)
      throw SettingError(Setting::Brdf, "",
                         " " + nameOrPath + ": this BRDF is read from a file; give the path of a " +
                             b.fileExtension + " file");
  valid += ", " + materialFileKindsText();
  throw SettingError(Setting::Brdf, "unknown ", " '" + nameOrPath + "'; valid: " + valid);
}
const EnvTechniqueInfo& findEnvTechnique(const std::string& name) {
  return findIn(envTechniqueRegistry(), name, Setting::EnvSampler);
}
const BrdfTechniqueInfo& findBrdfTechnique(const std::string& name) {
  return findIn(brdfTechniqueRegistry(), name, Setting::BrdfSampler);
}
const SequenceInfo& findSequence(const std::string& name) {
  return findIn(sequenceRegistry(), name, Setting::Sequence);
}
const MethodInfo& findMethod(const std::string& name) {
  return findIn(methodRegistry(), name, Setting::Method);
}

}  // namespace iblx
