// Tests of the image writers: EXR layout (FLOAT R, G, B, ZIP) and exactness, PNG tonemapping to 8-bit sRGB,
// extension dispatch and errors.
#include "engine/io/env_image.h"
#include "engine/io/image_write.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>
#include <stb/stb_image.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

using namespace iblx;
using namespace iblx::test;

namespace {

// Reads the little-endian int32 at bytes[offset].
std::int32_t int32At(const std::vector<unsigned char>& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = v << 8 | bytes[offset + std::size_t(b)];
  return std::int32_t(v);
}

// The value bytes of a header attribute "name\0type\0size value", found by searching for its name and type.
std::vector<unsigned char> exrAttribute(const std::vector<unsigned char>& bytes, const std::string& name,
                                        const std::string& type) {
  std::string key = name;
  key.push_back('\0');
  key += type;
  key.push_back('\0');
  const std::string text(bytes.begin(), bytes.end());
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return {};
  const std::size_t sizeOffset = at + key.size();
  const auto size = std::size_t(int32At(bytes, sizeOffset));
  return {bytes.begin() + std::ptrdiff_t(sizeOffset + 4),
          bytes.begin() + std::ptrdiff_t(sizeOffset + 4 + size)};
}

// Channel name -> pixel type (0 uint, 1 half, 2 float) from a "chlist" attribute value.
std::map<std::string, int> exrChannels(const std::vector<unsigned char>& list) {
  std::map<std::string, int> channels;
  std::size_t pos = 0;
  while (pos < list.size() && list[pos] != 0) {
    std::string name;
    while (list[pos] != 0) name.push_back(char(list[pos++]));
    ++pos;
    channels[name] = int32At(list, pos);
    pos += 16;  // type, pLinear + reserved, xSampling, ySampling
  }
  return channels;
}

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

Png loadPng(const std::filesystem::path& path) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &png.width, &png.height, &channels, 3);
  REQUIRE(data != nullptr);
  png.rgb.assign(data, data + 3 * png.width * png.height);
  stbi_image_free(data);
  return png;
}

void checkBytes(const std::vector<unsigned char>& actual, const std::vector<unsigned char>& expected) {
  REQUIRE(actual.size() == expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) {
    CAPTURE(i);
    CHECK(int(actual[i]) == int(expected[i]));
  }
}

}  // namespace

TEST_CASE("writeExr: FLOAT R, G, B channels with ZIP compression, read back exactly") {
  ScratchDir dir;
  WarningCapture warnings;
  const int width = 6, height = 3;
  std::vector<float> rgb(3 * width * height);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(i) * 1000.5f + 1.0e-7f;
  const auto path = dir.file("layout.exr");
  writeExr(path, width, height, rgb);

  const std::vector<unsigned char> bytes = readBytes(path);
  REQUIRE(bytes.size() > 8);
  CHECK(int32At(bytes, 0) == 20000630);  // OpenEXR magic number
  const std::vector<unsigned char> compression = exrAttribute(bytes, "compression", "compression");
  REQUIRE(compression.size() == 1);
  CHECK(compression[0] == 3);  // ZIP_COMPRESSION
  const std::map<std::string, int> expected = {{"B", 2}, {"G", 2}, {"R", 2}};
  CHECK(exrChannels(exrAttribute(bytes, "channels", "chlist")) == expected);

  const EnvImage image = loadEnvImage(path);
  CHECK(image.width == width);
  CHECK(image.height == height);
  CHECK(std::memcmp(image.rgb.data(), rgb.data(), rgb.size() * sizeof(float)) == 0);
}

TEST_CASE("writeExr: top row first") {
  ScratchDir dir;
  WarningCapture warnings;
  // Row y holds the value y: after reading back, texel (x, y) must hold y.
  const int width = 4, height = 2;
  std::vector<float> rgb(3 * width * height);
  for (int y = 0; y < height; ++y)
    for (int i = 0; i < 3 * width; ++i) rgb[std::size_t(3 * width * y + i)] = float(y);
  const auto path = dir.file("rows.exr");
  writeExr(path, width, height, rgb);
  const EnvImage image = loadEnvImage(path);
  CHECK(image.rgb[3 * image.index(3, 0)] == 0.0f);
  CHECK(image.rgb[3 * image.index(0, 1)] == 1.0f);
}

TEST_CASE("linearToSrgb: exact piecewise sRGB OETF") {
  CHECK(linearToSrgb(0.0) == 0.0);
  CHECK(linearToSrgb(1.0) == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(linearToSrgb(0.5) == doctest::Approx(0.735356983).epsilon(1e-8));
  CHECK(linearToSrgb(0.001) == doctest::Approx(0.01292));
  // The two pieces meet (to within the rounding of the standard's constants) at the breakpoint.
  CHECK(linearToSrgb(0.0031308) ==
        doctest::Approx(1.055 * std::pow(0.0031308, 1.0 / 2.4) - 0.055).epsilon(1e-4));
}

TEST_CASE("toDisplayByte: the viewer's curves, worked out by hand") {
  const DisplayTransform clamp{}, reinhard{.tonemap = Tonemap::Reinhard}, aces{.tonemap = Tonemap::Aces};
  CHECK(toDisplayByte(0.5f, clamp) == 188);                                 // sRGB(0.5) = 0.7354 -> 187.5
  CHECK(toDisplayByte(0.25f, DisplayTransform{.exposureEV = 1.0}) == 188);  // 0.25 * 2^1 = 0.5
  CHECK(toDisplayByte(1.0f, reinhard) == 188);                              // 1 / (1 + 1) = 0.5
  CHECK(toDisplayByte(3.0f, reinhard) == 225);                              // 0.75 -> sRGB 0.8808 -> 224.6
  CHECK(toDisplayByte(1.0f, aces) == 232);  // 2.54 / 3.16 = 0.8038 -> sRGB 0.9082 -> 231.6
  CHECK(toDisplayByte(0.5f, DisplayTransform{.gamma = 2.2}) == 186);  // 0.5^(1/2.2) = 0.7297 -> 186.1
  for (const DisplayTransform& t : {clamp, reinhard, aces, DisplayTransform{.gamma = 2.2}}) {
    CHECK(toDisplayByte(std::numeric_limits<float>::quiet_NaN(), t) == 0);
    CHECK(toDisplayByte(-1.0f, t) == 0);
    CHECK(toDisplayByte(std::numeric_limits<float>::infinity(), t) == 255);
    CHECK(toDisplayByte(1e30f, t) == 255);
  }
}

TEST_CASE("writePng: known inputs give the expected 8-bit sRGB values") {
  ScratchDir dir;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  // One row of 4 pixels.
  const std::vector<float> rgb = {0.0f, 1.0f, 0.5f, 2.0f, -1.0f, nan, inf, 0.25f, 0.001f, 0.2f, 0.0f, 1.0f};
  SUBCASE("EV 0") {
    const auto path = dir.file("known.png");
    writePng(path, 4, 1, rgb, 0.0);
    const Png png = loadPng(path);
    REQUIRE(png.width == 4);
    REQUIRE(png.height == 1);
    const std::vector<unsigned char> expected = {0, 255, 188, 255, 0, 0, 255, 137, 3, 124, 0, 255};
    checkBytes(png.rgb, expected);
  }
  SUBCASE("exposure scales by 2^EV before the OETF") {
    const auto path = dir.file("exposure.png");
    writePng(path, 2, 1, std::vector<float>{1.0f, 0.25f, 4.0f, 0.1f, 0.2f, 2.0f}, -1.0);
    const Png png = loadPng(path);
    const std::vector<unsigned char> expected = {188, 99, 255, 63, 89, 255};
    checkBytes(png.rgb, expected);
  }
}

TEST_CASE("writeImage: dispatch on the extension, errors name the file") {
  ScratchDir dir;
  WarningCapture warnings;
  const std::vector<float> rgb = {0.5f, 0.5f, 0.5f, 1.0f, 2.0f, 3.0f};
  SUBCASE(".exr and .PNG") {
    writeImage(dir.file("out.exr"), 2, 1, rgb);
    CHECK(loadEnvImage(dir.file("out.exr")).rgb == rgb);
    writeImage(dir.file("out.PNG"), 2, 1, rgb);
    CHECK(loadPng(dir.file("out.PNG")).rgb[0] == 188);
  }
  SUBCASE("unsupported extension") {
    const auto path = dir.file("out.tiff");
    const std::string message = errorMessage([&] { writeImage(path, 2, 1, rgb); });
    CHECK(contains(message, path.string()));
    CHECK(contains(message, ".exr"));
    CHECK(contains(message, ".png"));
    CHECK_FALSE(std::filesystem::exists(path));
  }
  SUBCASE("size mismatch and unwritable destinations") {
    for (const char* name : {"short.exr", "short.png"}) {
      const auto path = dir.file(name);
      CHECK(contains(errorMessage([&] { writeImage(path, 3, 1, rgb); }), path.string()));
      CHECK(contains(errorMessage([&] { writeImage(path, 0, 1, {}); }), path.string()));
    }
    for (const char* name : {"no/such/dir/out.exr", "no/such/dir/out.png"}) {
      const auto path = dir.file(name);
      const std::string message = errorMessage([&] { writeImage(path, 2, 1, rgb); });
      CHECK(contains(message, path.string()));
      CHECK_FALSE(contains(message, "<"));
    }
  }
}

TEST_CASE("display: the automatic exposure keys the object's log-average luminance to 0.18") {
  // Grey pixels of 0.09 and 0.36 (Y = value): log-average 0.18, so 0 EV; a uniform 0.09 needs +1 EV.
  const std::vector<float> twoGreys = {0.09f, 0.09f, 0.09f, 0.36f, 0.36f, 0.36f};
  CHECK(autoExposureEV(twoGreys, {}) == doctest::Approx(0.0).epsilon(1e-6));
  CHECK(autoExposureEV(std::vector<float>(6, 0.09f), {}) == doctest::Approx(1.0).epsilon(1e-6));
  // Rec. 709 weights: pure green of 0.18 / 0.7152 has Y = 0.18.
  CHECK(autoExposureEV(std::vector<float>{0.0f, 0.18f / 0.7152f, 0.0f}, {}) ==
        doctest::Approx(0.0).epsilon(1e-6));
  // Background pixels (mask 0), black and non-finite pixels are left out.
  const std::vector<float> mixed = {0.09f,   0.09f, 0.09f, 1000.0f, 1000.0f,
                                    1000.0f, 0.0f,  0.0f,  0.0f,    std::numeric_limits<float>::quiet_NaN(),
                                    0.0f,    0.0f};
  const std::vector<std::uint8_t> mask = {1, 0, 1, 1};
  CHECK(autoExposureEV(mixed, mask) == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(autoExposureEV(std::vector<float>(6, 0.0f), {}) == 0.0);     // nothing lit: no change
  CHECK(autoExposureEV(std::vector<float>(3, 1e-30f), {}) == 32.0);  // clamped

  const DisplaySettings automatic{.exposureEV = -0.5};
  const DisplayTransform resolved = resolveDisplay(automatic, std::vector<float>(6, 0.09f), {});
  CHECK(resolved.exposureEV == doctest::Approx(0.5).epsilon(1e-6));  // +1 automatic, -0.5 compensation
  CHECK(resolved.tonemap == Tonemap::Aces);                          // the default curve
  const DisplaySettings manual{
      .autoExposure = false, .exposureEV = 2.0, .tonemap = Tonemap::Clamp, .gamma = 2.2};
  const DisplayTransform fixed = resolveDisplay(manual, std::vector<float>(6, 0.09f), {});
  CHECK(fixed.exposureEV == 2.0);
  CHECK(fixed.gamma == 2.2);
  // The default scene's problem: a sphere lit by a 1e4 sun beside a sky of 1 has pixels far above 1; the
  // automatic exposure brings its typical pixel to mid grey, so the default curve does not clip it white.
  std::vector<float> lit(3 * 100);
  for (std::size_t p = 0; p < 100; ++p) lit[3 * p] = lit[3 * p + 1] = lit[3 * p + 2] = float(20.0 + p);
  const DisplayTransform t = resolveDisplay(DisplaySettings{}, lit, {});
  CHECK(toDisplayByte(lit[3 * 50], t) < 200);
  CHECK(toDisplayByte(lit[3 * 50], DisplayTransform{}) == 255);  // exposure 0, clamp: white
}
