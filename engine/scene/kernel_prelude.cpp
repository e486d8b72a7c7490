// Prelude assembly for the integrator, reference and BRDF-evaluation kernels (kernel_prelude.h).
#include "engine/scene/kernel_prelude.h"

#include "engine/core/error.h"
#include "engine/scene/brdf_params.h"

#include <regex>
#include <set>
#include <sstream>

namespace iblx {
namespace {

std::string describeTables(const std::vector<KernelTable>& tables) {
  std::string list;
  for (const KernelTable& t : tables) {
    if (!list.empty()) list.append(", ");
    list.append(t.name)
        .append(" (")
        .append(std::to_string(t.words))
        .append("-word, ")
        .append(t.owner)
        .append(")");
  }
  return list;
}

std::vector<KernelTable> allTables(const KernelParts& parts) {
  std::vector<KernelTable> tables = frameTables();
  tables.insert(tables.end(), parts.tables.begin(), parts.tables.end());
  return tables;
}

}  // namespace

std::vector<KernelTable> frameTables() {
  const std::string owner = "the frame";
  return {{"envRgb", 1, kFrameSet, 2, owner},
          {"envRows", 4, kFrameSet, 3, owner},
          {"envRgb1", 1, kFrameSet, 5, owner},
          {"envRgb2", 1, kFrameSet, 6, owner},
          {"envRgb3", 1, kFrameSet, 7, owner}};
}

std::uint32_t KernelParts::bindTables(std::uint32_t set, std::uint32_t firstBinding,
                                      const TechniqueData& data, const std::string& owner) {
  std::uint32_t binding = firstBinding;
  for (const TechniqueTable& table : data.tables) {
    for (const KernelTable& bound : allTables(*this))
      if (bound.name == table.name)
        throw Error("kernel " + kernel + ": table '" + table.name + "' of " + owner +
                    " is already bound by " + bound.owner + "; table names must be unique within a kernel");
    tables.push_back({table.name, table.words, set, binding++, owner});
  }
  defines.insert(defines.end(), data.defines.begin(), data.defines.end());
  return binding;
}

std::string assemblePrelude(const KernelParts& parts) {
  std::ostringstream s;
  s << "#version 460\n#extension GL_GOOGLE_include_directive : require\n";
  for (const char* interface : {"sequence", "env_technique", "brdf", "brdf_technique", "strategy"})
    s << "#include \"interfaces/" << interface << ".glsl\"\n";
  for (const auto& [name, value] : parts.defines) s << "#define " << name << " " << value << "\n";
  std::set<std::string> names;
  for (const KernelTable& t : allTables(parts)) {
    if (!names.insert(t.name).second)
      throw Error("kernel " + parts.kernel + ": two tables are named '" + t.name + "'");
    s << "#define IBLX_SET_" << t.name << " " << t.set << "\n#define IBLX_BINDING_" << t.name << "_W"
      << t.words << " " << t.binding << "\n";
  }
  s << parts.brdfParamBlock;
  s << "#include \"" << parts.kernel << "\"\n";
  for (const auto& part : parts.parts) s << "#include \"" << part << "\"\n";
  return s.str();
}

std::string explainMissingTable(const KernelParts& parts, const std::string& glslangMessage) {
  // glslang names the first undefined identifier: IBLX_SET_<name> when no table of that name is bound,
  // IBLX_BINDING_<name>_W<words> when it is bound at another width.
  static const std::regex undefined(
      R"(^(.*?): '(?:IBLX_SET_(\w+)|IBLX_BINDING_(\w+)_W(\d+))' : undeclared identifier)");
  std::smatch m;
  if (!std::regex_search(glslangMessage, m, undefined)) return {};
  const std::string location = m[1];
  const bool missing = m[2].matched;
  const std::string name = missing ? m[2].str() : m[3].str();
  const std::vector<KernelTable> tables = allTables(parts);
  std::string message = location + ": ";
  if (missing) {
    message.append("the part reads table '")
        .append(name)
        .append("', which no builder of kernel ")
        .append(parts.kernel);
    message.append(" provides; the kernel binds: ").append(describeTables(tables));
    return message;
  }
  for (const KernelTable& t : tables)
    if (t.name == name)
      return message.append("the part reads table '")
          .append(name)
          .append("' with ")
          .append(m[4].str())
          .append("-word elements, but ")
          .append(t.owner)
          .append(" provides ")
          .append(std::to_string(t.words))
          .append("-word elements");
  return {};
}

KernelParts brdfKernelParts(std::string kernel, const BrdfInfo& brdf, const TechniqueData& brdfData,
                            std::vector<std::string> parts) {
  if (parts.empty()) parts.push_back(brdf.evalPart);
  KernelParts k{std::move(kernel), std::move(parts), paramBlockGlsl(brdf), {}, {}, {}};
  k.bindTables(kBrdfSet, kBrdfDataBinding, brdfData, "BRDF " + brdf.name);
  if (!brdf.evalSource.empty()) k.sources.emplace_back(brdf.evalPart, brdf.evalSource);
  return k;
}

std::vector<std::pair<std::string, std::string>> EnvChunking::defines() const {
  if (chunks <= 1) return {};
  return {{"ENV_RADIANCE_CHUNKS", std::to_string(chunks)},
          {"ENV_TEXELS_PER_CHUNK", std::to_string(texelsPerChunk) + "u"}};
}

static_assert(productTableWords(kEnvProductGridWidth, kEnvProductGridRows) <= kProductTableStride,
              "a pixel's product table holds every layout's nodes");

KernelParts integratorParts(const Scene& scene, const TechniqueData& brdfData, const EnvChunking& chunking,
                            const ResolvedMethod& method, const TechniqueData& envData,
                            const TechniqueData& brdfTechniqueData, IntegratorMode mode,
                            ProductTableChunks productTables) {
  // The sequence, the env technique, the BRDF, the BRDF technique and the strategy, in that order.
  std::vector<std::string> parts{method.sequence->part};
  if (method.envTechnique) parts.push_back(method.envTechnique->part);
  parts.push_back(scene.brdf->evalPart);
  if (method.brdfTechnique) parts.push_back(method.brdfTechnique->part);
  const StrategyInfo& strategy = method.method->strategyInfo();
  parts.push_back(strategy.part);
  KernelParts k = brdfKernelParts("integrate.comp", *scene.brdf, brdfData, std::move(parts));
  if (mode == IntegratorMode::RecordPixel) {
    k.defines.emplace_back("IBLX_RECORD_SAMPLES", "1");
    k.defines.emplace_back("SAMPLE_RECORD_BINDING", std::to_string(kSampleRecordBinding));
    k.defines.emplace_back("SAMPLE_RECORD_DRAWS", std::to_string(method.drawsPerSample()) + "u");
  }
  if (mode == IntegratorMode::ProductTables && productTables.chunks == 0)
    throw Error("integratorParts: the product-table kernel needs the tables' buffers");
  if (productTables.chunks > 0) {
    if (mode == IntegratorMode::RecordPixel || !strategy.buildsProductTable)
      throw Error(
          "integratorParts: product tables in a buffer need a product strategy's image or table mode");
    if (productTables.chunks > kProductTableMaxChunks || productTables.pixelsPerChunk == 0)
      throw Error("integratorParts: product tables in " + std::to_string(productTables.chunks) +
                  " chunks of " + std::to_string(productTables.pixelsPerChunk) + " pixels");
    k.defines.emplace_back("PRODUCT_TABLE_BINDING", std::to_string(kProductTableBinding));
    k.defines.emplace_back("PRODUCT_TABLE_STRIDE", std::to_string(kProductTableStride) + "u");
    k.defines.emplace_back("PRODUCT_TABLE_CHUNKS", std::to_string(productTables.chunks));
    k.defines.emplace_back("PRODUCT_TABLE_PIXELS_PER_CHUNK",
                           std::to_string(productTables.pixelsPerChunk) + "u");
    if (mode == IntegratorMode::ProductTables) k.defines.emplace_back("PRODUCT_TABLE_BUILD", "1");
  }
  if (method.envTechnique)
    k.bindTables(kEnvTechniqueSet, 0, envData, "env technique " + method.envTechnique->name);
  if (method.brdfTechnique)
    k.bindTables(kBrdfSet, kBrdfDataBinding + std::uint32_t(brdfData.tables.size()), brdfTechniqueData,
                 "BRDF technique " + method.brdfTechnique->name);
  const auto chunkDefines = chunking.defines();
  k.defines.insert(k.defines.end(), chunkDefines.begin(), chunkDefines.end());
  if (method.misOneSample) k.defines.emplace_back("MIS_ONE_SAMPLE", "1");
  if (strategy.risCandidates)
    k.defines.emplace_back("RIS_CANDIDATES", std::to_string(method.risCandidates) + "u");
  return k;
}

KernelParts referenceParts(const Scene& scene, const TechniqueData& brdfData, const EnvChunking& chunking) {
  // No BRDF technique in the reference: only the BRDF's own tables.
  KernelParts k = brdfKernelParts("reference.comp", *scene.brdf, brdfData);
  const auto chunkDefines = chunking.defines();
  k.defines.insert(k.defines.end(), chunkDefines.begin(), chunkDefines.end());
  return k;
}

}  // namespace iblx
