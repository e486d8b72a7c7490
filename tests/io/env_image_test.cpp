// Tests of loadEnvImage and sanitize: EXR and .hdr decoding, sanitation warnings, and every failure mode a
// user's file can trigger (each must throw iblx::Error naming the file, never crash or return a partly black
// map).
#include "engine/io/env_image.h"
#include "engine/io/image_write.h"
#include "tests/io/exr_encoder.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace iblx;
using namespace iblx::test;

namespace {

// Deterministic test pattern with a wide dynamic range: values far above half's 65504 and far below its
// smallest normal, so that any conversion through half would show.
std::vector<float> wideRangePattern(int width, int height) {
  std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const double t = double((i * 2654435761u) % 1000) / 999.0;  // scrambled in [0, 1]
    rgb[i] = float(std::exp2(-30.0 + 50.0 * t)) * (1.0f + float(i % 7) / 7.0f);
  }
  rgb[0] = 0.0f;
  return rgb;
}

bool bitwiseEqual(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void checkErrorNamesFile(const std::filesystem::path& path, const std::string& message) {
  INFO("message: " << message);
  CHECK(contains(message, path.string()));
  CHECK_FALSE(
      contains(message, "<"));  // the markers errorMessage uses for "not an iblx::Error" or "no exception"
}

}  // namespace

TEST_CASE("loadEnvImage: EXR float write -> read round trip is exact") {
  ScratchDir dir;
  WarningCapture warnings;  // non-2:1 sizes warn; that is tested elsewhere
  const struct { int width, height; } sizes[] = {{16, 8}, {5, 3}, {7, 1}, {2, 1}};
  for (const auto& size : sizes) {
    CAPTURE(size.width);
    CAPTURE(size.height);
    const auto path =
        dir.file("round_trip_" + std::to_string(size.width) + "x" + std::to_string(size.height) + ".exr");
    const std::vector<float> rgb = wideRangePattern(size.width, size.height);
    writeExr(path, size.width, size.height, rgb);
    const EnvImage image = loadEnvImage(path);
    CHECK(image.width == size.width);
    CHECK(image.height == size.height);
    CHECK(bitwiseEqual(image.rgb, rgb));
  }
}

TEST_CASE("loadEnvImage: half-float RGBA EXR loads R, G, B and ignores A") {
  ScratchDir dir;
  const int width = 4, height = 2;
  const std::vector<float> r = {0.0f, 0.5f, 1.0f, 2.0f, 1024.0f, 65504.0f, 0.125f, 3.0f};
  const std::vector<float> g = {1.0f, 0.25f, 0.75f, 6.0f, 0.0625f, 7.0f, 100.0f, 1.5f};
  const std::vector<float> b = {2.0f, 4.0f, 8.0f, 16.0f, 32.0f, 64.0f, 128.0f, 256.0f};
  const std::vector<float> a(8, 0.5f);
  const auto path = dir.file("half_rgba.exr");
  writeBytes(path, ExrEncoder().encode(0, 0, width, height,
                                       {{"R", ExrPixelType::Half, r},
                                        {"G", ExrPixelType::Half, g},
                                        {"B", ExrPixelType::Half, b},
                                        {"A", ExrPixelType::Half, a}}));
  WarningCapture warnings;
  const EnvImage image = loadEnvImage(path);
  CHECK(warnings.messages.empty());
  REQUIRE(image.width == width);
  REQUIRE(image.height == height);
  for (std::size_t i = 0; i < r.size(); ++i) {
    CAPTURE(i);
    CHECK(image.rgb[3 * i + 0] == r[i]);
    CHECK(image.rgb[3 * i + 1] == g[i]);
    CHECK(image.rgb[3 * i + 2] == b[i]);
  }
}

TEST_CASE("loadEnvImage: luminance-only (Y) EXR is replicated to R, G, B") {
  ScratchDir dir;
  const std::vector<float> y = {0.0f, 0.5f, 1.0f, 3.25f, 1.0e6f, 1.0e-6f, 7.0f, 42.0f};
  const auto path = dir.file("luminance.exr");
  writeBytes(path, ExrEncoder().encode(0, 0, 4, 2, {{"Y", ExrPixelType::Float, y}}));
  const EnvImage image = loadEnvImage(path);
  REQUIRE(image.texelCount() == y.size());
  for (std::size_t i = 0; i < y.size(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(image.rgb[3 * i + std::size_t(c)] == y[i]);
}

TEST_CASE("loadEnvImage: luminance/chroma (Y, RY, BY) EXR goes through OpenEXR's YCA conversion") {
  ScratchDir dir;
  // Grey pixels (zero chroma) must come back with R = G = B = Y.
  const int width = 8, height = 4;
  std::vector<float> y(std::size_t(width * height));
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = float(1 + i % 5) * 0.25f;
  const std::vector<float> chroma(std::size_t(width / 2 * height / 2), 0.0f);
  const auto path = dir.file("yc.exr");
  writeBytes(path, ExrEncoder().encode(0, 0, width, height,
                                       {{"Y", ExrPixelType::Half, y},
                                        {"RY", ExrPixelType::Half, chroma, 2, 2},
                                        {"BY", ExrPixelType::Half, chroma, 2, 2}}));
  const EnvImage image = loadEnvImage(path);
  REQUIRE(image.texelCount() == y.size());
  for (std::size_t i = 0; i < y.size(); ++i)
    for (int c = 0; c < 3; ++c)
      CHECK(image.rgb[3 * i + std::size_t(c)] == doctest::Approx(y[i]).epsilon(1e-3));
}

TEST_CASE("loadEnvImage: EXR data window that does not start at 0, and UINT channels") {
  ScratchDir dir;
  const int width = 4, height = 2;
  std::vector<float> r(8), g(8), b(8);
  for (std::size_t i = 0; i < 8; ++i) {
    r[i] = float(i);
    g[i] = float(10 * i);
    b[i] = float(100 * i);
  }
  SUBCASE("negative origin, float channels") {
    const auto path = dir.file("offset_negative.exr");
    writeBytes(path, ExrEncoder().encode(-3, -7, width, height,
                                         {{"R", ExrPixelType::Float, r},
                                          {"G", ExrPixelType::Float, g},
                                          {"B", ExrPixelType::Float, b}}));
    const EnvImage image = loadEnvImage(path);
    REQUIRE(image.width == width);
    REQUIRE(image.height == height);
    for (std::size_t i = 0; i < 8; ++i) {
      CHECK(image.rgb[3 * i + 0] == r[i]);
      CHECK(image.rgb[3 * i + 1] == g[i]);
      CHECK(image.rgb[3 * i + 2] == b[i]);
    }
  }
  SUBCASE("positive origin, uint channels") {
    const auto path = dir.file("offset_uint.exr");
    writeBytes(path, ExrEncoder().encode(100, 20, width, height,
                                         {{"R", ExrPixelType::Uint, r},
                                          {"G", ExrPixelType::Uint, g},
                                          {"B", ExrPixelType::Uint, b}}));
    const EnvImage image = loadEnvImage(path);
    REQUIRE(image.texelCount() == 8);
    for (std::size_t i = 0; i < 8; ++i) {
      CHECK(image.rgb[3 * i + 0] == r[i]);
      CHECK(image.rgb[3 * i + 2] == b[i]);
    }
  }
}

TEST_CASE("loadEnvImage: EXR without R, G, B or Y lists the channels it has") {
  ScratchDir dir;
  const auto path = dir.file("no_rgb.exr");
  const std::vector<float> v(8, 1.0f);
  writeBytes(path,
             ExrEncoder().encode(0, 0, 4, 2, {{"R", ExrPixelType::Half, v}, {"Z", ExrPixelType::Float, v}}));
  const std::string message = errorMessage([&] { loadEnvImage(path); });
  checkErrorNamesFile(path, message);
  CHECK(contains(message, "R, Z"));
}

TEST_CASE("loadEnvImage: NaN, Inf and negative texels are fixed with exactly one counting warning") {
  ScratchDir dir;
  const int width = 8, height = 4;
  std::vector<float> rgb(3 * width * height, 0.25f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  rgb[0] = nan;
  rgb[10] = nan;
  rgb[20] = inf;
  rgb[21] = inf;
  rgb[30] = -inf;
  rgb[40] = -1.0f;
  rgb[41] = -1.0e-20f;
  rgb[42] = -3.0e10f;
  rgb[43] = -0.5f;
  rgb[50] = 7.5f;  // the largest finite value: +Inf becomes this
  const auto path = dir.file("dirty.exr");
  writeExr(path, width, height, rgb);

  WarningCapture warnings;
  const EnvImage image = loadEnvImage(path);
  REQUIRE(warnings.messages.size() == 1);
  const std::string& warning = warnings.messages[0];
  INFO(warning);
  CHECK(contains(warning, path.string()));
  CHECK(contains(warning, "replaced 2 NaN, 3 Inf and 4 negative texel values"));

  CHECK(image.rgb[0] == 0.0f);
  CHECK(image.rgb[10] == 0.0f);
  CHECK(image.rgb[20] == 7.5f);
  CHECK(image.rgb[21] == 7.5f);
  CHECK(image.rgb[30] == 0.0f);
  for (std::size_t i : {40, 41, 42, 43}) CHECK(image.rgb[i] == 0.0f);
  CHECK(image.rgb[50] == 7.5f);
  CHECK(image.rgb[1] == 0.25f);
  for (float v : image.rgb) CHECK((std::isfinite(v) && v >= 0.0f));
}

TEST_CASE("sanitize: edge cases") {
  const float inf = std::numeric_limits<float>::infinity();
  SUBCASE("+Inf with no finite value becomes 0") {
    EnvImage image{2, 1, {inf, inf, inf, -inf, inf, -5.0f}};
    const SanitizeReport report = sanitize(image);
    CHECK(report.infCount == 5);
    CHECK(report.negativeCount == 1);
    CHECK(report.total() == 6);
    for (float v : image.rgb) CHECK(v == 0.0f);
  }
  SUBCASE("a clean image is untouched and -0 becomes +0 without being counted") {
    EnvImage image{2, 1, {0.0f, -0.0f, 1.0f, 2.0f, 3.0f, 4.0f}};
    const SanitizeReport report = sanitize(image);
    CHECK(report.total() == 0);
    CHECK_FALSE(std::signbit(image.rgb[1]));
    CHECK(image.rgb[5] == 4.0f);
  }
}

TEST_CASE("loadEnvImage: image shape rules") {
  ScratchDir dir;
  SUBCASE("a non-2:1 map loads with one warning") {
    const auto path = dir.file("square.exr");
    writeExr(path, 4, 4, std::vector<float>(48, 1.0f));
    WarningCapture warnings;
    CHECK(loadEnvImage(path).width == 4);
    REQUIRE(warnings.messages.size() == 1);
    CHECK(contains(warnings.messages[0], path.string()));
    CHECK(contains(warnings.messages[0], "2:1"));
  }
  SUBCASE("a 1-pixel-wide map is rejected") {
    const auto path = dir.file("narrow.exr");
    writeExr(path, 1, 1, std::vector<float>(3, 1.0f));
    checkErrorNamesFile(path, errorMessage([&] { loadEnvImage(path); }));
  }
}

TEST_CASE("loadEnvImage: extensions are case-insensitive") {
  ScratchDir dir;
  WarningCapture warnings;
  const auto exr = dir.file("UPPER.EXR");
  writeExr(exr, 2, 1, std::vector<float>{1, 2, 3, 4, 5, 6});
  CHECK(loadEnvImage(exr).rgb[5] == 6.0f);
  const auto hdr = dir.file("Upper.Hdr");
  const std::vector<float> rgb = {1, 2, 3, 4, 5, 6};
  REQUIRE(stbi_write_hdr(hdr.string().c_str(), 2, 1, 3, rgb.data()));
  CHECK(loadEnvImage(hdr).rgb[5] == 6.0f);
}

// -----------------------------------------------------------------------------------------------------------
// Radiance .hdr

namespace {

// Width >= 8 makes stb write new-style RLE scanlines; a constant stretch makes it emit runs, not only
// literals.
std::vector<float> hdrPattern(int width, int height) {
  std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x)) + std::size_t(c);
        // Exponents from -8 to 40: wide, and below loadEnvImage's limit of 1e15 (2^49.8).
        rgb[i] = x >= width / 2
                     ? 0.75f
                     : float(std::exp2(-8.0 + std::fmod(0.37 * (x + 3 * y + 5 * c), 48.0) - 0.9 * c));
      }
  rgb[3] = rgb[4] = rgb[5] = 0.0f;
  return rgb;
}

// RGBE keeps 8 mantissa bits for the largest component of a pixel; writers truncate, so every component is
// within one unit of that mantissa: max(r, g, b) / 128.
void checkWithinRgbePrecision(const std::vector<float>& expected, const std::vector<float>& actual) {
  REQUIRE(expected.size() == actual.size());
  for (std::size_t p = 0; p < expected.size() / 3; ++p) {
    const float largest = std::max({expected[3 * p], expected[3 * p + 1], expected[3 * p + 2]});
    for (std::size_t c = 0; c < 3; ++c) {
      CAPTURE(p);
      CAPTURE(c);
      CHECK(std::abs(actual[3 * p + c] - expected[3 * p + c]) <= largest / 128.0f);
      CHECK(actual[3 * p + c] <= expected[3 * p + c]);
    }
  }
}

std::vector<unsigned char> hdrBytes(const std::string& header, const std::vector<unsigned char>& pixels) {
  std::vector<unsigned char> bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), pixels.begin(), pixels.end());
  return bytes;
}

}  // namespace

TEST_CASE("loadEnvImage: .hdr written by stb reads back within RGBE precision, identical to stbi_loadf") {
  ScratchDir dir;
  WarningCapture warnings;
  const struct {
    int width, height;
  } sizes[] = {{32, 16}, {5, 3}, {300, 2}};  // RLE, flat (width < 8), RLE with literals longer than 128
  for (const auto& size : sizes) {
    CAPTURE(size.width);
    const auto path = dir.file("stb_" + std::to_string(size.width) + ".hdr");
    const std::vector<float> rgb = hdrPattern(size.width, size.height);
    REQUIRE(stbi_write_hdr(path.string().c_str(), size.width, size.height, 3, rgb.data()));
    const EnvImage image = loadEnvImage(path);
    REQUIRE(image.width == size.width);
    REQUIRE(image.height == size.height);
    checkWithinRgbePrecision(rgb, image.rgb);
    CHECK(image.rgb[3] == 0.0f);  // exact zeros stay zero

    // stb's decoder is trusted on complete files; ours must agree bit for bit.
    int w = 0, h = 0, channels = 0;
    float* reference = stbi_loadf(path.string().c_str(), &w, &h, &channels, 3);
    REQUIRE(reference != nullptr);
    CHECK(bitwiseEqual(image.rgb, std::vector<float>(reference, reference + 3 * w * h)));
    stbi_image_free(reference);
  }
}

TEST_CASE("loadEnvImage: .hdr orientations and header variants") {
  ScratchDir dir;
  WarningCapture warnings;
  // Two rows of three flat pixels: mantissas (x+1)*16 + y in red, exponent 129 (scale 2^-7).
  std::vector<unsigned char> pixels;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      pixels.insert(pixels.end(), {static_cast<unsigned char>((x + 1) * 16 + y), 0, 0, 129});
  const auto red = [](const EnvImage& image, int x, int y) {
    return image.rgb[3 * image.index(x, y)] * 128.0f;
  };

  SUBCASE("standard -Y +X, with comments, EXPOSURE and a #?RGBE signature") {
    const auto path = dir.file("standard.hdr");
    writeBytes(path,
               hdrBytes("#?RGBE\n# a comment\nEXPOSURE=2.0\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 3\n", pixels));
    const EnvImage image = loadEnvImage(path);
    CHECK(red(image, 0, 0) == 16.0f);
    CHECK(red(image, 2, 1) == 49.0f);
  }
  SUBCASE("+Y is bottom-up") {
    const auto path = dir.file("bottom_up.hdr");
    writeBytes(path, hdrBytes("#?RADIANCE\n\n+Y 2 +X 3\n", pixels));
    const EnvImage image = loadEnvImage(path);
    CHECK(red(image, 0, 0) == 17.0f);
    CHECK(red(image, 0, 1) == 16.0f);
  }
  SUBCASE("-X is right-to-left") {
    const auto path = dir.file("mirrored.hdr");
    writeBytes(path, hdrBytes("#?RADIANCE\n\n-Y 2 -X 3\n", pixels));
    const EnvImage image = loadEnvImage(path);
    CHECK(red(image, 0, 0) == 48.0f);
    CHECK(red(image, 2, 0) == 16.0f);
  }
  SUBCASE("unsupported variants are errors naming the file") {
    const struct {
      const char* name;
      std::string header;
      const char* expected;
    } cases[] = {
        {"transposed.hdr", "#?RADIANCE\n\n+X 3 -Y 2\n", "column-major"},
        {"xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 3\n", "xyze"},
        {"no_signature.hdr", "RADIANCE\n\n-Y 2 +X 3\n", "#?"},
        {"bad_resolution.hdr", "#?RADIANCE\n\n-Y two +X 3\n", "resolution"},
        {"zero_size.hdr", "#?RADIANCE\n\n-Y 0 +X 3\n", "size"},
        {"no_header_end.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", "header"},
    };
    for (const auto& c : cases) {
      CAPTURE(c.name);
      const auto path = dir.file(c.name);
      writeBytes(path, hdrBytes(c.header, pixels));
      const std::string message = errorMessage([&] { loadEnvImage(path); });
      checkErrorNamesFile(path, message);
      CHECK(contains(message, c.expected));
    }
  }
  SUBCASE("old-style RLE repeat markers are reported, not decoded") {
    std::vector<unsigned char> old = pixels;
    old[4] = old[5] = old[6] = 1;
    const auto path = dir.file("old_rle.hdr");
    writeBytes(path, hdrBytes("#?RADIANCE\n\n-Y 2 +X 3\n", old));
    checkErrorNamesFile(path, errorMessage([&] { loadEnvImage(path); }));
  }
}

TEST_CASE("loadEnvImage: corrupt RLE data in .hdr is detected") {
  ScratchDir dir;
  // One 8-pixel RLE scanline whose red run is longer than the scanline.
  const std::vector<unsigned char> scanline = {2, 2, 0, 8, 128 + 9, 200};
  const auto path = dir.file("overrun.hdr");
  writeBytes(path, hdrBytes("#?RADIANCE\n\n-Y 1 +X 8\n", scanline));
  const std::string message = errorMessage([&] { loadEnvImage(path); });
  checkErrorNamesFile(path, message);
}

// -----------------------------------------------------------------------------------------------------------
// Failure modes shared by both formats

TEST_CASE("loadEnvImage: missing file, unknown extension, directory, empty file") {
  ScratchDir dir;
  SUBCASE("missing file") {
    for (const char* name : {"missing.exr", "missing.hdr"}) {
      const auto path = dir.file(name);
      const std::string message = errorMessage([&] { loadEnvImage(path); });
      checkErrorNamesFile(path, message);
      CHECK(contains(message, "cannot open"));
    }
  }
  SUBCASE("unknown extension lists the supported formats") {
    for (const char* name : {"map.png", "map", "map.exr.gz"}) {
      const auto path = dir.file(name);
      writeBytes(path, {1, 2, 3});
      const std::string message = errorMessage([&] { loadEnvImage(path); });
      checkErrorNamesFile(path, message);
      CHECK(contains(message, ".exr"));
      CHECK(contains(message, ".hdr"));
    }
  }
  SUBCASE("a directory") {
    const auto path = dir.file("folder.exr");
    std::filesystem::create_directory(path);
    const std::string message = errorMessage([&] { loadEnvImage(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "cannot open"));
  }
  SUBCASE("empty files") {
    for (const char* name : {"empty.exr", "empty.hdr"}) {
      const auto path = dir.file(name);
      writeBytes(path, {});
      checkErrorNamesFile(path, errorMessage([&] { loadEnvImage(path); }));
    }
  }
}

TEST_CASE("loadEnvImage: random bytes named .exr or .hdr are rejected") {
  ScratchDir dir;
  // Plain noise, then noise behind each format's signature so that the decoders get past their first check.
  const std::vector<unsigned char> exrMagic = {0x76, 0x2f, 0x31, 0x01, 0x02, 0x00, 0x00, 0x00};
  const std::string hdrSignature = "#?RADIANCE\n";
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    CAPTURE(seed);
    for (const char* ext : {".exr", ".hdr"}) {
      const bool exr = std::string(ext) == ".exr";
      std::vector<unsigned char> bytes = randomBytes(64 + 97 * seed, seed);
      if (seed > 10) {
        const std::vector<unsigned char> prefix =
            exr ? exrMagic : std::vector<unsigned char>(hdrSignature.begin(), hdrSignature.end());
        bytes.insert(bytes.begin(), prefix.begin(), prefix.end());
      }
      const auto path = dir.file("random_" + std::to_string(seed) + ext);
      writeBytes(path, bytes);
      checkErrorNamesFile(path, errorMessage([&] { loadEnvImage(path); }));
    }
  }
}

TEST_CASE("loadEnvImage: truncated EXR files are detected, never read as partly black") {
  ScratchDir dir;
  WarningCapture warnings;
  const int width = 64, height = 32;
  const std::vector<float> rgb = wideRangePattern(width, height);
  SUBCASE("ZIP EXR from writeExr, cut in half") {
    const auto full = dir.file("full.exr");
    writeExr(full, width, height, rgb);
    std::vector<unsigned char> bytes = readBytes(full);
    bytes.resize(bytes.size() / 2);
    const auto path = dir.file("half.exr");
    writeBytes(path, bytes);
    const std::string message = errorMessage([&] { loadEnvImage(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "truncated"));
  }
  SUBCASE("every cut point of an uncompressed and of a ZIP file") {
    std::vector<float> r(std::size_t(width * height)), g = r, b = r;
    for (std::size_t i = 0; i < r.size(); ++i) {
      r[i] = rgb[3 * i];
      g[i] = rgb[3 * i + 1];
      b[i] = rgb[3 * i + 2];
    }
    const auto zip = dir.file("zip.exr");
    writeExr(zip, width, height, rgb);
    const std::vector<std::vector<unsigned char>> files = {
        readBytes(zip),
        ExrEncoder().encode(
            0, 0, width, height,
            {{"R", ExrPixelType::Float, r}, {"G", ExrPixelType::Float, g}, {"B", ExrPixelType::Float, b}})};
    for (const auto& bytes : files) {
      const auto path = dir.file("cut.exr");
      writeBytes(path, bytes);
      REQUIRE(bitwiseEqual(loadEnvImage(path).rgb, rgb));  // the intact file is valid
      // Cut everywhere in the header and the offset table, then at many points in the pixel data.
      const std::size_t step = std::max<std::size_t>(1, bytes.size() / 300);
      for (std::size_t size = 1; size < bytes.size(); size += size < 600 ? 1 : step) {
        CAPTURE(size);
        writeBytes(path, std::vector<unsigned char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(size)));
        const std::string message = errorMessage([&] { loadEnvImage(path); });
        checkErrorNamesFile(path, message);
      }
    }
  }
}

TEST_CASE("loadEnvImage: an EXR whose writer never finished its offset table is rejected") {
  ScratchDir dir;
  const int width = 8, height = 4;
  const std::vector<float> v(std::size_t(width * height), 1.5f);
  ExrEncoder encoder;
  std::vector<unsigned char> bytes = encoder.encode(
      0, 0, width, height,
      {{"R", ExrPixelType::Float, v}, {"G", ExrPixelType::Float, v}, {"B", ExrPixelType::Float, v}});
  // OpenEXR writes the table as zeros first and fills it in when the file is closed.
  std::fill_n(bytes.begin() + std::ptrdiff_t(encoder.offsetTableStart()), 8 * height, 0);
  const auto complete = dir.file("unfinished.exr");
  writeBytes(complete, bytes);
  const std::string message = errorMessage([&] { loadEnvImage(complete); });
  checkErrorNamesFile(complete, message);
  CHECK(contains(message, "incomplete"));
  const auto cut = dir.file("unfinished_cut.exr");
  writeBytes(cut,
             std::vector<unsigned char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(bytes.size() / 2)));
  checkErrorNamesFile(cut, errorMessage([&] { loadEnvImage(cut); }));
}

TEST_CASE("loadEnvImage: truncated .hdr files are detected at every cut point") {
  ScratchDir dir;
  WarningCapture warnings;
  // RLE (width 32) and flat (width 6) files: stb_image returns zero-filled rows for the flat one and never
  // returns for the RLE one, which is why the loader decodes .hdr itself.
  for (int width : {32, 6}) {
    CAPTURE(width);
    const int height = 8;
    const auto full = dir.file("full.hdr");
    const std::vector<float> rgb = hdrPattern(width, height);
    REQUIRE(stbi_write_hdr(full.string().c_str(), width, height, 3, rgb.data()));
    const std::vector<unsigned char> bytes = readBytes(full);
    const auto path = dir.file("cut.hdr");
    for (std::size_t size = 0; size < bytes.size(); ++size) {
      CAPTURE(size);
      writeBytes(path, std::vector<unsigned char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(size)));
      checkErrorNamesFile(path, errorMessage([&] { loadEnvImage(path); }));
    }
  }
}

TEST_CASE("loadEnvImage: hostile maps: values beyond the limit, FIFOs, CR header lines, the memory budget") {
  ScratchDir dir;
  WarningCapture warnings;
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
  SUBCASE("a texel above 1e15 is refused naming the file and the texel; 1e15 itself loads") {
    std::vector<float> rgb(3 * 4 * 2, 1.0f);
    rgb[3 * 5 + 1] = 1e38f;  // texel (1, 1)
    const auto path = dir.file("hot.exr");
    writeExr(path, 4, 2, rgb);
    const std::string message = errorMessage([&] { loadEnvImage(path); });
    checkErrorNamesFile(path, message);
    CHECK(contains(message, "texel (1, 1) holds 1e+38, above the largest radiance iblx accepts (1e15)"));
    rgb[3 * 5 + 1] = 1e15f;
    writeExr(path, 4, 2, rgb);
    CHECK(loadEnvImage(path).rgb[3 * 5 + 1] == 1e15f);
  }
  SUBCASE("a legal RGBE exponent of 255 is refused the same way") {
    const auto path = dir.file("e255.hdr");
    writeBytes(path, hdrBytes(header, {128, 128, 128, 255, 128, 128, 128, 128}));
    CHECK(contains(errorMessage([&] { loadEnvImage(path); }), "e255.hdr: texel (0, 0) holds 8.51e+37"));
  }
  SUBCASE("header lines ending in CR LF are read") {
    const auto path = dir.file("crlf.hdr");
    writeBytes(path, hdrBytes("#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 1 +X 2\r\n",
                              {128, 128, 128, 128, 128, 0, 0, 129}));
    const EnvImage image = loadEnvImage(path);
    REQUIRE(image.width == 2);
    CHECK(image.rgb[0] == 0.5f);
    CHECK(image.rgb[3] == 1.0f);
  }
  SUBCASE("a FIFO is refused without blocking") {
    const auto path = dir.file("pipe.exr");
    REQUIRE(::mkfifo(path.c_str(), 0600) == 0);
    CHECK(contains(errorMessage([&] { loadEnvImage(path); }), "pipe.exr: it is a FIFO"));
  }
  SUBCASE("an image over the memory budget is refused before its pixels are allocated") {
    const auto exr = dir.file("big.exr"), hdr = dir.file("big.hdr");
    writeExr(exr, 256, 128, std::vector<float>(3 * 256 * 128, 1.0f));
    REQUIRE(
        stbi_write_hdr(hdr.string().c_str(), 256, 128, 3, std::vector<float>(3 * 256 * 128, 1.0f).data()));
    ::setenv("IBLX_MEMORY_BUDGET_GIB", "0.0001", 1);  // 105 KiB; the image needs 384 KiB
    const std::string exrMessage = errorMessage([&] { loadEnvImage(exr); });
    const std::string hdrMessage = errorMessage([&] { loadEnvImage(hdr); });
    ::unsetenv("IBLX_MEMORY_BUDGET_GIB");
    CHECK(contains(exrMessage, "big.exr: the 256x128 image needs 384 KiB, over iblx's memory budget"));
    CHECK(contains(hdrMessage, "big.hdr: the 256x128 image needs 384 KiB, over iblx's memory budget"));
    CHECK(loadEnvImage(exr).width == 256);
  }
}

TEST_CASE("loadEnvImage: a large EXR is read in stripes, every row in its place") {
  ScratchDir dir;
  // 2048 wide: 170 rows per 4 MiB stripe, so 400 rows take three stripes, the last one partial.
  const int width = 2048, height = 400;
  std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(i % 9973) + 0.25f * float(i / (3 * width));
  const auto path = dir.file("striped.exr");
  writeExr(path, width, height, rgb);
  CHECK(bitwiseEqual(loadEnvImage(path).rgb, rgb));
}

TEST_CASE(
    "loadEnvImage: an EXR header attribute claiming more than the file holds is refused before it is read") {
  ScratchDir dir;
  // Magic, version 2 (single part), then one attribute "comments" of type "string" claiming 2^31 - 1 bytes:
  // OpenEXR alone allocates that much before finding the file short.
  std::vector<unsigned char> bytes = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
  for (const char* text : {"comments", "string"})
    bytes.insert(bytes.end(), text, text + std::strlen(text) + 1);
  bytes.insert(bytes.end(), {0xff, 0xff, 0xff, 0x7f, 'a', 'b', 'c', 0});
  const auto path = dir.file("claims.exr");
  writeBytes(path, bytes);
  const std::string message = errorMessage([&] { loadEnvImage(path); });
  checkErrorNamesFile(path, message);
  CHECK(contains(message, "header attribute 'comments' claims 2147483647 bytes, more than the file holds"));
}
