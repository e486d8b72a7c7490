// ALTA's parametrisations on the GPU: the forward map from a direction pair (wi = light, wo = view) to the
// coordinates of the parametrisation ALTA_PARAM_IN, numbered as engine/io/alta_params.h's AltaParam lists
// them. The GLSL twin of altaRawCoordinates (engine/io/alta_params.cpp, which defines each map and cites its
// source); shared by ALTA data (shaders/brdf/alta_data.glsl) and the generated part of ALTA function files
// (engine/scene/alta_func_brdf.cpp). Azimuths are atan2's, in (-pi, pi]; folding them into a box is the
// caller's.
#ifndef IBLX_LIB_ALTA_PARAMS
#define IBLX_LIB_ALTA_PARAMS

#define ALTA_RUSIN_TH_PH_TD_PD 0
#define ALTA_RUSIN_TH_TD_PD 1
#define ALTA_RUSIN_TH_TD 2
#define ALTA_RUSIN_VH 3
#define ALTA_COS_TH_TD 4
#define ALTA_COS_TH 5
#define ALTA_SCHLICK_VH 6
#define ALTA_SCHLICK_TL_TK_PROJ_DPHI 7
#define ALTA_COS_TK 8
#define ALTA_RETRO_TL_TVL_PROJ_DPHI 9
#define ALTA_STEREOGRAPHIC 10
#define ALTA_SPHERICAL_TL_PL_TV_PV 11
#define ALTA_COS_TLV 12
#define ALTA_COS_TLR 13
#define ALTA_ISOTROPIC_TV_TL_DPHI 14
#define ALTA_ISOTROPIC_TV_PROJ_DPHI 15
#define ALTA_ISOTROPIC_TL_TV_PROJ_DPHI 16
#define ALTA_STARK_2D 17
#define ALTA_STARK_3D 18
#define ALTA_NEUMANN_2D 19
#define ALTA_NEUMANN_3D 20
#define ALTA_CARTESIAN 21

#ifndef ALTA_PARAM_IN
#error "define ALTA_PARAM_IN (engine/io/alta_params.h's AltaParam as a number) before including lib/alta_params.glsl"
#endif

// atan2 with atan2(0, 0) = 0, as C's (GLSL leaves it undefined).
float altaAtan2(float y, float x) { return x == 0.0 && y == 0.0 ? 0.0 : atan(y, x); }
float altaTheta(float cosine) { return acos(clamp(cosine, -1.0, 1.0)); }
vec3 altaNormalizedOr(vec3 v, vec3 fallback) { return dot(v, v) > 1e-20 ? normalize(v) : fallback; }

// Rusinkiewicz 1998: wi in h's frame, turned by -phi_h about n, then by -theta_h about the bitangent.
vec3 altaDifferenceVector(vec3 wi, float thetaH, float phiH) {
  float cp = cos(phiH), sp = sin(phiH), ct = cos(thetaH), st = sin(thetaH);
  vec3 r1 = vec3(cp * wi.x + sp * wi.y, -sp * wi.x + cp * wi.y, wi.z);
  return vec3(ct * r1.x - st * r1.z, r1.y, st * r1.x + ct * r1.z);
}

// The coordinates in ALTA_PARAM_IN's order; unused entries 0.
void altaParamCoordinates(vec3 wi, vec3 wo, out float x[6]) {
  x = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  vec3 h = altaNormalizedOr(wi + wo, vec3(0.0, 0.0, 1.0));
  vec3 hT = 0.5 * (wo + wi), bT = 0.5 * (wi - wo);  // Stark et al. 2005's H~ and B~
#if ALTA_PARAM_IN == ALTA_RUSIN_TH_PH_TD_PD || ALTA_PARAM_IN == ALTA_RUSIN_TH_TD_PD
  float thetaH = altaTheta(h.z), phiH = altaAtan2(h.y, h.x);
  vec3 d = altaDifferenceVector(wi, thetaH, phiH);
#if ALTA_PARAM_IN == ALTA_RUSIN_TH_PH_TD_PD
  x[0] = thetaH, x[1] = phiH, x[2] = altaTheta(d.z), x[3] = altaAtan2(d.y, d.x);
#else
  x[0] = thetaH, x[1] = altaTheta(d.z), x[2] = altaAtan2(d.y, d.x);
#endif
#elif ALTA_PARAM_IN == ALTA_RUSIN_TH_TD
  x[0] = altaTheta(h.z), x[1] = altaTheta(dot(wi, h));
#elif ALTA_PARAM_IN == ALTA_RUSIN_VH
  x[0] = h.x, x[1] = h.y, x[2] = h.z;
#elif ALTA_PARAM_IN == ALTA_COS_TH_TD
  x[0] = clamp(h.z, -1.0, 1.0), x[1] = clamp(dot(wi, h), -1.0, 1.0);
#elif ALTA_PARAM_IN == ALTA_COS_TH
  x[0] = clamp(h.z, -1.0, 1.0);
#elif ALTA_PARAM_IN == ALTA_SCHLICK_VH
  vec3 k = altaNormalizedOr(vec3(wi.x - wo.x, wi.y - wo.y, wo.z + wi.z), vec3(0.0, 0.0, 1.0));
  x[0] = k.x, x[1] = k.y, x[2] = k.z;
#elif ALTA_PARAM_IN == ALTA_SCHLICK_TL_TK_PROJ_DPHI
  vec3 k = altaNormalizedOr(vec3(wo.x - wi.x, wo.y - wi.y, wo.z + wi.z), vec3(0.0, 0.0, 1.0));
  float thetaK = altaTheta(k.z), dk = altaAtan2(wi.y, wi.x) - altaAtan2(k.y, k.x);
  x[0] = altaTheta(wi.z), x[1] = thetaK * cos(dk), x[2] = thetaK * sin(dk);
#elif ALTA_PARAM_IN == ALTA_COS_TK
  x[0] = altaNormalizedOr(vec3(wo.x - wi.x, wo.y - wi.y, wo.z + wi.z), vec3(0.0, 0.0, 1.0)).z;
#elif ALTA_PARAM_IN == ALTA_RETRO_TL_TVL_PROJ_DPHI
  // The angle a at L between the arcs to the normal and to V: spherical laws of cosines and sines.
  float thetaL = altaTheta(wi.z), thetaV = altaTheta(wo.z);
  float cosVL = clamp(dot(wo, wi), -1.0, 1.0), thetaVL = acos(cosVL);
  float sinL = sin(thetaL), sinVL = sin(thetaVL);
  x[0] = thetaL, x[1] = thetaV - thetaL, x[2] = 0.0;
  if (sinL * sinVL >= 1e-6) {
    float cosA = (cos(thetaV) - cos(thetaL) * cosVL) / (sinL * sinVL);
    float sinA = sin(altaAtan2(wi.y, wi.x) - altaAtan2(wo.y, wo.x)) * sin(thetaV) / sinVL;
    float a = atan(sinA, cosA);
    x[1] = thetaVL * cos(a), x[2] = thetaVL * sin(a);
  }
#elif ALTA_PARAM_IN == ALTA_STEREOGRAPHIC
  x[0] = wo.x / (1.0 + wo.z), x[1] = wo.y / (1.0 + wo.z), x[2] = wi.x / (1.0 + wi.z), x[3] = wi.y / (1.0 + wi.z);
#elif ALTA_PARAM_IN == ALTA_SPHERICAL_TL_PL_TV_PV
  x[0] = altaTheta(wi.z), x[1] = altaAtan2(wi.y, wi.x), x[2] = altaTheta(wo.z), x[3] = altaAtan2(wo.y, wo.x);
#elif ALTA_PARAM_IN == ALTA_COS_TLV
  x[0] = dot(wo, wi);
#elif ALTA_PARAM_IN == ALTA_COS_TLR
  x[0] = wo.x * wi.x - wo.y * wi.y - wo.z * wi.z;
#elif ALTA_PARAM_IN == ALTA_ISOTROPIC_TV_TL_DPHI
  x[0] = altaTheta(wo.z), x[1] = altaTheta(wi.z), x[2] = altaAtan2(wi.y, wi.x) - altaAtan2(wo.y, wo.x);
#elif ALTA_PARAM_IN == ALTA_ISOTROPIC_TV_PROJ_DPHI
  float thetaV = altaTheta(wo.z), dv = altaAtan2(wo.y, wo.x) - altaAtan2(wi.y, wi.x);
  x[0] = thetaV * cos(dv), x[1] = thetaV * sin(dv);
#elif ALTA_PARAM_IN == ALTA_ISOTROPIC_TL_TV_PROJ_DPHI
  float thetaV = altaTheta(wo.z), dl = altaAtan2(wi.y, wi.x) - altaAtan2(wo.y, wo.x);
  x[0] = altaTheta(wi.z), x[1] = thetaV * cos(dl), x[2] = thetaV * sin(dl);
#elif ALTA_PARAM_IN == ALTA_STARK_2D || ALTA_PARAM_IN == ALTA_STARK_3D
  x[0] = length(hT.xy), x[1] = length(bT);
#if ALTA_PARAM_IN == ALTA_STARK_3D
  x[2] = altaAtan2(bT.y, bT.x) - altaAtan2(hT.y, hT.x);
  x[2] = x[2] < 0.0 ? x[2] + 6.28318530717958647692 : x[2];  // [0, 2 pi), as Stark et al. define it
#endif
#elif ALTA_PARAM_IN == ALTA_NEUMANN_2D || ALTA_PARAM_IN == ALTA_NEUMANN_3D
  x[0] = length(hT.xy), x[1] = length(bT.xy);
#if ALTA_PARAM_IN == ALTA_NEUMANN_3D
  x[2] = altaAtan2(bT.y, bT.x) - altaAtan2(hT.y, hT.x);
#endif
#elif ALTA_PARAM_IN == ALTA_CARTESIAN
  x[0] = wo.x, x[1] = wo.y, x[2] = wo.z, x[3] = wi.x, x[4] = wi.y, x[5] = wi.z;
#else
#error "ALTA_PARAM_IN is not one of ALTA's parametrisations"
#endif
}

#endif
