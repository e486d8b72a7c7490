// ALTA's input parametrisations that iblx reads (ALTA's documentation, "params"), shared by its data files
// (engine/io/alta_data.h) and function files (engine/io/alta_func.h), each of which reads a subset. Angles in
// radians; L is the light (brdfEval's wi), V the view (wo).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <string>

namespace iblx {

enum class AltaParam {
  CosTh,              // COS_TH: (cos theta_h)
  CosThTd,            // COS_TH_TD: (cos theta_h, cos theta_d)
  RusinThTd,          // RUSIN_TH_TD: (theta_h, theta_d)
  RusinThTdPd,        // RUSIN_TH_TD_PD: (theta_h, theta_d, phi_d)
  IsotropicTvTlDphi,  // ISOTROPIC_TV_TL_DPHI: (theta_V, theta_L, phi_L - phi_V)
  SphericalTlPlTvPv,  // SPHERICAL_TL_PL_TV_PV: (theta_L, phi_L, theta_V, phi_V)
  Cartesian,          // CARTESIAN: (V_x, V_y, V_z, L_x, L_y, L_z)
};

std::string altaParamName(AltaParam p);
int altaParamDimension(AltaParam p);
// The parametrisation named `name`, if iblx knows it.
std::optional<AltaParam> findAltaParam(const std::string& name);

// The coordinates of (wi = light, wo = view), local frame n = +z, as the parametrisation lists them (unused
// entries 0); azimuths as atan2 gives them, in (-pi, pi] (differences of two in (-2 pi, 2 pi)).
// Rusinkiewicz's difference vector is the light's.
std::array<double, 6> altaRawCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo);

// The light and the view at Rusinkiewicz coordinates (theta_h, theta_d, phi_d), with phi_h = 0.
void altaRusinDirections(double thetaH, double thetaD, double phiD, glm::dvec3& wi, glm::dvec3& wo);

}  // namespace iblx
