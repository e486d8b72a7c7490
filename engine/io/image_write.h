// Writing rendered images: linear float OpenEXR, and tonemapped 8-bit sRGB PNG for viewing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace iblx {

// rgb: width x height texels, row-major, top row first, 3 floats (R, G, B) per pixel, linear radiance.

// FLOAT channels R, G, B with ZIP compression: lossless, so loadEnvImage reads back exactly what was written.
void writeExr(const std::filesystem::path& path, int width, int height, std::span<const float> rgb);

// Display-referred 8-bit PNG: radiance * 2^exposureEV, clamped to [0, 1] (NaN -> 0), exact piecewise sRGB
// OETF, rounded to the nearest code value.
void writePng(const std::filesystem::path& path, int width, int height, std::span<const float> rgb,
              double exposureEV);

// An already display-referred 8-bit RGB raster (3 bytes per pixel, row-major, top row first), written as is;
// used for figures. Throws Error naming the path if the size does not match or the file cannot be written.
void writePngRgb8(const std::filesystem::path& path, int width, int height,
                  std::span<const std::uint8_t> rgb);

// Chooses the format from the extension (.exr or .png, case-insensitive); exposureEV only affects PNG.
void writeImage(const std::filesystem::path& path, int width, int height, std::span<const float> rgb,
                double exposureEV = 0.0);

// The exact sRGB OETF (IEC 61966-2-1) for linear x in [0, 1].
double linearToSrgb(double x);

// Radiance to display code values, shared by PNG output and the viewer so both show the same bytes.
enum class Tonemap {
  Clamp,     // min(x, 1): what writePng does
  Reinhard,  // x / (1 + x) per channel (Reinhard et al. 2002, eq. 3)
  Aces,      // Narkowicz's fit of the ACES filmic curve (2015): x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)
};
struct DisplayTransform {
  double exposureEV = 0.0;  // radiance * 2^exposureEV before the curve
  Tonemap tonemap = Tonemap::Clamp;
  double gamma = 0.0;  // 0: the exact sRGB OETF; otherwise x^(1/gamma)
};
// One display code value (0-255) for a linear radiance value; NaN and negatives give 0, +Inf gives 255.
std::uint8_t toDisplayByte(float radiance, const DisplayTransform& transform);

}  // namespace iblx
