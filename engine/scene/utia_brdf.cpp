// UTIA files as BRDFs (utia_brdf.h).
#include "engine/scene/utia_brdf.h"

#include "engine/sampling/technique_data.h"

namespace iblx {

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

UtiaConvention utiaConvention(const ParamValues& values) {
  return {values.at("prescale")[0], values.at("srgb")[0] != 0.0, values.at("scale")[0]};
}

}  // namespace iblx
