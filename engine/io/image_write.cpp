// Image writers: OpenEXR for linear data, stb_image_write for tonemapped PNG.
#include "engine/io/image_write.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/file_names.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace iblx {
namespace {

namespace fs = std::filesystem;

// Size mismatches are caller bugs, but an Error naming the file is what a tool can report in one line.
void checkImageSize(const fs::path& path, int width, int height, std::span<const float> rgb) {
  if (width <= 0 || height <= 0)
    throw Error("cannot write " + path.string() + ": invalid image size " + std::to_string(width) + "x" +
                std::to_string(height));
  const std::size_t expected = 3 * std::size_t(width) * std::size_t(height);
  if (rgb.size() != expected)
    throw Error("cannot write " + path.string() + ": " + std::to_string(rgb.size()) + " floats given for a " +
                std::to_string(width) + "x" + std::to_string(height) + " RGB image (expected " +
                std::to_string(expected) + ")");
}

}  // namespace

double srgbToLinear(double x) {
  return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4);
}

double linearToSrgb(double x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

std::uint8_t toDisplayByte(float radiance, const DisplayTransform& transform) {
  const double v = double(radiance) * std::exp2(transform.exposureEV);
  if (!(v > 0.0)) return 0;  // also NaN
  double mapped = 1.0;
  switch (transform.tonemap) {
    case Tonemap::Clamp:
      mapped = std::min(v, 1.0);
      break;
    case Tonemap::Reinhard:
      mapped = std::isinf(v) ? 1.0 : v / (1.0 + v);
      break;
    case Tonemap::Aces:
      mapped =
          std::isinf(v) ? 1.0 : std::clamp(v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14), 0.0, 1.0);
      break;
  }
  const double encoded =
      transform.gamma > 0.0 ? std::pow(mapped, 1.0 / transform.gamma) : linearToSrgb(mapped);
  return std::uint8_t(std::lround(255.0 * encoded));
}

namespace {

// Writes a float RGB image with ZIP compression to `stream`. OpenEXR writes the offset table in OutputFile's
// destructor and swallows its errors there: callers check their stream's state afterwards.
void writeExrTo(Imf::OStream& stream, int width, int height, std::span<const float> rgb) {
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  const char* const names[3] = {"R", "G", "B"};
  Imf::FrameBuffer frameBuffer;
  // OpenEXR's Slice takes a mutable pointer but only reads from it when writing.
  char* base = reinterpret_cast<char*>(const_cast<float*>(rgb.data()));
  const std::size_t xStride = 3 * sizeof(float), yStride = xStride * std::size_t(width);
  for (int c = 0; c < 3; ++c) {
    header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
    frameBuffer.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xStride, yStride));
  }
  Imf::OutputFile file(stream, header);
  file.setFrameBuffer(frameBuffer);
  file.writePixels(height);
}

}  // namespace

void writeExr(const fs::path& path, int width, int height, std::span<const float> rgb) {
  checkImageSize(path, width, height, rgb);
  try {
    AtomicOutput output(path);
    {
      Imf::StdOFStream stream(output.stream(), path.string().c_str());
      writeExrTo(stream, width, height, rgb);
    }
    output.commit();  // checks the stream's state after OutputFile's destructor has run
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot write EXR file " + path.string() + ": " + e.what());
  }
}

std::vector<unsigned char> encodeExr(int width, int height, std::span<const float> rgb) {
  checkImageSize("EXR image", width, height, rgb);
  Imf::StdOSStream stream;
  writeExrTo(stream, width, height, rgb);
  const std::string bytes = stream.str();
  return {bytes.begin(), bytes.end()};
}

double autoExposureEV(std::span<const float> rgb, std::span<const std::uint8_t> objectMask) {
  double sumLog = 0.0;
  std::size_t count = 0;
  for (std::size_t p = 0; 3 * p + 2 < rgb.size(); ++p) {
    if (!objectMask.empty() && (p >= objectMask.size() || objectMask[p] == 0)) continue;
    const double y =
        0.2126 * double(rgb[3 * p]) + 0.7152 * double(rgb[3 * p + 1]) + 0.0722 * double(rgb[3 * p + 2]);
    if (!(y > 0.0) || !std::isfinite(y)) continue;
    sumLog += std::log(y);
    ++count;
  }
  if (count == 0) return 0.0;
  const double logAverage = sumLog / double(count);
  return std::clamp((std::log(0.18) - logAverage) / std::log(2.0), -32.0, 32.0);
}

DisplayTransform resolveDisplay(const DisplaySettings& settings, std::span<const float> rgb,
                                std::span<const std::uint8_t> objectMask) {
  const double automatic = settings.autoExposure ? autoExposureEV(rgb, objectMask) : 0.0;
  return {
      .exposureEV = automatic + settings.exposureEV, .tonemap = settings.tonemap, .gamma = settings.gamma};
}

void writePng(const fs::path& path, int width, int height, std::span<const float> rgb, double exposureEV) {
  writePng(path, width, height, rgb, DisplayTransform{.exposureEV = exposureEV});
}

void writePng(const fs::path& path, int width, int height, std::span<const float> rgb,
              const DisplayTransform& transform) {
  checkImageSize(path, width, height, rgb);
  std::vector<std::uint8_t> bytes(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) bytes[i] = toDisplayByte(rgb[i], transform);
  writePngRgb8(path, width, height, bytes);
}

void writePngRgb8(const fs::path& path, int width, int height, std::span<const std::uint8_t> rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != 3 * std::size_t(width) * std::size_t(height))
    throw Error("cannot write " + path.string() + ": " + std::to_string(rgb.size()) + " bytes given for a " +
                std::to_string(width) + "x" + std::to_string(height) + " RGB8 image");
  // Encoded in memory, then written atomically: stb's own file writer does not report a failed write.
  std::vector<unsigned char> png;
  const auto append = [](void* context, void* data, int size) {
    auto* bytes = static_cast<std::vector<unsigned char>*>(context);
    bytes->insert(bytes->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), 3 * width))
    throw Error("cannot write PNG file " + path.string() + ": the encoder failed");
  writeFileAtomically(path, png);
}

void writeImage(const fs::path& path, int width, int height, std::span<const float> rgb) {
  writeImage(path, width, height, rgb, DisplayTransform{});
}

void writeImage(const fs::path& path, int width, int height, std::span<const float> rgb,
                const DisplayTransform& transform) {
  const std::string ext = lowerExtension(path);
  if (ext == ".exr")
    writeExr(path, width, height, rgb);
  else if (ext == ".png")
    writePng(path, width, height, rgb, transform);
  else
    throw Error("cannot write " + path.string() + ": unsupported extension '" + ext +
                "' (supported output formats: .exr, .png)");
}

}  // namespace iblx
