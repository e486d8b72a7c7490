// The registry lists. Each line is one BRDF, technique, sequence or method; nothing else names them.
#include "engine/render/methods.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/render/scene.h"
#include "engine/sampling/env_cdf.h"
#include "engine/sampling/env_hier.h"
#include "engine/sampling/env_product.h"
#include "engine/sampling/latlong_texel.h"
#include "engine/sampling/merl_sampling.h"
#include "engine/sampling/ot_cache.h"
#include "engine/sampling/ot_map.h"
#include "engine/sampling/ot_solver.h"
#include "engine/sampling/ot_sun.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace iblx {
namespace {

TechniqueData noData(const EnvImage&) {
  return {};
}

TechniqueData makeEnvCdf(const EnvImage& image) {
  const EnvCdfData cdf = buildEnvCdf(image);
  std::vector<float> packed(cdf.marginalCdf);  // layout of shaders/env/env_cdf.glsl: marginal, then rows
  packed.insert(packed.end(), cdf.conditionalCdf.begin(), cdf.conditionalCdf.end());
  std::vector<std::uint32_t> guide(cdf.marginalGuide);
  guide.insert(guide.end(), cdf.conditionalGuide.begin(), cdf.conditionalGuide.end());
  TechniqueData data;
  data.add("env-cdf tables", std::span<const float>(packed));
  data.add("env-cdf guide", std::span<const std::uint32_t>(guide));
  data.defines = {{"ENV_CDF_ROW_GUIDE_SIZE", std::to_string(cdf.rowGuideCells) + "u"},
                  {"ENV_CDF_COLUMN_GUIDE_SIZE", std::to_string(cdf.columnGuideCells) + "u"}};
  return data;
}

// env-hier's tables (bindings 0-2) from its pyramid.
TechniqueData packEnvHier(const EnvHierSampler& sampler) {
  const EnvHierGpuData& hier = sampler.gpuData();
  TechniqueData data;
  data.add("env-hier splits", std::span<const glm::vec4>(hier.splits), 4);
  data.add("env-hier guide", std::span<const uint32_t>(hier.guideNodes));
  data.add("env-hier texel rectangles", std::span<const glm::vec4>(hier.texelRects), 4);
  // Sizes are compile-time constants of the part: read from a buffer, lavapipe would load them per lane.
  const auto u = [](uint32_t v) { return std::to_string(v) + "u"; };
  data.defines = {{"ENV_HIER_LEAF_START", u(hier.leafStart)},
                  {"ENV_HIER_GUIDE_SIZE", u(hier.guideSize)},
                  {"ENV_HIER_WIDTH", std::to_string(sampler.data().width)}};
  return data;
}

TechniqueData makeEnvHier(const EnvImage& image) {
  return packEnvHier(EnvHierSampler(buildEnvHier(image)));
}

// env-hier's tables, then the product strategies' from the same pyramid (shaders/lib/product_sampling.glsl):
// bindings 3-4 the pyramid level `product` and `product-mis` choose nodes on, binding 5 the caps of
// `product-warp`'s uniform grid over u (its rectangles are arithmetic).
TechniqueData makeEnvHierProduct(const EnvImage& image) {
  const EnvHierSampler sampler(buildEnvHier(image));
  TechniqueData data = packEnvHier(sampler);
  const EnvProductLevel product = buildEnvProductLevel(sampler);
  const EnvProductLevel grid = buildEnvProductGrid(sampler);
  data.add("env-hier product node rectangles", std::span<const glm::vec4>(product.rects), 4);
  data.add("env-hier product node centres", std::span<const glm::vec4>(product.centers), 4);
  data.add("env-hier product grid centres", std::span<const glm::vec4>(grid.centers), 4);
  const auto u = [](uint32_t v) { return std::to_string(v) + "u"; };
  data.defines.insert(data.defines.end(), {{"PRODUCT_WIDTH", u(product.width)},
                                           {"PRODUCT_ROWS", u(product.rows)},
                                           {"PRODUCT_TEXELS_PER_NODE", u(product.texelsPerNode)},
                                           {"PRODUCT_GRID_WIDTH", u(grid.width)},
                                           {"PRODUCT_GRID_ROWS", u(grid.rows)},
                                           {"PRODUCT_DEFENSIVE", std::to_string(kEnvProductDefensive)}});
  return data;
}

// Grid of the OT map: 256 (the default) or, for smaller maps, the map's height (no finer than its
// rows), at least 32; IBLX_OT_SIZE overrides it (benchmarks).
int otGridSize(const EnvImage& image) {
  if (const char* forced = std::getenv("IBLX_OT_SIZE")) {
    const int n = std::atoi(forced);
    if (n < 8 || n > 2048)
      throw Error("IBLX_OT_SIZE: expected a grid size in [8, 2048], got '" + std::string(forced) + "'");
    return n;
  }
  return std::clamp(image.height, 32, 256);
}

// The OT techniques' map: the sun texels' excess is split off (ot_sun.h) and the map solved for the rest.
struct EnvOtMaps {
  OtSunSplit sun;
  OtMap map;
};

EnvOtMaps solveEnvOtMap(const EnvImage& image) {
  const int n = otGridSize(image);
  EnvOtMaps maps{splitOtSun(texelSamplingWeights(image, "OT density"), image.width, image.height), {}};
  const std::vector<double> density =
      otDensityFromWeights(maps.sun.smoothWeights, image.width, image.height, n);
  maps.map = solveOtMapCached(density, n, OtSolverOptions{}, defaultCacheDir());
  const OtMap& map = maps.map;
  if (map.negativeAreaQuads > 0)
    throw Error("OT map: " + std::to_string(map.negativeAreaQuads) +
                " folded quads at n = " + std::to_string(n));
  if (!map.converged)  // still an exact sampler (its pdf is the map's own), only a less efficient one
    warn("OT map at n = " + std::to_string(n) + " did not converge (L2 " + std::to_string(map.l2) + ", L1 " +
         std::to_string(map.l1) + "); sampling with the best map reached");
  return maps;
}

// A QuadGridMap's vertex images and piece types, the first two buffers a quad map needs on the GPU.
void addQuadMapGeometry(TechniqueData& data, const QuadGridMap& map, const std::string& name) {
  if (map.invalidPieces() > 0)
    throw Error(name + ": " + std::to_string(map.invalidPieces()) +
                " quads of the map are not injective; the sampler would not be exact");
  const std::vector<glm::vec2> vertices(map.image().begin(), map.image().end());
  std::vector<std::uint32_t> pieces(map.pieces().size());
  for (std::size_t c = 0; c < pieces.size(); ++c) pieces[c] = std::uint32_t(map.pieces()[c]);
  data.add(name + " vertices", std::span<const glm::vec2>(vertices), 2);
  data.add(name + " pieces", std::span<const std::uint32_t>(pieces));
}

// Buffers of shaders/lib/quad_grid_map.glsl and lib/ot_sun.glsl, in their binding order (0-6).
TechniqueData packEnvOt(const QuadGridMap& map, const OtSunSplit& sun, int densityGrid,
                        const std::string& name) {
  TechniqueData data;
  addQuadMapGeometry(data, map, name);
  data.add(name + " quadtree", map.nodes(), 2);
  data.add(name + " leaf cells", map.leafCells());
  data.add(name + " sun texels", std::span<const std::uint32_t>(sun.texels));
  data.add(name + " sun cdf", std::span<const float>(sun.cdf));
  data.add(name + " sun rows", std::span<const std::uint32_t>(sun.rowFirst));
  const auto u = [](std::uint32_t v) { return std::to_string(v) + "u"; };
  data.defines = {{"OT_GRID", u(std::uint32_t(map.size()))},
                  {"OT_TREE_DEPTH", u(std::uint32_t(map.treeDepth()))},
                  {"OT_LARGEST_LEAF", u(map.largestLeaf())},
                  {"OT_DENSITY_GRID", u(std::uint32_t(densityGrid))},
                  {"OT_SUN_TEXELS", std::to_string(sun.texels.size())},
                  {"OT_SUN_SHARE_BITS", u(std::bit_cast<std::uint32_t>(sun.sunShare))}};
  return data;
}

TechniqueData makeEnvOtFwd(const EnvImage& image) {
  const EnvOtMaps maps = solveEnvOtMap(image);
  return packEnvOt(forwardMap(maps.map), maps.sun, maps.map.n, "env-ot-fwd");
}

TechniqueData makeEnvOtInv(const EnvImage& image) {
  const EnvOtMaps maps = solveEnvOtMap(image);
  const QuadGridMap forward = forwardMap(maps.map);
  TechniqueData data = packEnvOt(tabulatedInverse(forward, maps.map.n), maps.sun, maps.map.n, "env-ot-inv");
  // Bindings 7-8: the forward map, whose image of a point guesses the point's preimage under the inverse.
  addQuadMapGeometry(data, forward, "env-ot-inv forward");
  return data;
}

double ggxLobeWidth(const Scene& scene, const GpuServices&) {
  return 2.0 * std::atan(scene.params.at("roughness")[0]);
}

TechniqueData makeMerlData(const Scene& scene) {
  TechniqueData data;
  data.add("MERL table", std::span<const float>(scene.measured->brdf.rgb));
  return data;
}

TechniqueData makeMerlThetaH(const Scene& scene, const GpuServices&) {
  TechniqueData data;
  data.add("merl-thetah cdf", std::span<const float>(scene.measured->thetaHTable().cdf));
  return data;
}

TechniqueData makeBrdfTab(const Scene& scene, const GpuServices& gpu) {
  const auto table = tabulateBrdfTable(gpu, scene);
  TechniqueData data;
  data.add("brdf-tab slices", std::span<const float>(table->tables));
  if (table->absolutePhi) data.defines.emplace_back("HALF_VECTOR_TABLE_ABSOLUTE_PHI", "1");
  return data;
}

TechniqueData makeMerlTable(const Scene& scene, const GpuServices&) {
  TechniqueData data;
  data.add("merl-table slices", std::span<const float>(scene.measured->sampleTable().tables));
  return data;
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
     "MERL measured isotropic BRDF, nearest bin as MERL's reference code (--brdf FILE.binary)",
     "brdf/merl.glsl",
     {},
     "merl-table",
     [](const Scene& scene, const GpuServices&) { return scene.measured->lobeWidth(); },
     ".binary",
     makeMerlData},
};

const EnvTechniqueInfo kEnvTechniques[] = {
    {"uniform", "uniform directions on the sphere (baseline)", "env/uniform.glsl", noData},
    {"cosine", "cosine-weighted hemisphere around the normal (baseline)", "env/cosine.glsl", noData},
    {"env-cdf", "marginal/conditional CDF over texels", "env/env_cdf.glsl", makeEnvCdf},
    {"env-hier", "hierarchical 2x2 mip-pyramid warp", "env/env_hier.glsl", makeEnvHier},
    {"env-ot-inv", "optimal-transport map, tabulated inverse: one bilinear lookup per sample",
     "env/env_ot_inv.glsl", makeEnvOtInv},
    {"env-ot-fwd", "optimal-transport forward quad mesh inverted per sample (quadtree point location)",
     "env/env_ot_fwd.glsl", makeEnvOtFwd},
};

bool isBrdf(const BrdfInfo& brdf, const char* name) {
  return brdf.name == name && brdf.evalSource.empty();  // a .brdf file may be called "ggx" too
}

const BrdfTechniqueInfo kBrdfTechniques[] = {
    {"cosine", "cosine-weighted hemisphere", "brdf_sampler/cosine.glsl", "any BRDF", nullptr, nullptr},
    {"ggx-vndf", "GGX visible normals (Heitz 2018) + cosine for the diffuse lobe",
     "brdf_sampler/ggx_vndf.glsl", "ggx", [](const BrdfInfo& b) { return isBrdf(b, "ggx"); }, nullptr},
    {"merl-thetah", "1D inverse CDF over MERL's theta_h bins, phi_h uniform (baseline)",
     "brdf_sampler/merl_thetah.glsl", "merl", [](const BrdfInfo& b) { return isBrdf(b, "merl"); },
     makeMerlThetaH},
    {"merl-table", "per-theta_o 2D tables of f cos over the half vector (sqrt-warped theta_h x phi_h)",
     "brdf_sampler/half_vector_table.glsl", "merl", [](const BrdfInfo& b) { return isBrdf(b, "merl"); },
     makeMerlTable},
    {"brdf-tab",
     "merl-table's tables of f cos over the half vector, tabulated on the GPU from the compiled BRDF",
     "brdf_sampler/half_vector_table.glsl", "any BRDF", nullptr, makeBrdfTab},
    {"isfunc", "the .brdf file's own sampleBRDF and pdfBRDF (its ::begin isFunc section)",
     "brdf_sampler/isfunc.glsl", ".brdf files whose isFunc defines sampleBRDF and pdfBRDF",
     [](const BrdfInfo& b) { return b.hasSampleHook; }, nullptr},
};

const SequenceInfo kSequences[] = {
    {"random", "independent uniform points (PCG hash)", "sequence/random.glsl"},
    {"sobol", "Owen-scrambled Sobol (randomized QMC, Burley 2020)", "sequence/sobol.glsl"},
    {"cp-shared", "one shared Sobol point set, Cranley-Patterson-shifted per pixel",
     "sequence/cp_shared.glsl"},
};

// The methods beyond one env technique alone; those come first, one per entry of kEnvTechniques (methods()).
const MethodInfo kCombinedMethods[] = {
    {"brdf", "the BRDF technique alone (--brdf-sampler)", Strategy::SingleBrdf, ""},
    {"mis", "two-sample MIS of --env-sampler and --brdf-sampler (one-sample with --mis-split)", Strategy::Mis,
     ""},
    {"ris", "--ris-candidates from --env-sampler resampled by f cos (Talbot 2005)", Strategy::Ris, ""},
    {"product", "env x f cos per pixel over env-hier's pyramid, finished in its texel tables",
     Strategy::Product, "env-hier", makeEnvHierProduct},
    {"product-mis", "two-sample MIS of 'product' and --brdf-sampler", Strategy::ProductMis, "env-hier",
     makeEnvHierProduct},
    {"product-warp", "warp composition (Hart 2020): per pixel, f cos tabulated over env-hier's unit square",
     Strategy::ProductWarp, "env-hier", makeEnvHierProduct},
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
const T& findIn(std::span<const T> list, const std::string& name, const std::string& what) {
  for (const auto& item : list)
    if (item.name == name) return item;
  std::string valid;
  for (const auto& item : list) valid += (valid.empty() ? "" : ", ") + item.name;
  throw Error("unknown " + what + " '" + name + "'; valid: " + valid);
}

// A registry name padded to the listing's name column (13 wide, so product-warp keeps a space).
std::string column(const std::string& name) {
  constexpr std::size_t kWidth = 13;
  return name + std::string(kWidth - std::min(kWidth - 1, name.size()), ' ');
}

std::string formatValue(const ParamDecl& p, const std::array<double, 3>& v) {
  std::ostringstream s;
  if (p.type == ParamType::Color)
    s << v[0] << "," << v[1] << "," << v[2];
  else
    s << v[0];
  return s.str();
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

std::string strategyPart(Strategy strategy) {
  switch (strategy) {
    case Strategy::SingleEnv:
      return "strategy/single_env.glsl";
    case Strategy::SingleBrdf:
      return "strategy/single_brdf.glsl";
    case Strategy::Mis:
      return "strategy/mis.glsl";
    case Strategy::Ris:
      return "strategy/ris.glsl";
    case Strategy::Product:
      return "strategy/product.glsl";
    case Strategy::ProductMis:
      return "strategy/product_mis.glsl";
    case Strategy::ProductWarp:
      return "strategy/product_warp.glsl";
  }
  return {};
}

const BrdfInfo& findBrdf(const std::string& name) {
  return findIn(brdfRegistry(), name, "--brdf");
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
    if (!b.fileExtension.empty()) {
      if (b.name == nameOrPath)
        throw Error("--brdf " + nameOrPath + ": this BRDF is read from a file; pass --brdf path/material" +
                    b.fileExtension);
      valid += ", a " + b.fileExtension + " file (" + b.name + ")";
    }
  valid += ", a .brdf or .bparam file (BRDF Explorer)";
  throw Error("unknown --brdf '" + nameOrPath + "'; valid: " + valid);
}
const EnvTechniqueInfo& findEnvTechnique(const std::string& name, const std::string& what) {
  return findIn(envTechniqueRegistry(), name, what);
}
const BrdfTechniqueInfo& findBrdfTechnique(const std::string& name, const std::string& what) {
  return findIn(brdfTechniqueRegistry(), name, what);
}
const SequenceInfo& findSequence(const std::string& name) {
  return findIn(sequenceRegistry(), name, "--seq");
}
const MethodInfo& findMethod(const std::string& name) {
  return findIn(methodRegistry(), name, "--method");
}

std::string describeRegistry() {
  std::ostringstream s;
  s << "methods (--method):\n";
  for (const auto& m : methodRegistry())
    s << "  " << column(m.name) << m.description
      << "\n";
  s << "env techniques (--env-sampler, used by mis; each is also a method):\n";
  for (const auto& t : envTechniqueRegistry())
    s << "  " << column(t.name) << t.description
      << "; any BRDF\n";
  s << "BRDF techniques (--brdf-sampler, used by brdf and mis):\n";
  for (const auto& t : brdfTechniqueRegistry()) {
    s << "  " << column(t.name) << t.description << "; "
      << (t.applies ? "BRDFs: " : "") << t.appliesText << "\n";
  }
  s << "sequences (--seq):\n";
  for (const auto& q : sequenceRegistry())
    s << "  " << column(q.name) << q.description
      << "\n";
  s << "BRDFs (--brdf NAME, a .brdf / .bparam file, or a MERL .binary file) and parameters (--param "
       "NAME=VALUE):\n";
  for (const auto& b : brdfRegistry()) s << describeBrdf(b);
  return s.str();
}

std::string describeBrdf(const BrdfInfo& b) {
  std::ostringstream s;
  s << "  " << column(b.name) << b.description
    << "; best sampler: " << b.bestSampler << "\n";
  for (const auto& p : b.params) {
    s << "      " << p.name << " ("
      << (p.type == ParamType::Color  ? "color r,g,b"
          : p.type == ParamType::Bool ? "bool"
                                      : "float");
    if (p.type != ParamType::Bool) s << " in [" << p.min << ", " << p.max << "]";
    s << ", default " << formatValue(p, p.defaultValue) << ")";
    if (!p.description.empty()) s << ": " << p.description;
    s << "\n";
  }
  return s.str();
}

ParamValues resolveParams(const BrdfInfo& brdf,
                          const std::vector<std::pair<std::string, std::string>>& given) {
  ParamValues values;
  for (const auto& p : brdf.params) values[p.name] = p.defaultValue;
  for (const auto& [name, text] : given) {
    auto decl = std::find_if(brdf.params.begin(), brdf.params.end(),
                             [&](const ParamDecl& p) { return p.name == name; });
    if (decl == brdf.params.end()) {
      std::string valid;
      for (const auto& p : brdf.params) valid += (valid.empty() ? "" : ", ") + p.name;
      throw Error("--param " + name + ": BRDF '" + brdf.name + "' has no parameter '" + name +
                  "'; its parameters: " + valid);
    }
    std::array<double, 3> v{0, 0, 0};
    const int count = decl->type == ParamType::Color ? 3 : 1;
    std::string rest = text;
    if (decl->type == ParamType::Bool && (rest == "true" || rest == "false"))
      rest.assign(1, rest == "true"
                         ? '1'
                         : '0');  // assign(count, char): GCC 12 warns falsely on operator=(const char*)
    int parsed = 0;
    std::istringstream in(rest);
    std::string item;
    if (!rest.empty() && rest.back() == ',') throw Error("--param " + name + "=" + text + ": trailing comma");
    while (std::getline(in, item, ',')) {
      if (parsed >= 3) throw Error("--param " + name + "=" + text + ": too many values");
      char* end = nullptr;
      v[parsed] = std::strtod(item.c_str(), &end);
      if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v[parsed]))
        throw Error("--param " + name + "=" + text + ": '" + item + "' is not a number");
      ++parsed;
    }
    if (decl->type == ParamType::Color && parsed == 1) v = {v[0], v[0], v[0]}, parsed = 3;  // grey shorthand
    if (parsed != count)
      throw Error("--param " + name + "=" + text + ": expected " +
                  (count == 3 ? "a color r,g,b" : "one value"));
    if (decl->type == ParamType::Bool && v[0] != 0.0 && v[0] != 1.0)
      throw Error("--param " + name + "=" + text + ": expected 0, 1, true or false");
    for (int c = 0; c < count; ++c)
      if (v[c] < decl->min || v[c] > decl->max) {
        std::ostringstream msg;
        msg << "--param " << name << "=" << text << ": out of range [" << decl->min << ", " << decl->max
            << "]";
        throw Error(msg.str());
      }
    values[name] = v;
  }
  return values;
}

std::vector<float> packParams(const BrdfInfo& brdf, const ParamValues& values) {
  std::vector<float> packed(4 * std::max<size_t>(brdf.params.size(), 1), 0.0f);
  for (size_t i = 0; i < brdf.params.size(); ++i) {
    const auto& p = brdf.params[i];
    const auto& v = values.at(p.name);
    if (p.type == ParamType::Bool) {
      const uint32_t bit = v[0] != 0.0 ? 1u : 0u;  // GLSL bool in a buffer is a 32-bit integer
      std::memcpy(&packed[4 * i], &bit, sizeof bit);
    } else {
      for (int c = 0; c < (p.type == ParamType::Color ? 3 : 1); ++c) packed[4 * i + c] = float(v[c]);
    }
  }
  return packed;
}

std::string paramBlockGlsl(const BrdfInfo& brdf) {
  std::ostringstream s;
  s << "layout(std430, set = 3, binding = 0) readonly buffer BrdfParamBlock {\n";
  if (brdf.params.empty()) s << "  vec4 iblxUnusedParam;\n";
  for (size_t i = 0; i < brdf.params.size(); ++i) {
    const auto& p = brdf.params[i];
    // One 16-byte slot per parameter (std430: float arrays have a 4-byte stride).
    if (p.type == ParamType::Color)
      s << "  vec3 " << p.name << "; float iblxPad" << i << ";\n";
    else
      s << "  " << (p.type == ParamType::Bool ? "bool " : "float ") << p.name << "; float iblxPad" << i
        << "[3];\n";
  }
  s << "};\n";
  return s.str();
}

}  // namespace iblx
