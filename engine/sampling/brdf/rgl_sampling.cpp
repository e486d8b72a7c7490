// RGL-EPFL material evaluation and sampling in double (rgl_sampling.h).
#include "engine/sampling/brdf/rgl_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace iblx {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> toDouble(const std::vector<float>& v) {
  return {v.begin(), v.end()};
}

// theta = acos(z), stable near the pole (Dupuy & Jakob's reader): 2 asin(|w - n| / 2).
double elevation(glm::dvec3 w) {
  return 2.0 *
         std::asin(std::clamp(0.5 * std::sqrt(w.x * w.x + w.y * w.y + (w.z - 1.0) * (w.z - 1.0)), -1.0, 1.0));
}
double thetaToU(double theta) {
  return std::sqrt(std::max(theta, 0.0) * (2.0 / kPi));
}
double phiToU(double phi) {
  return (phi + kPi) / (2.0 * kPi);
}
double uToTheta(double u) {
  return u * u * (kPi / 2.0);
}
double uToPhi(double u) {
  return (2.0 * u - 1.0) * kPi;
}

// Solid angle per unit square of (u_theta, u_phi): sin(theta) dtheta dphi = 2 pi^2 u sin(theta) du.
double unitSquareJacobian(double uTheta, double theta) {
  return 2.0 * kPi * kPi * uTheta * std::sin(theta);
}

}  // namespace

RglBsdf::RglBsdf(const RglTables& t)
    : ndf_(t.ndf.values, t.ndf.width, t.ndf.height, {}, false),
      sigma_(t.sigma.values, t.sigma.width, t.sigma.height, {}, false),
      vndf_(t.vndf.values, t.vndf.width, t.vndf.height, {toDouble(t.phiI), toDouble(t.thetaI)}, true),
      luminance_(t.luminance.values, t.luminance.width, t.luminance.height,
                 {toDouble(t.phiI), toDouble(t.thetaI)}, true),
      rgb_(t.rgb.values, t.rgb.width, t.rgb.height, {toDouble(t.phiI), toDouble(t.thetaI), {0.0, 1.0, 2.0}},
           false),
      isotropic_(t.isotropic()),
      jacobian_(t.jacobian),
      reduction_(t.reduction()) {}

RglBsdf::Reduced RglBsdf::reduce(glm::dvec3 wi, glm::dvec3 wo) const {
  // A file storing half (quarter) of the view azimuths: mirror the view into the stored range, the light with
  // it; applying the same signs again undoes it.
  double sx = 1.0, sy = 1.0;
  if (reduction_ >= 2) {
    sy = wo.y < 0.0 ? 1.0 : -1.0;
    sx = reduction_ == 4 ? (wo.x < 0.0 ? 1.0 : -1.0) : sy;
  }
  return {glm::dvec3(sx * wo.x, sy * wo.y, wo.z), glm::dvec3(sx * wi.x, sy * wi.y, wi.z), sx, sy};
}

glm::dvec3 RglBsdf::eval(glm::dvec3 wi, glm::dvec3 wo) const {
  if (wi.z <= 0.0 || wo.z <= 0.0) return glm::dvec3(0.0);
  const Reduced r = reduce(wi, wo);
  const glm::dvec3 m = glm::normalize(r.wo + r.wi);
  const double thetaV = elevation(r.wo), phiV = std::atan2(r.wo.y, r.wo.x);
  const double thetaM = elevation(m), phiM = std::atan2(m.y, m.x);
  const glm::dvec2 uV(thetaToU(thetaV), phiToU(phiV));
  glm::dvec2 uM(thetaToU(thetaM), phiToU(isotropic_ ? phiM - phiV : phiM));
  uM.y -= std::floor(uM.y);
  const double params[2] = {phiV, thetaV};
  const glm::dvec2 s = vndf_.invert(uM, params).point;
  glm::dvec3 value;
  for (int c = 0; c < 3; ++c) {
    const double rgbParams[3] = {phiV, thetaV, double(c)};
    value[c] = std::max(rgb_.eval(s, rgbParams), 0.0);
  }
  // Dupuy & Jakob 2018, eq. 11: the stored values are f cos divided by the VNDF warp's Jacobian.
  if (jacobian_) value *= ndf_.eval(uM, {}) / (4.0 * sigma_.eval(uV, {}));
  return value / wi.z;
}

RglBsdf::Sample RglBsdf::sample(glm::dvec2 u, glm::dvec3 wo) const {
  if (wo.z <= 0.0) return {glm::dvec3(0.0, 0.0, 1.0), 0.0};
  const Reduced r = reduce(glm::dvec3(0.0), wo);
  const double thetaV = elevation(r.wo), phiV = std::atan2(r.wo.y, r.wo.x);
  const double params[2] = {phiV, thetaV};
  const BilinearWarp2D::Result lum = luminance_.sample(u, params);
  const BilinearWarp2D::Result normal = vndf_.sample(lum.point, params);
  const double thetaM = uToTheta(normal.point.x);
  const double phiM = uToPhi(normal.point.y) + (isotropic_ ? phiV : 0.0);
  const glm::dvec3 m(std::sin(thetaM) * std::cos(phiM), std::sin(thetaM) * std::sin(phiM), std::cos(thetaM));
  const double cosVM = glm::dot(r.wo, m);
  const double jacobian = unitSquareJacobian(normal.point.x, thetaM) * 4.0 * cosVM;
  if (!(jacobian > 0.0)) return {glm::dvec3(0.0, 0.0, 1.0), 0.0};
  const glm::dvec3 wi = 2.0 * cosVM * m - r.wo;
  return {glm::dvec3(r.sx * wi.x, r.sy * wi.y, wi.z), normal.pdf * lum.pdf / jacobian};
}

double RglBsdf::pdf(glm::dvec3 wi, glm::dvec3 wo) const {
  if (wo.z <= 0.0) return 0.0;
  const Reduced r = reduce(wi, wo);
  const glm::dvec3 h = r.wo + r.wi;
  if (glm::dot(h, h) <= 0.0) return 0.0;
  const glm::dvec3 m = glm::normalize(h);
  if (m.z <= 0.0) return 0.0;
  const double thetaV = elevation(r.wo), phiV = std::atan2(r.wo.y, r.wo.x);
  const double thetaM = elevation(m), phiM = std::atan2(m.y, m.x);
  glm::dvec2 uM(thetaToU(thetaM), phiToU(isotropic_ ? phiM - phiV : phiM));
  uM.y -= std::floor(uM.y);
  const double params[2] = {phiV, thetaV};
  const BilinearWarp2D::Result normal = vndf_.invert(uM, params);
  const double jacobian = unitSquareJacobian(uM.x, thetaM) * 4.0 * glm::dot(r.wo, m);
  if (!(jacobian > 0.0)) return 0.0;
  return normal.pdf * luminance_.eval(normal.point, params) / jacobian;
}

TechniqueData RglBsdf::techniqueData() const {
  std::vector<float> data;
  TechniqueData out;
  const auto append = [&](const char* name, const std::vector<double>& values) {
    out.define(name, std::uint32_t(data.size()));
    data.insert(data.end(), values.begin(), values.end());
  };
  const std::vector<double>& phi = vndf_.paramValues()[0];
  const std::vector<double>& theta = vndf_.paramValues()[1];
  append("RGL_AT_PHI", phi);
  append("RGL_AT_THETA", theta);
  append("RGL_AT_NDF", ndf_.values());
  append("RGL_AT_SIGMA", sigma_.values());
  append("RGL_AT_VNDF", vndf_.values());
  append("RGL_AT_VNDF_COND", vndf_.conditionalCdf());
  append("RGL_AT_VNDF_MARG", vndf_.marginalCdf());
  append("RGL_AT_LUM", luminance_.values());
  append("RGL_AT_LUM_COND", luminance_.conditionalCdf());
  append("RGL_AT_LUM_MARG", luminance_.marginalCdf());
  append("RGL_AT_RGB", rgb_.values());
  const auto steps = searchSteps;
  out.define("RGL_PHI_STEPS", steps(phi.size()));
  out.define("RGL_THETA_STEPS", steps(theta.size()));
  out.define("RGL_VNDF_W_STEPS", steps(vndf_.width()));
  out.define("RGL_VNDF_H_STEPS", steps(vndf_.height()));
  out.define("RGL_N_STEPS", steps(luminance_.width()));
  out.define("RGL_N_PHI", std::uint32_t(phi.size()));
  out.define("RGL_N_THETA", std::uint32_t(theta.size()));
  out.define("RGL_NDF_W", ndf_.width());
  out.define("RGL_NDF_H", ndf_.height());
  out.define("RGL_SIGMA_W", sigma_.width());
  out.define("RGL_SIGMA_H", sigma_.height());
  out.define("RGL_VNDF_W", vndf_.width());
  out.define("RGL_VNDF_H", vndf_.height());
  out.define("RGL_N", luminance_.width());
  out.define("RGL_ISOTROPIC", isotropic_ ? "1" : "0");
  out.define("RGL_JACOBIAN", jacobian_ ? "1" : "0");
  out.define("RGL_REDUCTION", std::to_string(reduction_));
  out.add("rglData", data);
  return out;
}

namespace {

// GGX NDF and its projected area (Walter et al. 2007, eq. 33; Heitz 2014, eq. 72 with Lambda of eq. 86).
double ggxNdf(double cosTheta, double alpha) {
  const double a2 = alpha * alpha, c2 = cosTheta * cosTheta;
  const double d = c2 * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}
double ggxProjectedArea(double theta, double alpha) {
  const double c = std::cos(theta), s = std::sin(theta);
  return 0.5 * (c + std::sqrt(c * c + alpha * alpha * s * s));
}
glm::dvec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace

RglSynthPlan planRglSynth(const RglSynthLayout& layout) {
  RglSynthPlan plan;
  RglTables& t = plan.tables;
  t.description = "tabulated by iblx measured-synth";
  const double alpha = layout.alpha;
  for (std::uint32_t k = 0; k < layout.thetaViews; ++k)
    t.thetaI.push_back(float(k * (89.0 / (layout.thetaViews - 1.0)) * kPi / 180.0));
  if (layout.phiViews == 1)
    t.phiI = {0.0f};
  else
    for (std::uint32_t k = 0; k < layout.phiViews; ++k)
      t.phiI.push_back(float((2.0 * k / (layout.phiViews - 1.0) - 1.0) * kPi));
  const std::uint32_t v = layout.vndfSize, n = layout.sampleSize;
  const auto uOf = [](std::uint32_t i, std::uint32_t size) { return i / (size - 1.0); };
  t.ndf = t.sigma = {v, v, std::vector<float>(std::size_t(v) * v)};
  for (std::uint32_t y = 0; y < v; ++y)
    for (std::uint32_t x = 0; x < v; ++x) {
      const double theta = uToTheta(uOf(x, v));
      t.ndf.values[y * v + x] = float(ggxNdf(std::cos(theta), alpha));
      t.sigma.values[y * v + x] = float(ggxProjectedArea(theta, alpha));
    }
  const std::size_t slices = t.phiI.size() * t.thetaI.size();
  // Visible normals D(m) max(0, v.m) / sigma(v) (Heitz 2014, eq. 38), as a density over the unit square.
  t.vndf = {v, v, std::vector<float>(slices * v * v)};
  for (std::size_t slice = 0; slice < slices; ++slice) {
    const double phiV = t.phiI[slice / t.thetaI.size()], thetaV = t.thetaI[slice % t.thetaI.size()];
    const glm::dvec3 view = direction(thetaV, phiV);
    for (std::uint32_t y = 0; y < v; ++y)
      for (std::uint32_t x = 0; x < v; ++x) {
        const double uTheta = uOf(x, v), thetaM = uToTheta(uTheta);
        const double phiM = uToPhi(uOf(y, v)) + (layout.phiViews == 1 ? phiV : 0.0);
        const glm::dvec3 m = direction(thetaM, phiM);
        t.vndf.values[slice * v * v + y * v + x] =
            float(ggxNdf(m.z, alpha) * std::max(glm::dot(view, m), 0.0) / ggxProjectedArea(thetaV, alpha) *
                  unitSquareJacobian(uTheta, thetaM));
      }
  }
  t.luminance = {n, n, std::vector<float>(slices * n * n, 1.0f)};
  t.rgb = {n, n, std::vector<float>(slices * 3 * n * n, 1.0f)};
  const RglBsdf warps(t);  // the warps only: rgb and luminance are placeholders until finishRglSynth
  for (std::size_t slice = 0; slice < slices; ++slice) {
    const double phiV = t.phiI[slice / t.thetaI.size()], thetaV = t.thetaI[slice % t.thetaI.size()];
    const glm::dvec3 view = direction(thetaV, phiV);
    const double params[2] = {phiV, thetaV};
    const double sigma = warps.sigma().eval(glm::dvec2(thetaToU(thetaV), phiToU(phiV)), {});
    for (std::uint32_t y = 0; y < n; ++y)
      for (std::uint32_t x = 0; x < n; ++x) {
        const glm::dvec2 uM = warps.vndf().sample(glm::dvec2(uOf(x, n), uOf(y, n)), params).point;
        const double thetaM = uToTheta(uM.x);
        const glm::dvec3 m = direction(thetaM, uToPhi(uM.y) + (layout.phiViews == 1 ? phiV : 0.0));
        const glm::dvec3 light = 2.0 * glm::dot(view, m) * m - view;
        const double ndf = warps.ndf().eval(uM, {});
        plan.wi.push_back(light);
        plan.wo.push_back(view);
        plan.toStored.push_back(light.z > 0.0 && ndf > 0.0 ? light.z * 4.0 * sigma / ndf : 0.0);
      }
  }
  return plan;
}

RglTables finishRglSynth(RglSynthPlan plan, std::span<const glm::dvec3> f) {
  RglTables& t = plan.tables;
  const std::size_t cells = std::size_t(t.rgb.width) * t.rgb.width, slices = t.phiI.size() * t.thetaI.size();
  for (std::size_t slice = 0; slice < slices; ++slice) {
    double total = 0.0;
    for (std::size_t cell = 0; cell < cells; ++cell) {
      const std::size_t node = slice * cells + cell;
      const glm::dvec3 stored = glm::max(f[node], glm::dvec3(0.0)) * plan.toStored[node];
      for (int c = 0; c < 3; ++c)
        t.rgb.values[(slice * 3 + std::size_t(c)) * cells + cell] = float(stored[c]);
      const double luminance = 0.2126 * stored.r + 0.7152 * stored.g + 0.0722 * stored.b;
      t.luminance.values[node] = float(luminance);
      total += luminance;
    }
    // A view where the BRDF is 0 everywhere still needs a warp: uniform.
    if (!(total > 0.0)) std::fill_n(t.luminance.values.begin() + std::ptrdiff_t(slice * cells), cells, 1.0f);
  }
  return std::move(plan.tables);
}

}  // namespace iblx
