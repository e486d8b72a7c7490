// BRDF technique "merl-table" for "merl": per-theta_o slices of 2D float CDFs of f cos over the half vector
// (u_theta rows x u_phi columns, phi_h relative to wo's azimuth); engine/sampling/brdf/merl_sampling.cpp builds them
// and documents the layout. sample() and pdf() pick the slice of wo the same way. Twin: MerlTableSampler.
#include "lib/table.glsl"
#include "lib/merl_half_vector.glsl"

IBLX_TABLE(merlTable, 1);

const int kMerlSlices = 32, kMerlRows = 90, kMerlColumns = 64;
const int kMerlSliceFloats = (kMerlRows + 1) + kMerlRows * (kMerlColumns + 1);

uint merlSliceBase(vec3 wo) {
  float thetaO = atan(length(wo.xy), wo.z);
  return uint(clamp(int(thetaO / (0.5 * kPi) * float(kMerlSlices)), 0, kMerlSlices - 1) * kMerlSliceFloats);
}

float merlAzimuth(vec3 w) { return (w.x == 0.0 && w.y == 0.0) ? 0.0 : atan(w.y, w.x); }

// The azimuth u_phi is measured from: the view's, or the tangent's for tables over phi_h itself (brdf-tab on
// an anisotropic BRDF, whose lobe is fixed in the tangent frame).
float tableAzimuthOrigin(vec3 wo) {
#ifdef HALF_VECTOR_TABLE_ABSOLUTE_PHI
  return 0.0;
#else
  return merlAzimuth(wo);
#endif
}

uint merlRowBase(uint slice, int row) { return slice + uint(kMerlRows + 1 + row * (kMerlColumns + 1)); }

// Largest i in [0, n) with table[base + i] <= u (table[base + n] = 1 > u). n is a constant: the loop unrolls.
int merlTableBin(uint base, const int n, float u) { return tableSearchFloat(merlTable, base, 0, n, u); }

vec3 brdfSample(vec2 u, vec3 wo, out float pdf) {
  pdf = 0.0;
  if (wo.z <= 0.0) return vec3(0.0, 0.0, 1.0);
  uint slice = merlSliceBase(wo);
  int row = merlTableBin(slice, kMerlRows, u.y);
  float r0 = tableFloat(merlTable, slice + uint(row));
  float rowProb = tableFloat(merlTable, slice + uint(row) + 1u) - r0;
  uint rowBase = merlRowBase(slice, row);
  int column = merlTableBin(rowBase, kMerlColumns, u.x);
  float c0 = tableFloat(merlTable, rowBase + uint(column));
  float columnProb = tableFloat(merlTable, rowBase + uint(column) + 1u) - c0;
  // rowProb, columnProb > 0: the searches never return a zero-width bin; the guards keep the code total.
  float ty = rowProb > 0.0 ? clamp((u.y - r0) / rowProb, 0.0, kOneMinusEpsilon) : 0.5;
  float tx = columnProb > 0.0 ? clamp((u.x - c0) / columnProb, 0.0, kOneMinusEpsilon) : 0.5;
  float uTheta = (float(row) + ty) / float(kMerlRows);
  float uPhi = (float(column) + tx) / float(kMerlColumns);
  vec3 h = merlHalfVector(uTheta, tableAzimuthOrigin(wo) + kTwoPi * uPhi);
  float woDotH = dot(wo, h);
  vec3 wi = 2.0 * woDotH * h - wo;
  float pdfU = rowProb * columnProb * float(kMerlRows * kMerlColumns);
  pdf = merlHalfVectorPdf(pdfU, uTheta, length(h.xy), woDotH);
  return wi;
}

float brdfPdf(vec3 wi, vec3 wo) {
  vec3 h;
  if (wo.z <= 0.0 || !merlHalfVectorOf(wi, wo, h)) return 0.0;
  uint slice = merlSliceBase(wo);
  float sinThetaH;
  float uTheta = merlUTheta(h, sinThetaH);
  float uPhi = fract((merlAzimuth(h) - tableAzimuthOrigin(wo)) / kTwoPi);
  int row = clamp(int(uTheta * float(kMerlRows)), 0, kMerlRows - 1);
  int column = clamp(int(uPhi * float(kMerlColumns)), 0, kMerlColumns - 1);
  uint rowBase = merlRowBase(slice, row);
  float rowProb = tableFloat(merlTable, slice + uint(row) + 1u) - tableFloat(merlTable, slice + uint(row));
  float columnProb =
      tableFloat(merlTable, rowBase + uint(column) + 1u) - tableFloat(merlTable, rowBase + uint(column));
  float pdfU = rowProb * columnProb * float(kMerlRows * kMerlColumns);
  return merlHalfVectorPdf(pdfU, uTheta, sinThetaH, dot(wo, h));
}
