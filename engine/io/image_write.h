// Writing rendered images: linear float OpenEXR, and tonemapped 8-bit sRGB PNG for viewing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace iblx {

// rgb: width x height texels, row-major, top row first, 3 floats (R, G, B) per pixel, linear radiance.

// FLOAT channels R, G, B with ZIP compression: lossless, so loadEnvImage reads back exactly what was written.
void writeExr(const std::filesystem::path& path, int width, int height, std::span<const float> rgb);

struct DisplayTransform;
// Display-referred 8-bit PNG: every channel through toDisplayByte(transform).
void writePng(const std::filesystem::path& path, int width, int height, std::span<const float> rgb,
              const DisplayTransform& transform);
// The same with the clamp curve: radiance * 2^exposureEV, clamped to [0, 1] (NaN -> 0), exact piecewise sRGB
// OETF, rounded to the nearest code value.
void writePng(const std::filesystem::path& path, int width, int height, std::span<const float> rgb,
              double exposureEV);

// An already display-referred 8-bit RGB raster (3 bytes per pixel, row-major, top row first), written as is;
// used for figures. Throws Error naming the path if the size does not match or the file cannot be written.
void writePngRgb8(const std::filesystem::path& path, int width, int height,
                  std::span<const std::uint8_t> rgb);

// Chooses the format from the extension (.exr or .png, case-insensitive); the transform only affects PNG
// (EXR stays linear and untouched).
void writeImage(const std::filesystem::path& path, int width, int height, std::span<const float> rgb,
                const DisplayTransform& transform);
void writeImage(const std::filesystem::path& path, int width, int height, std::span<const float> rgb);
// The bytes writeExr would write, in memory (for files written sealed, engine/core/cache_file.h).
std::vector<unsigned char> encodeExr(int width, int height, std::span<const float> rgb);

// The exact sRGB OETF (IEC 61966-2-1) for linear x in [0, 1].
double linearToSrgb(double x);
// Its inverse, the sRGB EOTF (IEC 61966-2-1), for encoded x in [0, 1].
double srgbToLinear(double x);

// Radiance to display code values, shared by PNG output, the viewer and every figure showing an image, so all
// show the same bytes.
enum class Tonemap {
  Clamp,     // min(x, 1)
  Reinhard,  // x / (1 + x) per channel (Reinhard et al. 2002, eq. 3)
  Aces,      // Narkowicz's fit of the ACES filmic curve (2015): x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)
};
// The curve names the command line and the viewer use ("clamp", "reinhard", "aces"), in enum order.
inline constexpr const char* kTonemapNames[] = {"clamp", "reinhard", "aces"};

// One image's transform, with its exposure resolved.
struct DisplayTransform {
  double exposureEV = 0.0;  // radiance * 2^exposureEV before the curve
  Tonemap tonemap = Tonemap::Clamp;
  double gamma = 0.0;  // 0: the exact sRGB OETF; otherwise x^(1/gamma)
};
// One display code value (0-255) for a linear radiance value; NaN and negatives give 0, +Inf gives 255.
std::uint8_t toDisplayByte(float radiance, const DisplayTransform& transform);

// What a user chooses (flags, viewer panel). The default fits HDR skies without flags: a 10^4 sun beside a
// sky of 1 would otherwise clip the object white at exposure 0.
struct DisplaySettings {
  bool autoExposure = true;  // add autoExposureEV of the image
  double exposureEV = 0.0;   // exposure compensation in stops (the whole exposure without autoExposure)
  Tonemap tonemap = Tonemap::Aces;
  double gamma = 0.0;
};
// The exposure that maps the log-average luminance of the object's pixels to middle grey 0.18: the "key" of
// Reinhard et al. 2002 (eq. 1, a = 0.18), log2(0.18 / exp(mean log Y)), Y Rec. 709 luminance. Pixels of zero
// luminance and background pixels (objectMask[p] == 0; an empty mask takes every pixel) are left out, so a
// black half or the sky behind the object does not pull the key. 0 when no pixel is lit; clamped to [-32,
// 32].
double autoExposureEV(std::span<const float> rgb, std::span<const std::uint8_t> objectMask);
// The transform for one image under the given settings.
DisplayTransform resolveDisplay(const DisplaySettings& settings, std::span<const float> rgb,
                                std::span<const std::uint8_t> objectMask);

}  // namespace iblx
