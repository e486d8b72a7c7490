// The registry (DESIGN §2, STYLE "For iblx" 7): every BRDF, technique, sequence and method iblx knows, in one
// explicit list each. The CLI, --list-methods, the benchmark and the tests iterate over these lists; adding a
// method is one builder, one GLSL part and one line in methods.cpp.
#pragma once

#include "engine/core/params.h"
#include "engine/io/env_image.h"

#include <array>
#include <cstdint>
#include <cstddef>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace iblx {

struct Scene;          // engine/render/scene.h
class VulkanContext;   // engine/vk/context.h
class ShaderCompiler;  // engine/vk/shader_compiler.h

// What a builder that needs the GPU gets (brdf-tab tabulates the compiled BRDF; the reference measures a
// .brdf file's lobe).
struct GpuServices {
  const VulkanContext& context;
  ShaderCompiler& compiler;
};

// GPU data of a technique or of a BRDF read from a file: read-only tables in binding order (each with the
// 32-bit words per element its GLSL part reads it with: 1, 2 or 4, shaders/lib/table.glsl), and preprocessor
// definitions for its GLSL part (sizes known at build time, so most loops over them have constant trip counts
// and unroll; they are part of the SPIR-V cache key through the prelude).
struct TechniqueData {
  std::vector<std::vector<std::byte>> buffers;
  std::vector<std::string> names;
  std::vector<uint32_t> elementWords;
  std::vector<std::pair<std::string, std::string>> defines;

  template <typename T>
  void add(std::string name, std::span<const T> values, uint32_t wordsPerElement = 1) {
    const auto* p = reinterpret_cast<const std::byte*>(values.data());
    buffers.emplace_back(p, p + values.size_bytes());
    names.push_back(std::move(name));
    elementWords.push_back(wordsPerElement);
  }
};

// ---- BRDFs
// -------------------------------------------------------------------------------------------------

struct BrdfInfo {
  std::string name;
  std::string description;
  std::string evalPart;  // shaders/ path implementing interfaces/brdf.glsl
  std::vector<ParamDecl> params;
  std::string bestSampler;  // BRDF technique used when --brdf-sampler is not given
  // Angular width (radians) of the narrowest lobe of the scene's BRDF; 0 when the BRDF is smooth.
  // The reference uses it to refine its quadrature around the mirror direction.
  std::function<double(const Scene&, const GpuServices&)> lobeWidth;
  // A BRDF read from a file (`--brdf FILE`) names the file extension it reads; empty for built-ins.
  std::string fileExtension;
  // Buffers its eval part reads, made from the scene (set 3 from binding BRDF_DATA_BINDING on); may be null.
  std::function<TechniqueData(const Scene&)> data;
  // A BRDF made at run time (a .brdf file, engine/render/analytic_brdf.h): the GLSL text of evalPart, which
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
  // Its tables, made from the scene (set 3 from binding BRDF_SAMPLER_BINDING on); may be null.
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
// uniform grid of env-hier's unit square (warp composition).
enum class Strategy { SingleEnv, SingleBrdf, Mis, Ris, Product, ProductMis, ProductWarp };

struct MethodInfo {
  std::string name;
  std::string description;
  Strategy strategy;
  // Fixed env technique of SingleEnv and the product methods; MIS and RIS take --env-sampler.
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

// Lookups that throw iblx::Error listing the valid names (`what` names the flag, e.g. "--method").
const BrdfInfo& findBrdf(const std::string& name);
// --brdf's argument without reading any file: a built-in, a file-based registry entry (MERL .binary) or
// null for a .brdf / .bparam file (engine/render/scene.h's loadBrdfArgument reads those). Throws for an
// unknown name.
const BrdfInfo* findBrdfForArgument(const std::string& nameOrPath);
const EnvTechniqueInfo& findEnvTechnique(const std::string& name, const std::string& what = "--env-sampler");
const BrdfTechniqueInfo& findBrdfTechnique(const std::string& name,
                                           const std::string& what = "--brdf-sampler");
const SequenceInfo& findSequence(const std::string& name);
const MethodInfo& findMethod(const std::string& name);

// Human-readable registry (for --list-methods), and one BRDF with its parameters.
std::string describeRegistry();
std::string describeBrdf(const BrdfInfo& brdf);

// Fills defaults, parses "r,g,b" / "x" / "0|1|true|false" strings, range-checks; throws on unknown names.
ParamValues resolveParams(const BrdfInfo& brdf,
                          const std::vector<std::pair<std::string, std::string>>& given);
// Packs values into the BRDF parameter block: one 16-byte slot per parameter in declaration order.
std::vector<float> packParams(const BrdfInfo& brdf, const ParamValues& values);
// GLSL declaration of that block (set 3, binding 0) with each parameter as a plain name.
std::string paramBlockGlsl(const BrdfInfo& brdf);

}  // namespace iblx
