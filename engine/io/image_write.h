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

}  // namespace iblx
