// ALTA data files (Pacanowski, Belcour, Barla et al., Inria; the ALTA library's data format): measured or
// tabulated BRDF samples as text or a binary stream, read with every check a user needs and written for
// `iblx measured-synth`. engine/io/alta_grid.h turns the samples into the table iblx renders.
//
// Header: lines "#KEY value" ("# " starts a comment), ending at the first line without '#' or at
// "#ALTA END HEADER"; #DIM N P (input and output dimensions), #PARAM_IN, #PARAM_OUT, #VS 0|1|2 (a confidence
// interval after the first output: 1 value (+-r) or 2 (min max)). Text body: one sample per line,
// x_1 .. x_N y_1 .. y_P [interval]. Binary body: #FORMAT binary, #VERSION 0, #PRECISION ieee754-double,
// #SAMPLE_COUNT n, #ENDIAN little, then "#BEGIN_STREAM" and a newline, n x (N + P + interval) doubles, and
// "#END_STREAM". Angles in radians.
//
// Inputs: every parametrisation of engine/io/alta_params.h, with wi = light L and wo = view V. Outputs:
// INV_STERADIAN (f, 1/sr), INV_STERADIAN_COSINE_FACTOR (f cos theta_L), RGB_COLOR (f per linear RGB channel)
// and XYZ_COLOR (CIE XYZ, converted to linear sRGB); 1 output is grey. A missing #PARAM_OUT is read as
// INV_STERADIAN (ALTA's reader leaves it unknown).
#pragma once

#include "engine/io/alta_params.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace iblx {

enum class AltaOutput { InvSteradian, InvSteradianCosine, RgbColor, XyzColor };

std::string altaOutputName(AltaOutput output);

struct AltaData {
  AltaParam param = AltaParam::RusinThTdPd;  // the file's
  AltaOutput output = AltaOutput::InvSteradian;
  std::size_t samples = 0;
  std::vector<double> x;    // samples x dimensions of param
  std::vector<double> rgb;  // samples x 3: linear RGB, in the output's unit (f or f cos)
  std::size_t negativeEntries = 0;
};

// The parametrisation iblx tabulates a file's samples in (engine/sampling/brdf/alta_grid.h). Where a
// conversion keeps the function and gives axes on which measurements lie as a grid (angles rather than
// cosines or vector components), one of four: the samples are converted through altaDirections
// (alta_params.h), the 4D ones and CARTESIAN to SPHERICAL_TL_PL_TV_PV; COS_TH, COS_TH_TD and STARK_2D to
// RUSIN_TH_TD (COS_TH with theta_d on one node); the isotropic 3D ones and ISOTROPIC_TV_PROJ_DPHI to
// ISOTROPIC_TV_TL_DPHI (ISOTROPIC_TV_PROJ_DPHI with theta_L on one node). Otherwise (those four, and
// RUSIN_VH, SCHLICK_VH, COS_TK, COS_TLV, COS_TLR, NEUMANN_2D, whose functions none of the four holds) the
// file's own: the GLSL part computes every parametrisation's coordinates (shaders/lib/alta_params.glsl).
AltaParam altaTableParam(AltaParam file);
// The four parametrisations above that are tables of their own: RUSIN_TH_TD_PD, RUSIN_TH_TD,
// ISOTROPIC_TV_TL_DPHI and SPHERICAL_TL_PL_TV_PV.
bool altaParamIsTableParam(AltaParam param);

// Whether a file starts like an ALTA data file: a '#' header with #DIM and #PARAM_IN, not a function file.
bool looksLikeAltaData(const std::filesystem::path& path);

// Throws iblx::Error "FILE:LINE: problem" (or "FILE: problem" for the binary stream) for a header line that
// is missing or wrong (#DIM, an unknown or unsupported #PARAM_IN or #PARAM_OUT, dimensions that disagree with
// them, #VS), a sample line with the wrong count of values or a value that is not a number, a value that is
// not finite or above 1e15, a binary stream whose length disagrees with #SAMPLE_COUNT or whose precision,
// endianness or version is not ALTA's, no samples, or more than the memory budget. Negative values are
// zeroed, with one warning giving their count.
AltaData loadAltaData(const std::filesystem::path& path);

// Writes samples (x and rgb as in AltaData, rgb in the output's unit; RGB_COLOR with 3 outputs, the other
// outputs with 1, the mean of rgb) as text or as ALTA's binary stream.
void writeAltaData(const std::filesystem::path& path, const AltaData& data, bool binary);

}  // namespace iblx
