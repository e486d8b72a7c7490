// The registry (docs/DESIGN.md §4): every BRDF, technique, sequence and method iblx knows, in one
// explicit list each. The CLI, --list-methods, the benchmark and the tests iterate over these lists; adding a
// method is one builder (with its TechniqueData, engine/sampling/), one GLSL part and one line in
// methods.cpp.
#pragma once

#include "engine/core/params.h"
#include "engine/io/env_image.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace iblx {

struct Scene;          // engine/scene/scene.h
struct MerlTableData;  // engine/sampling/brdf/merl_sampling.h

// What a builder that needs the GPU gets: brdf-tab tabulates the compiled BRDF, and a .brdf file's lobe is
// measured by evaluating it. The GPU part implements it (engine/render/brdf_tabulation.h, VulkanServices), so
// the registry itself is CPU code.
class GpuServices {
 public:
  virtual ~GpuServices() = default;
  // brdf-tab's half-vector tables of the scene's compiled BRDF, kept per BRDF source and parameter values.
  virtual std::shared_ptr<const MerlTableData> tabulateBrdf(const Scene& scene) const = 0;
  // Angular width (radians) of the narrowest lobe of the scene's BRDF; 0 when it has no peak.
  virtual double measureLobeWidth(const Scene& scene) const = 0;
};

// ---- BRDFs
// -------------------------------------------------------------------------------------------------

struct BrdfInfo {
  std::string name;
  std::string description;
  std::string evalPart;  // shaders/ path implementing interfaces/brdf.glsl
  std::vector<ParamDecl> params;
  std::string bestSampler;  // BRDF technique used when the method spec names none
  // Angular width (radians) of the narrowest lobe of the scene's BRDF; 0 when the BRDF is smooth.
  // The reference uses it to refine its quadrature around the mirror direction.
  std::function<double(const Scene&, const GpuServices&)> lobeWidth;
  // A BRDF read from a file (`--brdf FILE`) names the file extension it reads; empty for built-ins.
  std::string fileExtension;
  // Tables its eval part reads, made from the scene (set 3 from kBrdfDataBinding on, kernel_prelude.h); may
  // be null.
  std::function<TechniqueData(const Scene&)> data;
  // A BRDF made at run time (a .brdf file, engine/scene/analytic_brdf.h): the GLSL text of evalPart, which
  // every compile of a kernel that includes it registers with the compiler (KernelParts::sources).
  std::string evalSource;
  // The file's own sampling routine (::begin isFunc with sampleBRDF and pdfBRDF): technique `isfunc`.
  bool hasSampleHook = false;
};

// Which optimal-transport map a technique evaluates per sample (engine/ot/): `otmap --diagnose` reports that
// map's round trip and convexity beside the technique's pdf.
enum class EvaluatedOtMap { None, Inverse, Forward };

struct EnvTechniqueInfo {
  std::string name;
  std::string description;
  std::string part;  // implements interfaces/env_technique.glsl
  std::function<TechniqueData(const EnvImage&)> build;
  // The solid-angle pdf of its CPU twin built for a map, for diagnostics that integrate it (`otmap
  // --diagnose`); null for the baselines, whose pdf depends on no table.
  std::function<std::function<double(glm::dvec3)>(const EnvImage&)> cpuPdf;
  EvaluatedOtMap otMap = EvaluatedOtMap::None;
};

struct BrdfTechniqueInfo {
  std::string name;
  std::string description;
  std::string part;         // implements interfaces/brdf_technique.glsl
  std::string appliesText;  // for --list-methods, e.g. "any BRDF", "ggx"
  // Whether it can sample a BRDF; null = every BRDF.
  std::function<bool(const BrdfInfo&)> applies;
  // Its tables, made from the scene (set 3, after the BRDF's own); may be null.
  std::function<TechniqueData(const Scene&, const GpuServices&)> build;
  bool appliesTo(const BrdfInfo& brdf) const { return !applies || applies(brdf); }
};

struct SequenceInfo {
  std::string name;
  std::string description;
  std::string part;  // implements interfaces/sequence.glsl
};

// ---- strategies (how an estimate combines techniques) -----------------------------------------------------
// Each strategy's capabilities are data: the scene resolver, the kernel prelude, the CLI, the viewer and the
// tests read them, so a strategy is one entry of strategyRegistry() and one GLSL part (docs/DESIGN.md §4).
// Product and ProductMis sample env x f cos per pixel over a level of env-hier's pyramid
// (engine/sampling/product/env_hier_product.h), alone or under two-sample MIS with the BRDF technique;
// ProductWarp over a uniform grid of the env technique's unit square (warp composition): env-hier's
// (product-warp) or env-ot's (product-warp-ot, engine/sampling/product/env_ot_product.h).
enum class Strategy { SingleEnv, SingleBrdf, Mis, Ris, Product, ProductMis, ProductWarp };

struct StrategyInfo {
  Strategy id;
  std::string name;
  std::string description;
  std::string part;  // implements interfaces/strategy.glsl
  // Which techniques it draws from. An env technique is named by the method (env techniques alone, the
  // product methods) or, where envTechniqueChosen, by --env-sampler (default env-cdf).
  bool usesEnvTechnique = false;
  bool envTechniqueChosen = false;
  bool usesBrdfTechnique = false;  // --brdf-sampler, default the BRDF's best sampler
  // Its options: --mis (balance or power weights), --mis-split and --mis-compensation (a one-sample split of
  // two techniques, and the env technique's compensated pdf), --ris-candidates.
  bool misWeights = false;
  bool misSplit = false;
  bool risCandidates = false;
  uint32_t drawsPerSample = 1;  // directions drawn per sample (a one-sample split draws one)
  // Whether it builds per-pixel product tables (shaders/lib/product_sampling.glsl).
  bool buildsProductTable = false;
  // A measurement-only strategy is listed apart and offered by converge, bench and study, not by render or
  // the viewer.
  bool measurementOnly = false;
};

struct MethodInfo {
  std::string name;
  std::string description;
  Strategy strategy;  // strategyInfo() has its capabilities
  // Fixed env technique of SingleEnv and the product methods; MIS and RIS take the spec's env technique.
  std::string envTechnique;
  // The env technique's tables with more that the strategy reads, built in place of the technique's own
  // (the product strategies add their node tables to env-hier's); null = the technique's build.
  std::function<TechniqueData(const EnvImage&)> envData;
  const StrategyInfo& strategyInfo() const;
};

std::span<const BrdfInfo> brdfRegistry();
std::span<const EnvTechniqueInfo> envTechniqueRegistry();
std::span<const BrdfTechniqueInfo> brdfTechniqueRegistry();
std::span<const SequenceInfo> sequenceRegistry();
std::span<const StrategyInfo> strategyRegistry();
std::span<const MethodInfo> methodRegistry();
const StrategyInfo& findStrategy(Strategy id);

// Lookups that throw a SettingError (engine/core/setting.h) listing the valid names.
const BrdfInfo& findBrdf(const std::string& name);
// --brdf's argument without reading any file: a built-in, a file-based registry entry (MERL .binary) or
// null for a .brdf / .bparam file (engine/scene/scene.h's loadBrdfArgument reads those). Throws for an
// unknown name.
const BrdfInfo* findBrdfForArgument(const std::string& nameOrPath);
const EnvTechniqueInfo& findEnvTechnique(const std::string& name);
const BrdfTechniqueInfo& findBrdfTechnique(const std::string& name);
const SequenceInfo& findSequence(const std::string& name);
const MethodInfo& findMethod(const std::string& name);

}  // namespace iblx
