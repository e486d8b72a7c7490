// ALTA's input parametrisations (ALTA's documentation, "params", and its params.cpp): names, dimensions, the
// forward map from a direction pair to a parametrisation's coordinates, and an inverse that gives one
// direction pair with those coordinates. Shared by its data files (engine/io/alta_data.h) and function files
// (engine/io/alta_func.h), each of which reads a subset. Angles in radians; L is the light (brdfEval's wi), V
// the view (wo); the local frame has the normal at +z.
//
// The forward maps are ALTA's, with one convention fixed where ALTA is not consistent: Rusinkiewicz's
// difference vector is the light's (Rusinkiewicz 1998), so a phi_d differs by pi from ALTA's code, which
// rotates the view (reciprocity makes the two equivalent). Definitions (H~ = (V + L) / 2, B~ = (L - V) / 2,
// a subscript p the projection onto the tangent plane, K the "back vector" of Schlick 1994):
//   RUSIN_TH_PH_TD_PD  theta_h, phi_h, theta_d, phi_d      RUSIN_TH_TD_PD  theta_h, theta_d, phi_d
//   RUSIN_TH_TD        theta_h, theta_d                    RUSIN_VH        H (x, y, z)
//   COS_TH_TD          cos theta_h, cos theta_d            COS_TH          cos theta_h
//   SCHLICK_VH         K = normalize(L_x - V_x, L_y - V_y, V_z + L_z) (x, y, z; ALTA's own name for it)
//   SCHLICK_TL_TK_PROJ_DPHI  theta_L, theta_K cos D, theta_K sin D, with K = normalize(V_x - L_x, V_y - L_y,
//                      V_z + L_z) and D = phi_L - phi_K
//   COS_TK             the z of that K
//   RETRO_TL_TVL_PROJ_DPHI  theta_L, theta_VL cos a, theta_VL sin a: theta_VL the angle between V and L, a
//   the
//                      angle at L between the arcs to the normal and to V (spherical laws of cosines and
//                      sines; Belcour et al. 2014); theta_L, theta_V - theta_L, 0 where a is undefined
//   STEREOGRAPHIC      V_x / (1 + V_z), V_y / (1 + V_z), L_x / (1 + L_z), L_y / (1 + L_z)
//   SPHERICAL_TL_PL_TV_PV  theta_L, phi_L, theta_V, phi_V
//   COS_TLV            V . L
//   COS_TLR            V_x L_x - V_y L_y - V_z L_z (ALTA's expression, which is not the dot product with the
//                      mirror direction its name suggests)
//   ISOTROPIC_TV_TL_DPHI   theta_V, theta_L, phi_L - phi_V
//   ISOTROPIC_TV_PROJ_DPHI theta_V cos D, theta_V sin D, D = phi_V - phi_L
//   ISOTROPIC_TL_TV_PROJ_DPHI  theta_L, theta_V cos D, theta_V sin D, D = phi_L - phi_V
//   STARK_2D           |H~_p|, |B~|                        STARK_3D   |H~_p|, |B~|, phi(B~) - phi(H~) in [0,
//   2 pi) NEUMANN_2D         |H~_p|, |B~_p|                      NEUMANN_3D |H~_p|, |B~_p|, phi(B~) - phi(H~)
//   CARTESIAN          V (x, y, z), L (x, y, z)
// (Stark et al. 2005, "Barycentric parameterizations for isotropic BRDFs"; Neumann et al. 1999.) Azimuths are
// atan2's, in (-pi, pi]; differences of two are not wrapped.
//
// A parametrisation of fewer dimensions than the BRDF's drops angles, and data in it mean that the BRDF does
// not depend on them: the azimuth of the pair about the normal (isotropy) for every one but
// RUSIN_TH_PH_TD_PD, SPHERICAL_TL_PL_TV_PV, STEREOGRAPHIC, RUSIN_VH, SCHLICK_VH and CARTESIAN; phi_d too for
// RUSIN_TH_TD and COS_TH_TD; all but theta_h for COS_TH; B~'s azimuth for STARK_2D and NEUMANN_2D; theta_L
// for ISOTROPIC_TV_PROJ_DPHI; everything but the one value for COS_TK, COS_TLV and COS_TLR.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

enum class AltaParam {
  RusinThPhTdPd,
  RusinThTdPd,
  RusinThTd,
  RusinVh,
  CosThTd,
  CosTh,
  SchlickVk,
  SchlickTlTkProjDphi,
  CosTk,
  RetroTlTvlProjDphi,
  Stereographic,
  SphericalTlPlTvPv,
  CosTlv,
  CosTlr,
  IsotropicTvTlDphi,
  IsotropicTvProjDphi,
  IsotropicTlTvProjDphi,
  Stark2d,
  Stark3d,
  Neumann2d,
  Neumann3d,
  Cartesian,
};

// Every parametrisation, in the order above.
std::span<const AltaParam> altaParams();
// The name ALTA writes in files (SCHLICK_VH for SchlickVk).
std::string altaParamName(AltaParam p);
int altaParamDimension(AltaParam p);
// The parametrisation named `name` as ALTA writes it (SCHLICK_VK is read as SCHLICK_VH too), if any.
std::optional<AltaParam> findAltaParam(const std::string& name);

// The coordinates of (wi = light, wo = view), as the parametrisation lists them (unused entries 0).
std::array<double, 6> altaRawCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo);

// How a coordinate that is an azimuth (or a difference of two) comes back into a box that holds one turn or
// less of it: by whole turns; by whole turns and reciprocity (phi_d and phi_d + pi, RUSIN_TH_TD_PD); by whole
// turns and the mirror symmetry of the plane of incidence (phi_L - phi_V and its negative,
// ISOTROPIC_TV_TL_DPHI). NotAngle for the other coordinates (clamped to the box only).
enum class AltaAngle { NotAngle, Turn, Reciprocity, Mirror };
AltaAngle altaAngleKind(AltaParam p, int coordinate);

// One direction pair (wi = light, wo = view) with coordinates x (altaParamDimension(p) of them): the light at
// azimuth 0 where the parametrisation drops the pair's azimuth, a dropped angle at ALTA's choice (phi_d = pi
// / 2 for RUSIN_TH_TD, 0 for COS_TH_TD, the light at the normal for ISOTROPIC_TV_PROJ_DPHI and COS_TLV).
// nullopt when no pair has them (a STARK or NEUMANN point outside the unit disc).
std::optional<std::pair<glm::dvec3, glm::dvec3>> altaDirections(AltaParam p, std::span<const double> x);

// The light and the view at Rusinkiewicz coordinates (theta_h, theta_d, phi_d), with phi_h = 0.
void altaRusinDirections(double thetaH, double thetaD, double phiD, glm::dvec3& wi, glm::dvec3& wo);

}  // namespace iblx
