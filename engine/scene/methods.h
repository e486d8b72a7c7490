// The registry (docs/DESIGN.md §4): every BRDF, technique, sequence and method iblx knows, in one
// explicit list each. The CLI, --list-methods, the benchmark and the tests iterate over these lists; adding a
// method is one builder (with its TechniqueData, engine/sampling/), one GLSL part and one line in
// methods.cpp.
#pragma once

#include "engine/core/params.h"
#include "engine/io/env_image.h"
#include "engine/sampling/technique_data.h"

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
struct MerlTableData;  // engine/sampling/merl_sampling.h

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

struct EnvTechniqueInfo {
  std::string name;
  std::string description;
  std::string part;  // implements interfaces/env_sampler.glsl
  std::function<TechniqueData(const EnvImage&)> build;
};

struct BrdfTechniqueInfo {
  std::string name;
  std::string description;
  std::string part;         // implements interfaces/brdf_sampler.glsl
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

// ---- methods (what --method selects) ----------------------------------------------------------------------
// Product and ProductMis sample env x f cos per pixel over a level of env-hier's pyramid
// (engine/sampling/env_product.h), alone or under two-sample MIS with the BRDF technique; ProductWarp over a
// uniform grid of the env technique's unit square (warp composition): env-hier's (product-warp) or env-ot's
// (product-warp-ot, engine/sampling/env_ot_product.h).
enum class Strategy { SingleEnv, SingleBrdf, Mis, Ris, Product, ProductMis, ProductWarp };
// The strategies that build a per-pixel product table (shaders/lib/product_sampling.glsl).
inline bool buildsProductTable(Strategy s) {
  return s == Strategy::Product || s == Strategy::ProductMis || s == Strategy::ProductWarp;
}

struct MethodInfo {
  std::string name;
  std::string description;
  Strategy strategy;
  // Fixed env technique of SingleEnv and the product methods; MIS and RIS take the spec's env technique.
  std::string envTechnique;
  // The env technique's tables with more that the strategy reads, built in place of the technique's own
  // (the product strategies add their node tables to env-hier's); null = the technique's build.
  std::function<TechniqueData(const EnvImage&)> envData;
};

std::span<const BrdfInfo> brdfRegistry();
std::span<const EnvTechniqueInfo> envTechniqueRegistry();
std::span<const BrdfTechniqueInfo> brdfTechniqueRegistry();
std::span<const SequenceInfo> sequenceRegistry();
std::span<const MethodInfo> methodRegistry();
std::string strategyPart(Strategy strategy);

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
