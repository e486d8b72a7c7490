// Measured files as BRDFs (measured_brdfs.h).
#include "engine/scene/measured_brdfs.h"

#include <cctype>

#include "engine/io/alta_func.h"
#include "engine/sampling/brdf/alta_grid.h"
#include "engine/sampling/technique_data.h"
#include "engine/scene/alta_func_brdf.h"

namespace iblx {
namespace {
constexpr const char* kRglEvalPart = "brdf/rgl.glsl";
}  // namespace

std::shared_ptr<const BrdfInfo> makeUtiaBrdf(UtiaBrdf brdf, const std::filesystem::path& file) {
  auto table = std::make_shared<const std::vector<float>>(std::move(brdf.rgb));
  auto info = std::make_shared<BrdfInfo>();
  info->name = file.stem().string();
  info->description = "UTIA measured anisotropic BRDF " + file.string() +
                      " (6 theta x 48 phi per direction, RGB; quadrilinear lookup)";
  info->evalPart = "brdf/utia.glsl";
  info->params = {
      {"prescale", ParamType::Float, 0.0, 1e6, {1.0, 0, 0}, "stored values are multiplied by this first"},
      {"srgb", ParamType::Bool, 0.0, 1.0, {0.0, 0, 0}, "then decoded from sRGB to linear (1) or kept (0)"},
      {"scale", ParamType::Float, 0.0, 1e6, {1.0, 0, 0}, "then multiplied by this, giving 1/sr"}};
  info->bestSampler = "brdf-tab";
  info->lobeWidth = [](const Scene& scene, const GpuServices& gpu) { return gpu.measureLobeWidth(scene); };
  info->data = [table](const Scene&) {
    TechniqueData data;
    data.add("utiaRgb", *table);
    return data;
  };
  return info;
}

std::shared_ptr<const BrdfInfo> makeMitBrdf(MitBrdf brdf, const std::filesystem::path& file) {
  const MitDims dims = brdf.dims;
  auto table = std::make_shared<const std::vector<float>>(std::move(brdf.rgb));
  auto info = std::make_shared<BrdfInfo>();
  info->name = file.stem().string();
  info->description = "MIT CSAIL measured anisotropic BRDF " + file.string() + " (" +
                      std::to_string(dims.thetaIn) + " theta_in x " + std::to_string(dims.thetaOut) +
                      " theta_out x " + std::to_string(dims.phiDiff) + " phi_diff" +
                      (dims.halfData ? " over [0, pi]" : "") + " x " + std::to_string(dims.phiIn) +
                      " phi_in bins, RGB; nearest bin)";
  info->evalPart = "brdf/mit.glsl";
  info->params = {{"scale",
                   ParamType::Float,
                   0.0,
                   1e6,
                   {1.0, 0, 0},
                   "stored values are multiplied by this, giving 1/sr (BRDF Explorer shows them x 10)"}};
  info->bestSampler = "brdf-tab";
  info->lobeWidth = [](const Scene& scene, const GpuServices& gpu) { return gpu.measureLobeWidth(scene); };
  info->data = [table, dims](const Scene&) {
    TechniqueData data;
    data.add("mitRgb", *table);
    data.define("MIT_THETA_IN", std::uint32_t(dims.thetaIn));
    data.define("MIT_THETA_OUT", std::uint32_t(dims.thetaOut));
    data.define("MIT_PHI_DIFF", std::uint32_t(dims.phiDiff));
    data.define("MIT_PHI_IN", std::uint32_t(dims.phiIn));
    data.define("MIT_HALF_DATA", dims.halfData ? "1" : "0");
    return data;
  };
  return info;
}

std::shared_ptr<const BrdfInfo> makeRglBrdf(const RglTables& tables, const std::filesystem::path& file) {
  const RglBsdf material(tables);
  auto info = std::make_shared<BrdfInfo>();
  info->name = file.stem().string();
  std::string description = "RGL-EPFL measured " +
                            std::string(tables.isotropic() ? "isotropic" : "anisotropic") + " BRDF " +
                            file.string();
  if (!tables.description.empty()) description.append(" ('").append(tables.description).append("')");
  description.append(" (").append(std::to_string(tables.phiI.size())).append(" phi_i x ");
  description.append(std::to_string(tables.thetaI.size())).append(" theta_i views; VNDF ");
  description.append(std::to_string(tables.vndf.height))
      .append(" x ")
      .append(std::to_string(tables.vndf.width));
  description.append(", colour ").append(std::to_string(tables.rgb.width)).append(" x ");
  description.append(std::to_string(tables.rgb.width));
  if (tables.spectralBands > 0)
    description.append(", from ").append(std::to_string(tables.spectralBands)).append(" wavelengths");
  if (tables.reduction() > 1)
    description.append(", 1/").append(std::to_string(tables.reduction())).append(" of the azimuths stored");
  description.append("; bilinear warps)");
  info->description = description;
  info->evalPart = kRglEvalPart;
  info->bestSampler = "rgl-vndf";
  info->lobeWidth = [](const Scene& scene, const GpuServices& gpu) { return gpu.measureLobeWidth(scene); };
  // Packed once: every kernel that evaluates the material uploads a copy.
  auto data = std::make_shared<const TechniqueData>(material.techniqueData());
  info->data = [data](const Scene&) { return *data; };
  return info;
}

std::shared_ptr<const BrdfInfo> makeAltaDataBrdf(const AltaData& data, const std::filesystem::path& file) {
  const AltaGrid grid = makeAltaGrid(data, file.string());
  auto info = std::make_shared<BrdfInfo>();
  info->name = file.stem().string();
  std::string shape;
  for (const auto& axis : grid.axes)
    shape.append(shape.empty() ? "" : " x ").append(std::to_string(axis.size()));
  std::string description = "ALTA data file " + file.string() + " (" + std::to_string(data.samples) + " " +
                            altaParamName(data.param) + " samples of " + altaOutputName(data.output) + "; ";
  description.append(grid.resampledFrom > 0 ? "resampled onto a " : "a ").append(shape).append(" ");
  description.append(altaParamName(grid.param)).append(" grid, multilinear lookup)");
  description.append(leaveOneOutText(grid));
  info->description = description;
  info->evalPart = "brdf/alta_data.glsl";
  info->bestSampler = "brdf-tab";
  info->lobeWidth = [](const Scene& scene, const GpuServices& gpu) { return gpu.measureLobeWidth(scene); };
  auto tables = std::make_shared<const TechniqueData>(altaGridTechniqueData(grid));
  info->data = [tables](const Scene&) { return *tables; };
  return info;
}

std::span<const MaterialFileFormat> materialFileFormats() {
  // Content first: a UTIA .bin by its exact size, an MIT .dat by its header, an RGL .bsdf by its magic, ALTA
  // files by their first lines.
  static const MaterialFileFormat formats[] = {
      {"UTIA .bin",
       {".bin"},
       looksLikeUtia,
       false,
       [](const std::filesystem::path& p) { return makeUtiaBrdf(loadUtia(p), p); }},
      {"ALTA data",
       {".data", ".alta"},
       looksLikeAltaData,
       false,
       [](const std::filesystem::path& p) { return makeAltaDataBrdf(loadAltaData(p), p); }},
      {"MIT CSAIL .dat",
       {".dat"},
       looksLikeMitBrdf,
       false,
       [](const std::filesystem::path& p) { return makeMitBrdf(loadMitBrdf(p), p); }},
      {"RGL-EPFL .bsdf",
       {".bsdf"},
       looksLikeRglBsdf,
       false,
       [](const std::filesystem::path& p) { return makeRglBrdf(loadRglBsdf(p), p); }},
      {"ALTA function",
       {".func"},
       looksLikeAltaFunc,
       true,
       [](const std::filesystem::path& p) { return makeAltaFuncBrdf(loadAltaFunc(p), p); }},
  };
  return formats;
}

std::string materialFileKindsText() {
  std::vector<std::string> kinds;
  for (const BrdfInfo& b : brdfRegistry())
    if (!b.fileExtension.empty()) kinds.push_back(b.name + " " + b.fileExtension);
  for (const MaterialFileFormat& format : materialFileFormats()) kinds.push_back(format.name);
  std::string text;
  for (std::size_t i = 0; i < kinds.size(); ++i)
    text += (i == 0 ? "a " : i + 1 == kinds.size() ? " or " : ", ") + kinds[i];
  return text + " file, or a .brdf or .bparam file (BRDF Explorer)";
}

std::vector<std::string> brdfFileExtensions() {
  std::vector<std::string> extensions{".brdf", ".bparam", ".binary"};
  for (const MaterialFileFormat& format : materialFileFormats())
    extensions.insert(extensions.end(), format.extensions.begin(), format.extensions.end());
  return extensions;
}

bool isBrdfFile(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  for (const std::string& e : brdfFileExtensions())
    if (e == extension) return true;
  for (const MaterialFileFormat& format : materialFileFormats())
    if (format.recognise(path)) return true;
  return false;
}

bool isRglBrdf(const BrdfInfo& brdf) {
  return brdf.evalPart == kRglEvalPart;
}

UtiaConvention utiaConvention(const ParamValues& values) {
  return {values.at("prescale")[0], values.at("srgb")[0] != 0.0, values.at("scale")[0]};
}

}  // namespace iblx
