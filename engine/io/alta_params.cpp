// ALTA's parametrisations: names and dimensions (alta_params.h).
#include "engine/io/alta_params.h"

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

}  // namespace iblx
