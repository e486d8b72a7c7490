// ALTA's parametrisations: names and dimensions (alta_params.h).
#include "engine/io/alta_params.h"

#include <algorithm>
#include <cmath>

namespace iblx {
namespace {

struct ParamEntry {
  AltaParam param;
  const char* name;
  int dimension;
};
constexpr ParamEntry kParams[] = {
    {AltaParam::CosTh, "COS_TH", 1},
    {AltaParam::CosThTd, "COS_TH_TD", 2},
    {AltaParam::RusinThTd, "RUSIN_TH_TD", 2},
    {AltaParam::RusinThTdPd, "RUSIN_TH_TD_PD", 3},
    {AltaParam::IsotropicTvTlDphi, "ISOTROPIC_TV_TL_DPHI", 3},
    {AltaParam::SphericalTlPlTvPv, "SPHERICAL_TL_PL_TV_PV", 4},
    {AltaParam::Cartesian, "CARTESIAN", 6},
};

}  // namespace

std::string altaParamName(AltaParam p) {
  for (const auto& e : kParams)
    if (e.param == p) return e.name;
  return "?";
}

int altaParamDimension(AltaParam p) {
  for (const auto& e : kParams)
    if (e.param == p) return e.dimension;
  return 0;
}

std::optional<AltaParam> findAltaParam(const std::string& name) {
  for (const auto& e : kParams)
    if (name == e.name) return e.param;
  return std::nullopt;
}

std::array<double, 6> altaRawCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo) {
  const auto angle = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)); };
  const glm::dvec3 sum = wi + wo;
  const glm::dvec3 h = glm::dot(sum, sum) > 0.0 ? glm::normalize(sum) : glm::dvec3(0.0, 0.0, 1.0);
  const double cosH = std::clamp(h.z, -1.0, 1.0), cosD = std::clamp(glm::dot(wi, h), -1.0, 1.0);
  switch (p) {
    case AltaParam::CosTh:
      return {cosH, 0, 0, 0, 0, 0};
    case AltaParam::CosThTd:
      return {cosH, cosD, 0, 0, 0, 0};
    case AltaParam::RusinThTd:
      return {angle(cosH), angle(cosD), 0, 0, 0, 0};
    case AltaParam::RusinThTdPd: {
      // Rusinkiewicz 1998: wi in h's frame, turned by -phi_h about n, then by -theta_h about the bitangent.
      const double phiH = std::atan2(h.y, h.x), thetaH = angle(cosH);
      const double cp = std::cos(phiH), sp = std::sin(phiH);
      const glm::dvec3 r1(cp * wi.x + sp * wi.y, -sp * wi.x + cp * wi.y, wi.z);
      const double ct = std::cos(thetaH), st = std::sin(thetaH);
      const glm::dvec3 d(ct * r1.x - st * r1.z, r1.y, st * r1.x + ct * r1.z);
      return {thetaH, angle(cosD), std::atan2(d.y, d.x), 0, 0, 0};
    }
    case AltaParam::IsotropicTvTlDphi:
      return {angle(wo.z), angle(wi.z), std::atan2(wi.y, wi.x) - std::atan2(wo.y, wo.x), 0, 0, 0};
    case AltaParam::SphericalTlPlTvPv:
      return {angle(wi.z), std::atan2(wi.y, wi.x), angle(wo.z), std::atan2(wo.y, wo.x), 0, 0};
    case AltaParam::Cartesian:
      return {wo.x, wo.y, wo.z, wi.x, wi.y, wi.z};
  }
  return {};
}

void altaRusinDirections(double thetaH, double thetaD, double phiD, glm::dvec3& wi, glm::dvec3& wo) {
  // Rusinkiewicz 1998: the difference vector (theta_d, phi_d) in the frame of h, turned by theta_h about y.
  const glm::dvec3 d(std::sin(thetaD) * std::cos(phiD), std::sin(thetaD) * std::sin(phiD), std::cos(thetaD));
  const double c = std::cos(thetaH), s = std::sin(thetaH);
  wi = glm::dvec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
  const glm::dvec3 h(s, 0.0, c);
  wo = 2.0 * glm::dot(wi, h) * h - wi;
}

}  // namespace iblx
