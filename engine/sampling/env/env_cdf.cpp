// env-cdf: table builder (double accumulation, float storage) and the float-exact CPU twin of the GLSL
// sampler.
#include "engine/sampling/env/env_cdf.h"

#include "engine/core/error.h"
#include "engine/sampling/float_cdf.h"

#include <algorithm>
#include <span>
#include <string>
#include <utility>

namespace iblx {

int envCdfGuideCells(int n, int cellsPerBin) {
  int cells = 1;
  while (cells * 2 <= n * cellsPerBin) cells *= 2;
  return cells;
}

EnvCdfData buildEnvCdf(const EnvImage& image) {
  const std::vector<double> weights = texelSamplingWeights(image, "env-cdf");
  const int width = image.width, height = image.height;
  if (width > kEnvCdfMaxBins || height > kEnvCdfMaxBins)
    throw Error("env-cdf: a " + std::to_string(width) + " x " + std::to_string(height) +
                " map is larger than the " + std::to_string(kEnvCdfMaxBins) +
                " texels per side its guide tables address; use env-hier");
  EnvCdfData data;
  data.width = width;
  data.height = height;
  data.marginalCdf.resize(std::size_t(height) + 1);
  data.conditionalCdf.resize(std::size_t(height) * std::size_t(width + 1));

  // Conditional CDF of each row, and the row weights sum_x w(x, y) for the marginal.
  std::vector<double> rowWeights(std::size_t(height), 0.0);
  for (int y = 0; y < height; ++y) {
    const std::span<const double> row(weights.data() + image.index(0, y), std::size_t(width));
    for (double w : row) rowWeights[std::size_t(y)] += w;
    writeFloatCdf(row, data.conditionalCdf.data() + std::size_t(y) * std::size_t(width + 1));
  }
  // texelSamplingWeights already replaced an all-zero image by Omega(y); this only guards total underflow.
  double total = 0.0;
  for (double w : rowWeights) total += w;
  if (!(total > 0.0)) {
    for (int y = 0; y < height; ++y) rowWeights[std::size_t(y)] = latLongTexelSolidAngle(y, width, height);
  }
  writeFloatCdf(rowWeights, data.marginalCdf.data());

  data.rowGuideCells = envCdfGuideCells(height, kEnvCdfRowCellsPerBin);
  data.columnGuideCells = envCdfGuideCells(width, kEnvCdfColumnCellsPerBin);
  const std::size_t rowGuide = std::size_t(data.columnGuideCells);
  data.marginalGuide.resize(std::size_t(data.rowGuideCells));
  data.conditionalGuide.resize(std::size_t(height) * rowGuide);
  writeGuide(data.marginalCdf.data(), height, data.rowGuideCells, data.marginalGuide.data());
  for (int y = 0; y < height; ++y)
    writeGuide(data.conditionalCdf.data() + std::size_t(y) * std::size_t(width + 1), width,
               data.columnGuideCells, data.conditionalGuide.data() + std::size_t(y) * rowGuide);
  return data;
}

EnvCdfSampler::EnvCdfSampler(EnvCdfData data) : data_(std::move(data)) {
  const int width = data_.width, height = data_.height;
  if (width <= 0 || height <= 0 || data_.marginalCdf.size() != std::size_t(height) + 1 ||
      data_.conditionalCdf.size() != std::size_t(height) * std::size_t(width + 1) ||
      data_.rowGuideCells <= 0 || data_.columnGuideCells <= 0 ||
      data_.marginalGuide.size() != std::size_t(data_.rowGuideCells) ||
      data_.conditionalGuide.size() != std::size_t(height) * std::size_t(data_.columnGuideCells))
    throw Error("env-cdf: table sizes do not match a " + std::to_string(width) + " x " +
                std::to_string(height) + " map; rebuild them with buildEnvCdf");
  rowSolidAngles_ = rowSolidAngles(width, height);
}

const float* EnvCdfSampler::conditionalRow(int y) const {
  return data_.conditionalCdf.data() + std::size_t(y) * std::size_t(data_.width + 1);
}

const std::uint32_t* EnvCdfSampler::conditionalGuideRow(int y) const {
  return data_.conditionalGuide.data() + std::size_t(y) * std::size_t(data_.columnGuideCells);
}

float EnvCdfSampler::texelProbability(int x, int y) const {
  const float* m = data_.marginalCdf.data();
  const float* c = conditionalRow(y);
  const float rowProb = m[y + 1] - m[y], colProb = c[x + 1] - c[x];
  return rowProb * colProb;
}

EnvSample EnvCdfSampler::sample(glm::dvec2 u) const {
  const int width = data_.width, height = data_.height;
  const float uy = toGpuU(u.y), ux = toGpuU(u.x);
  // Row y from the marginal, then t.y = offset of u.y inside the row's bin.
  const float* m = data_.marginalCdf.data();
  const int y = findBinGuided(m, data_.marginalGuide.data(), data_.rowGuideCells, uy);
  const float rowProb = m[y + 1] - m[y];
  const float ty = remapInFloatBin(uy, m[y], rowProb);
  // Column x from row y's conditional, then t.x.
  const float* c = conditionalRow(y);
  const int x = findBinGuided(c, conditionalGuideRow(y), data_.columnGuideCells, ux);
  const float colProb = c[x + 1] - c[x];
  const float tx = remapInFloatBin(ux, c[x], colProb);
  // P = probability of the texel actually chosen; constant density P / Omega(y) inside it.
  const float prob = rowProb * colProb;
  const float omega = rowSolidAngles_[std::size_t(y)];
  EnvSample s;
  s.texel = {x, y};
  s.direction = texelToDirection(x, y, {double(tx), double(ty)}, width, height);
  s.pdfSolidAngle = omega > 0.0f ? double(prob / omega) : 0.0;
  return s;
}

double EnvCdfSampler::pdf(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return 0.0;
  const glm::ivec2 t = directionToTexel(wi, data_.width, data_.height);
  const float prob = texelProbability(t.x, t.y);
  const float omega = rowSolidAngles_[std::size_t(t.y)];
  return omega > 0.0f ? double(prob / omega) : 0.0;
}

std::optional<glm::dvec2> EnvCdfSampler::invert(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return std::nullopt;
  const glm::ivec2 texel = directionToTexel(wi, data_.width, data_.height);
  const float* m = data_.marginalCdf.data();
  const float* c = conditionalRow(texel.y);
  const float rowProb = m[texel.y + 1] - m[texel.y], colProb = c[texel.x + 1] - c[texel.x];
  if (!(rowProb > 0.0f && colProb > 0.0f)) return std::nullopt;
  // u = cdf[bin] + t * (probability of the bin), per axis.
  const glm::dvec2 t = directionToTexelOffset(wi, texel, data_.width, data_.height);
  const double uy = double(m[texel.y]) + t.y * double(rowProb);
  const double ux = double(c[texel.x]) + t.x * double(colProb);
  return glm::dvec2(std::min(ux, double(kOneMinusEpsilonF)), std::min(uy, double(kOneMinusEpsilonF)));
}

TechniqueData envCdfTechniqueData(const EnvImage& image) {
  const EnvCdfData cdf = buildEnvCdf(image);
  std::vector<float> packed(cdf.marginalCdf);
  packed.insert(packed.end(), cdf.conditionalCdf.begin(), cdf.conditionalCdf.end());
  std::vector<std::uint32_t> guide(cdf.marginalGuide);
  guide.insert(guide.end(), cdf.conditionalGuide.begin(), cdf.conditionalGuide.end());
  TechniqueData data;
  data.add("envCdf", packed);
  data.add("envCdfGuide", guide);
  data.define("ENV_CDF_ROW_GUIDE_SIZE", std::uint32_t(cdf.rowGuideCells));
  data.define("ENV_CDF_COLUMN_GUIDE_SIZE", std::uint32_t(cdf.columnGuideCells));
  return data;
}

}  // namespace iblx
