// RGL-EPFL measured materials (.bsdf; Dupuy & Jakob, "An adaptive parameterization for efficient material
// acquisition and rendering", SIGGRAPH Asia 2018): the tables of a tensor file (engine/io/tensor_file.h),
// checked field by field, spectral files converted to linear sRGB; and the writer of `iblx measured-synth`.
// engine/sampling/brdf/rgl_sampling.h turns the tables into the warps that evaluate and sample the material.
//
// Fields: theta_i f32[nt] and phi_i f32[np] (the incident directions measured; np <= 2 means isotropic),
// ndf and sigma f32[H, W] over (u_theta, u_phi) of a direction, vndf f32[np, nt, H, W] over the microfacet
// normal, luminance f32[np, nt, N, N] and rgb f32[np, nt, 3, N, N] over the VNDF warp's unit square, or
// spectra f32[np, nt, nl, N, N] with wavelengths f32[nl] in nm; description u8[n]; jacobian u8[1] (1: the
// values are divided by the warp's Jacobian ndf / (4 sigma), which evaluation multiplies back; a file
// without the field is read as 1).
//
// Spectra become linear sRGB (D65 primaries) by integrating against the CIE 1931 2-degree observer (the
// multi-lobe fit of Wyman, Sloan & Shirley 2013, JCGT 2(2)) with the trapezoid rule over the file's
// wavelengths, then dividing each channel by the value a constant spectrum of 1 gets, so that a grey
// spectrum stays grey (a von Kries adaptation from illuminant E to the display white).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace iblx {

struct RglGrid {
  std::uint32_t width = 0, height = 0;  // width is the grid's last axis (u_theta for ndf, sigma and vndf)
  std::vector<float> values;            // slices x height x width
};

struct RglTables {
  std::string description;
  std::vector<float> thetaI, phiI;  // radians, increasing
  RglGrid ndf, sigma;               // one slice each
  RglGrid vndf;                     // phiI.size() x thetaI.size() slices
  RglGrid luminance;                // phiI.size() x thetaI.size() slices
  RglGrid rgb;                      // phiI.size() x thetaI.size() x 3 slices, negative entries zeroed
  bool jacobian = true;
  std::size_t spectralBands = 0;  // > 0: rgb was converted from this many wavelengths
  std::size_t negativeEntries = 0;

  bool isotropic() const { return phiI.size() <= 2; }
  // Anisotropic files may store a half or a quarter of the azimuths and rely on mirror symmetry: 1, 2 or 4.
  int reduction() const;
};

// Whether a file starts like a tensor file (the .bsdf container).
bool looksLikeRglBsdf(const std::filesystem::path& path);

// Throws iblx::Error "FILE: problem" naming the field for a missing field, a wrong dtype or shape, values
// that are not finite or above 1e15, negative ndf, sigma, vndf or luminance values, a sigma of 0, theta_i or
// phi_i not increasing, a phi_i range that is not a whole, half or quarter turn, and everything
// readTensorFile refuses, and a vndf or luminance slice that is 0 everywhere. Negative rgb (or spectral)
// values are zeroed with one warning giving their count.
RglTables loadRglBsdf(const std::filesystem::path& path);

// Writes the tables as a .bsdf tensor file (RGB, with description and jacobian fields).
void writeRglBsdf(const std::filesystem::path& path, const RglTables& tables);

// The linear sRGB of a spectrum sampled at `wavelengths` (nm), by the rule above (exposed for tests).
struct SpectrumToRgb {
  explicit SpectrumToRgb(const std::vector<float>& wavelengths);
  void convert(const float* spectrum, std::size_t stride, double rgb[3]) const;

 private:
  std::vector<double> weightR_, weightG_, weightB_;
};

}  // namespace iblx
