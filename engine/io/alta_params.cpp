// ALTA's parametrisations: names, dimensions, forward maps and inverses (alta_params.h).
#include "engine/io/alta_params.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace iblx {
namespace {

constexpr double kPi = std::numbers::pi;

struct ParamEntry {
  AltaParam param;
  const char* name;
  int dimension;
};
constexpr ParamEntry kParams[] = {
    {AltaParam::RusinThPhTdPd, "RUSIN_TH_PH_TD_PD", 4},
    {AltaParam::RusinThTdPd, "RUSIN_TH_TD_PD", 3},
    {AltaParam::RusinThTd, "RUSIN_TH_TD", 2},
    {AltaParam::RusinVh, "RUSIN_VH", 3},
    {AltaParam::CosThTd, "COS_TH_TD", 2},
    {AltaParam::CosTh, "COS_TH", 1},
    {AltaParam::SchlickVk, "SCHLICK_VH", 3},
    {AltaParam::SchlickTlTkProjDphi, "SCHLICK_TL_TK_PROJ_DPHI", 3},
    {AltaParam::CosTk, "COS_TK", 1},
    {AltaParam::RetroTlTvlProjDphi, "RETRO_TL_TVL_PROJ_DPHI", 3},
    {AltaParam::Stereographic, "STEREOGRAPHIC", 4},
    {AltaParam::SphericalTlPlTvPv, "SPHERICAL_TL_PL_TV_PV", 4},
    {AltaParam::CosTlv, "COS_TLV", 1},
    {AltaParam::CosTlr, "COS_TLR", 1},
    {AltaParam::IsotropicTvTlDphi, "ISOTROPIC_TV_TL_DPHI", 3},
    {AltaParam::IsotropicTvProjDphi, "ISOTROPIC_TV_PROJ_DPHI", 2},
    {AltaParam::IsotropicTlTvProjDphi, "ISOTROPIC_TL_TV_PROJ_DPHI", 3},
    {AltaParam::Stark2d, "STARK_2D", 2},
    {AltaParam::Stark3d, "STARK_3D", 3},
    {AltaParam::Neumann2d, "NEUMANN_2D", 2},
    {AltaParam::Neumann3d, "NEUMANN_3D", 3},
    {AltaParam::Cartesian, "CARTESIAN", 6},
};

double angle(double cosine) {
  return std::acos(std::clamp(cosine, -1.0, 1.0));
}
double azimuth(const glm::dvec3& v) {
  return std::atan2(v.y, v.x);
}
glm::dvec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
glm::dvec3 normalizedOr(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double length2 = glm::dot(v, v);
  return length2 > 1e-20 ? v / std::sqrt(length2) : fallback;
}
glm::dvec3 halfVector(const glm::dvec3& wi, const glm::dvec3& wo) {
  return normalizedOr(wi + wo, {0.0, 0.0, 1.0});
}
// A unit vector from its tangent-plane part (x, y), above the plane; nullopt outside the unit disc.
std::optional<glm::dvec3> fromProjection(double x, double y) {
  const double r2 = x * x + y * y;
  if (!(r2 <= 1.0 + 1e-12)) return std::nullopt;
  return glm::dvec3(x, y, std::sqrt(std::max(0.0, 1.0 - r2)));
}
// The polar form of a projected pair (r cos a, r sin a).
void polar(double x, double y, double& r, double& a) {
  r = std::sqrt(x * x + y * y);
  a = r > 0.0 ? std::atan2(y, x) : 0.0;
}

// Rusinkiewicz 1998: wi in h's frame, turned by -phi_h about n, then by -theta_h about the bitangent.
glm::dvec3 differenceVector(const glm::dvec3& wi, const glm::dvec3& h) {
  const double phiH = azimuth(h), thetaH = angle(h.z);
  const double cp = std::cos(phiH), sp = std::sin(phiH);
  const glm::dvec3 r1(cp * wi.x + sp * wi.y, -sp * wi.x + cp * wi.y, wi.z);
  const double ct = std::cos(thetaH), st = std::sin(thetaH);
  return {ct * r1.x - st * r1.z, r1.y, st * r1.x + ct * r1.z};
}

glm::dvec3 rotateZ(const glm::dvec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

}  // namespace

std::span<const AltaParam> altaParams() {
  static const std::vector<AltaParam> all = [] {
    std::vector<AltaParam> list;
    for (const auto& e : kParams) list.push_back(e.param);
    return list;
  }();
  return all;
}

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
  if (name == "SCHLICK_VK") return AltaParam::SchlickVk;  // the enum's name; ALTA writes SCHLICK_VH
  for (const auto& e : kParams)
    if (name == e.name) return e.param;
  return std::nullopt;
}

AltaAngle altaAngleKind(AltaParam p, int coordinate) {
  switch (p) {
    case AltaParam::RusinThTdPd:
      return coordinate == 2 ? AltaAngle::Reciprocity : AltaAngle::NotAngle;
    case AltaParam::IsotropicTvTlDphi:
      return coordinate == 2 ? AltaAngle::Mirror : AltaAngle::NotAngle;
    case AltaParam::RusinThPhTdPd:
    case AltaParam::SphericalTlPlTvPv:
      return coordinate == 1 || coordinate == 3 ? AltaAngle::Turn : AltaAngle::NotAngle;
    case AltaParam::Stark3d:
    case AltaParam::Neumann3d:
      return coordinate == 2 ? AltaAngle::Turn : AltaAngle::NotAngle;
    default:
      return AltaAngle::NotAngle;
  }
}

std::array<double, 6> altaRawCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo) {
  const glm::dvec3 h = halfVector(wi, wo);
  const double cosH = std::clamp(h.z, -1.0, 1.0), cosD = std::clamp(glm::dot(wi, h), -1.0, 1.0);
  const glm::dvec3 hTilde = 0.5 * (wo + wi), bTilde = 0.5 * (wi - wo);
  const double hProjected = std::hypot(hTilde.x, hTilde.y);
  switch (p) {
    case AltaParam::RusinThPhTdPd: {
      const glm::dvec3 d = differenceVector(wi, h);
      return {angle(cosH), azimuth(h), angle(cosD), azimuth(d), 0, 0};
    }
    case AltaParam::RusinThTdPd: {
      const glm::dvec3 d = differenceVector(wi, h);
      return {angle(cosH), angle(cosD), azimuth(d), 0, 0, 0};
    }
    case AltaParam::RusinThTd:
      return {angle(cosH), angle(cosD), 0, 0, 0, 0};
    case AltaParam::RusinVh:
      return {h.x, h.y, h.z, 0, 0, 0};
    case AltaParam::CosThTd:
      return {cosH, cosD, 0, 0, 0, 0};
    case AltaParam::CosTh:
      return {cosH, 0, 0, 0, 0, 0};
    case AltaParam::SchlickVk: {
      const glm::dvec3 k = normalizedOr({wi.x - wo.x, wi.y - wo.y, wo.z + wi.z}, {0.0, 0.0, 1.0});
      return {k.x, k.y, k.z, 0, 0, 0};
    }
    case AltaParam::SchlickTlTkProjDphi: {
      const glm::dvec3 k = normalizedOr({wo.x - wi.x, wo.y - wi.y, wo.z + wi.z}, {0.0, 0.0, 1.0});
      const double thetaK = angle(k.z), d = azimuth(wi) - azimuth(k);
      return {angle(wi.z), thetaK * std::cos(d), thetaK * std::sin(d), 0, 0, 0};
    }
    case AltaParam::CosTk: {
      const glm::dvec3 k = normalizedOr({wo.x - wi.x, wo.y - wi.y, wo.z + wi.z}, {0.0, 0.0, 1.0});
      return {k.z, 0, 0, 0, 0, 0};
    }
    case AltaParam::RetroTlTvlProjDphi: {
      const double thetaL = angle(wi.z), thetaV = angle(wo.z),
                   cosVL = std::clamp(glm::dot(wo, wi), -1.0, 1.0);
      const double thetaVL = angle(cosVL), sinL = std::sin(thetaL), sinVL = std::sin(thetaVL);
      if (sinL * sinVL < 1e-12) return {thetaL, thetaV - thetaL, 0, 0, 0, 0};
      const double cosA = (std::cos(thetaV) - std::cos(thetaL) * cosVL) / (sinL * sinVL);
      const double sinA = std::sin(azimuth(wi) - azimuth(wo)) * std::sin(thetaV) / sinVL;
      const double a = std::atan2(sinA, cosA);
      return {thetaL, thetaVL * std::cos(a), thetaVL * std::sin(a), 0, 0, 0};
    }
    case AltaParam::Stereographic:
      return {wo.x / (1.0 + wo.z), wo.y / (1.0 + wo.z), wi.x / (1.0 + wi.z), wi.y / (1.0 + wi.z), 0, 0};
    case AltaParam::SphericalTlPlTvPv:
      return {angle(wi.z), azimuth(wi), angle(wo.z), azimuth(wo), 0, 0};
    case AltaParam::CosTlv:
      return {glm::dot(wo, wi), 0, 0, 0, 0, 0};
    case AltaParam::CosTlr:
      return {wo.x * wi.x - wo.y * wi.y - wo.z * wi.z, 0, 0, 0, 0, 0};
    case AltaParam::IsotropicTvTlDphi:
      return {angle(wo.z), angle(wi.z), azimuth(wi) - azimuth(wo), 0, 0, 0};
    case AltaParam::IsotropicTvProjDphi: {
      const double thetaV = angle(wo.z), d = azimuth(wo) - azimuth(wi);
      return {thetaV * std::cos(d), thetaV * std::sin(d), 0, 0, 0, 0};
    }
    case AltaParam::IsotropicTlTvProjDphi: {
      const double thetaV = angle(wo.z), d = azimuth(wi) - azimuth(wo);
      return {angle(wi.z), thetaV * std::cos(d), thetaV * std::sin(d), 0, 0, 0};
    }
    case AltaParam::Stark2d:
      return {hProjected, glm::length(bTilde), 0, 0, 0, 0};
    case AltaParam::Stark3d: {
      double d = azimuth(bTilde) - azimuth(hTilde);
      if (d < 0.0) d += 2.0 * kPi;
      return {hProjected, glm::length(bTilde), d, 0, 0, 0};
    }
    case AltaParam::Neumann2d:
      return {hProjected, std::hypot(bTilde.x, bTilde.y), 0, 0, 0, 0};
    case AltaParam::Neumann3d:
      return {hProjected, std::hypot(bTilde.x, bTilde.y), azimuth(bTilde) - azimuth(hTilde), 0, 0, 0};
    case AltaParam::Cartesian:
      return {wo.x, wo.y, wo.z, wi.x, wi.y, wi.z};
  }
  return {};
}

std::optional<std::pair<glm::dvec3, glm::dvec3>> altaDirections(AltaParam p, std::span<const double> x) {
  const auto at = [&](std::size_t i) { return i < x.size() ? x[i] : 0.0; };
  glm::dvec3 wi(0.0, 0.0, 1.0), wo(0.0, 0.0, 1.0);
  switch (p) {
    case AltaParam::RusinThPhTdPd:
      altaRusinDirections(at(0), at(2), at(3), wi, wo);
      wi = rotateZ(wi, at(1)), wo = rotateZ(wo, at(1));
      break;
    case AltaParam::RusinThTdPd:
      altaRusinDirections(at(0), at(1), at(2), wi, wo);
      break;
    case AltaParam::RusinThTd:
      altaRusinDirections(at(0), at(1), 0.5 * kPi, wi, wo);
      break;
    case AltaParam::RusinVh:
      wi = wo = normalizedOr({at(0), at(1), at(2)}, {0.0, 0.0, 1.0});
      break;
    case AltaParam::CosThTd:
      altaRusinDirections(angle(at(0)), angle(at(1)), 0.0, wi, wo);
      break;
    case AltaParam::CosTh:
      wi = wo = direction(angle(at(0)), 0.0);
      break;
    case AltaParam::SchlickVk: {
      // K is the half vector of L and V mirrored about the normal: L = K, V = K's mirror image.
      const glm::dvec3 k = normalizedOr({at(0), at(1), at(2)}, {0.0, 0.0, 1.0});
      wi = k, wo = glm::dvec3(-k.x, -k.y, k.z);
      break;
    }
    case AltaParam::SchlickTlTkProjDphi: {
      double thetaK = 0.0, d = 0.0;
      polar(at(1), at(2), thetaK, d);
      wi = direction(at(0), 0.0);
      const glm::dvec3 k = direction(thetaK, -d), mirrored(-wi.x, -wi.y, wi.z);
      wo = 2.0 * glm::dot(k, mirrored) * k - mirrored;  // V + L mirrored about the normal is along K
      break;
    }
    case AltaParam::CosTk: {
      const double s = std::sqrt(std::max(0.0, 1.0 - at(0) * at(0)));
      wo = glm::dvec3(s, 0.0, at(0)), wi = glm::dvec3(-s, 0.0, at(0));
      break;
    }
    case AltaParam::RetroTlTvlProjDphi: {
      double thetaVL = 0.0, a = 0.0;
      polar(at(1), at(2), thetaVL, a);
      const double thetaL = at(0);
      wi = direction(thetaL, 0.0);
      // At L, the arc towards the normal and its perpendicular (L x towards-normal); V at angle a from the
      // first.
      const glm::dvec3 towardsNormal(-std::cos(thetaL), 0.0, std::sin(thetaL)), across(0.0, -1.0, 0.0);
      wo = std::cos(thetaVL) * wi + std::sin(thetaVL) * (std::cos(a) * towardsNormal + std::sin(a) * across);
      break;
    }
    case AltaParam::Stereographic: {
      const auto unproject = [](double u, double v) {
        const double n = u * u + v * v;
        return glm::dvec3(2.0 * u, 2.0 * v, 1.0 - n) / (1.0 + n);
      };
      wo = unproject(at(0), at(1)), wi = unproject(at(2), at(3));
      break;
    }
    case AltaParam::SphericalTlPlTvPv:
      wi = direction(at(0), at(1)), wo = direction(at(2), at(3));
      break;
    case AltaParam::CosTlv:
      wo = direction(angle(at(0)), 0.0), wi = glm::dvec3(0.0, 0.0, 1.0);
      break;
    case AltaParam::CosTlr: {
      // Two directions in the x-z plane at theta each: the value is -cos(2 theta).
      const double theta = 0.5 * angle(-at(0));
      wo = wi = direction(theta, 0.0);
      break;
    }
    case AltaParam::IsotropicTvTlDphi:
      wo = direction(at(0), 0.0), wi = direction(at(1), at(2));
      break;
    case AltaParam::IsotropicTvProjDphi: {
      double thetaV = 0.0, d = 0.0;
      polar(at(0), at(1), thetaV, d);
      wo = direction(thetaV, d), wi = glm::dvec3(0.0, 0.0, 1.0);
      break;
    }
    case AltaParam::IsotropicTlTvProjDphi: {
      double thetaV = 0.0, d = 0.0;
      polar(at(1), at(2), thetaV, d);
      wi = direction(at(0), 0.0), wo = direction(thetaV, -d);
      break;
    }
    case AltaParam::Stark2d:
    case AltaParam::Stark3d: {
      // H~ in the x-z plane, B~ of length x1 perpendicular to it at azimuth x2 (0 for STARK_2D).
      const double z2 = 1.0 - at(0) * at(0) - at(1) * at(1);
      if (!(z2 >= -1e-12)) return std::nullopt;
      const double hz = std::sqrt(std::max(0.0, z2)), phi = p == AltaParam::Stark3d ? at(2) : 0.5 * kPi;
      const double theta = std::atan2(hz, -at(0) * std::cos(phi));
      const glm::dvec3 hTilde(at(0), 0.0, hz),
          bTilde = at(1) * glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                      std::cos(theta));
      wo = hTilde - bTilde, wi = hTilde + bTilde;
      break;
    }
    case AltaParam::Neumann2d:
    case AltaParam::Neumann3d: {
      const double phi = p == AltaParam::Neumann3d ? at(2) : 0.5 * kPi;
      const double bx = at(1) * std::cos(phi), by = at(1) * std::sin(phi);
      const auto v = fromProjection(at(0) - bx, -by), l = fromProjection(at(0) + bx, by);
      if (!v || !l) return std::nullopt;
      wo = *v, wi = *l;
      break;
    }
    case AltaParam::Cartesian:
      wo = normalizedOr({at(0), at(1), at(2)}, {0.0, 0.0, 1.0});
      wi = normalizedOr({at(3), at(4), at(5)}, {0.0, 0.0, 1.0});
      break;
  }
  return std::pair{wi, wo};
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
