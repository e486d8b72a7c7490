// The fuzz targets that need no GPU and no glslang: EXR and Radiance .hdr environment maps, MERL .binary,
// BRDF Explorer .brdf/.bparam, OBJ meshes, and the OT map, ground-truth and SPIR-V cache files. Each target's
// seeds are written by the project's own writers (or laid out byte by byte where the project has none).
#include "tests/fuzz/cpu_targets.h"

#include "engine/core/cache_file.h"
#include "engine/core/error.h"
#include "engine/geometry/obj_file.h"
#include "engine/io/alta_func.h"
#include "engine/io/alta_func_eval.h"

#include "engine/io/brdf_file.h"
#include "engine/io/env_image.h"
#include "engine/io/image_write.h"
#include "engine/io/merl.h"
#include "engine/io/alta_data.h"
#include "engine/io/mit_brdf.h"
#include "engine/io/rgl_bsdf.h"
#include "engine/sampling/brdf/alta_grid.h"
#include "engine/sampling/brdf/rgl_sampling.h"
#include "engine/io/utia.h"
#include "engine/io/reference_cache.h"
#include "engine/ot/cache.h"
#include "tests/io/exr_encoder.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>

namespace iblx::fuzz {

namespace {

Bytes textBytes(std::string_view text) {
  return Bytes(text.begin(), text.end());
}

Bytes fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Bytes withPrefix(std::initializer_list<std::uint8_t> prefix, const Bytes& rest) {
  Bytes out(prefix);
  out.insert(out.end(), rest.begin(), rest.end());
  return out;
}

// A small image with a gradient, a bright texel, a zero and (where asked) a NaN and a negative value, so the
// seeds reach the loaders' sanitation as well as their parsing.
std::vector<float> testImage(int width, int height, bool withSpecials) {
  std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.25f * float(i % 7) + 0.5f;
  rgb[0] = 0.0f;
  rgb[3] = 1024.0f;
  if (withSpecials) {
    rgb[4] = std::numeric_limits<float>::quiet_NaN();
    rgb[5] = -2.0f;
  }
  return rgb;
}

// ---- EXR ------------------------------------------------------------------------------------------------

void runExr(std::span<const std::uint8_t> input) {
  loadEnvImage(writeScratchFile("input.exr", input));
}

std::vector<Bytes> exrSeeds() {
  std::vector<Bytes> seeds;
  // OpenEXR's own writer (ZIP compression, float RGB), as the project writes its outputs.
  const auto zipped = scratchDirectory() / "seed.exr";
  writeExr(zipped, 8, 4, testImage(8, 4, true));
  seeds.push_back(fileBytes(zipped));
  // Uncompressed files laid out byte by byte: half RGBA, float luminance, uint RGB with an offset window.
  using test::ExrChannelData, test::ExrEncoder, test::ExrPixelType;
  const std::vector<float> halves = {0.0f, 0.5f, 1.0f, 2.0f, 4.0f, 8.0f, 0.25f, 16.0f};
  seeds.push_back(ExrEncoder().encode(0, 0, 4, 2,
                                      {{"R", ExrPixelType::Half, halves},
                                       {"G", ExrPixelType::Half, halves},
                                       {"B", ExrPixelType::Half, halves},
                                       {"A", ExrPixelType::Half, halves}}));
  seeds.push_back(ExrEncoder().encode(0, 0, 4, 2, {{"Y", ExrPixelType::Float, halves}}));
  const std::vector<float> counts = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  seeds.push_back(ExrEncoder().encode(3, -2, 4, 3,
                                      {{"R", ExrPixelType::Uint, counts},
                                       {"G", ExrPixelType::Uint, counts},
                                       {"B", ExrPixelType::Uint, counts}}));
  return seeds;
}

// ---- Radiance .hdr --------------------------------------------------------------------------------------

void runHdr(std::span<const std::uint8_t> input) {
  loadEnvImage(writeScratchFile("input.hdr", input));
}

Bytes hdrHeader(int width, int height) {
  return textBytes(
      "#?RADIANCE\n# written for iblx's fuzz corpus\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y " +
      std::to_string(height) + " +X " + std::to_string(width) + "\n");
}

std::array<std::uint8_t, 4> rgbe(float r, float g, float b) {
  const float largest = std::max({r, g, b});
  if (largest < 1e-32f) return {0, 0, 0, 0};
  int exponent = 0;
  const float scale = std::frexp(largest, &exponent) * 256.0f / largest;
  return {std::uint8_t(r * scale), std::uint8_t(g * scale), std::uint8_t(b * scale),
          std::uint8_t(exponent + 128)};
}

std::vector<Bytes> hdrSeeds() {
  std::vector<Bytes> seeds;
  // Flat RGBE scanlines (width < 8: no run-length encoding).
  {
    Bytes file = hdrHeader(4, 3);
    for (int i = 0; i < 12; ++i) {
      const auto texel = rgbe(0.1f * float(i), 0.5f, float(i % 3));
      file.insert(file.end(), texel.begin(), texel.end());
    }
    seeds.push_back(file);
  }
  // The run-length encoded layout: per scanline 2, 2, width (16 bits), then each channel as runs (a count
  // above 128 repeats one byte count - 128 times) and literal stretches (count <= 128).
  {
    const int width = 16, height = 2;
    Bytes file = hdrHeader(width, height);
    for (int y = 0; y < height; ++y) {
      file.insert(file.end(), {2, 2, std::uint8_t(width >> 8), std::uint8_t(width & 0xff)});
      for (int c = 0; c < 4; ++c) {
        file.insert(file.end(), {std::uint8_t(128 + 8), std::uint8_t(c == 3 ? 129 : 40 + 10 * c)});
        file.push_back(8);
        for (int x = 0; x < 8; ++x) file.push_back(std::uint8_t(c == 3 ? 130 : 16 * x + y));
      }
    }
    seeds.push_back(file);
  }
  return seeds;
}

// ---- MERL .binary ---------------------------------------------------------------------------------------

// Input byte 0 selects the layout: 1 expands the input to a full-size file (bytes 1-12 the header, the rest
// repeated to fill the 3 x 1,458,000 doubles), so mutations reach the value checks; anything else writes the
// rest as it is, which mostly meets the header and size checks.
void runMerl(std::span<const std::uint8_t> input) {
  if (!input.empty() && input[0] == 1 && input.size() > 13) {
    Bytes file(kMerlFileBytes);
    std::copy(input.begin() + 1, input.begin() + 13, file.begin());
    const auto pattern = input.subspan(13);
    for (std::size_t at = 12; at < file.size(); at += pattern.size())
      std::copy_n(pattern.begin(), std::min(pattern.size(), file.size() - at),
                  file.begin() + std::ptrdiff_t(at));
    loadMerl(writeScratchFile("input.binary", file));
    return;
  }
  loadMerl(writeScratchFile("input.binary", input.empty() ? input : input.subspan(1)));
}

Bytes merlHeader() {
  Bytes header(12);
  const std::int32_t dims[3] = {kMerlThetaHBins, kMerlThetaDBins, kMerlPhiDBins};
  std::memcpy(header.data(), dims, sizeof dims);
  return header;
}

std::vector<Bytes> merlSeeds() {
  Bytes pattern;
  for (double v : {0.5, 1.0, -1.0, 2.5, std::numeric_limits<double>::quiet_NaN(), 3000.0, 0.0}) {
    const auto bits = std::bit_cast<std::array<std::uint8_t, 8>>(v);
    pattern.insert(pattern.end(), bits.begin(), bits.end());
  }
  Bytes expanded = withPrefix({1}, merlHeader());
  expanded.insert(expanded.end(), pattern.begin(), pattern.end());
  Bytes shortFile = withPrefix({0}, merlHeader());
  shortFile.insert(shortFile.end(), pattern.begin(), pattern.end());
  return {expanded, shortFile, withPrefix({0}, merlHeader())};
}

// ---- UTIA .bin -------------------------------------------------------------------------------------------

// Input byte 0 selects the layout: 1 repeats the rest to fill a full-size file (UTIA has no header: only a
// file of the exact size reaches the value checks); anything else writes the rest as it is (the size check).
void runUtia(std::span<const std::uint8_t> input) {
  if (!input.empty() && input[0] == 1 && input.size() > 1) {
    Bytes file(kUtiaFileBytes);
    const auto pattern = input.subspan(1);
    for (std::size_t at = 0; at < file.size(); at += pattern.size())
      std::copy_n(pattern.begin(), std::min(pattern.size(), file.size() - at),
                  file.begin() + std::ptrdiff_t(at));
    loadUtia(writeScratchFile("input.bin", file));
    return;
  }
  loadUtia(writeScratchFile("input.bin", input.empty() ? input : input.subspan(1)));
}

std::vector<Bytes> utiaSeeds() {
  Bytes pattern;
  for (double v : {0.5, 1.0, -1.0, 2.5, 0.0, 1e20}) {
    const auto bits = std::bit_cast<std::array<std::uint8_t, 8>>(v);
    pattern.insert(pattern.end(), bits.begin(), bits.end());
  }
  return {withPrefix({1}, pattern), withPrefix({0}, pattern)};
}

// ---- MIT CSAIL .dat -------------------------------------------------------------------------------------

void runMit(std::span<const std::uint8_t> input) {
  loadMitBrdf(writeScratchFile("input.dat", input));
}

std::vector<Bytes> mitSeeds() {
  const auto file = [](const MitDims& dims, float value) {
    const auto path = std::filesystem::temp_directory_path() / "iblx-fuzz-mit-seed.dat";
    writeMitBrdf(path, dims, std::vector<float>(3 * dims.bins(), value));
    std::ifstream in(path, std::ios::binary);
    Bytes bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::filesystem::remove(path);
    return bytes;
  };
  return {file({2, 2, 4, 4, false}, 0.5f), file({3, 1, 2, 2, true}, -1.0f), file({1, 1, 1, 1, false}, 2.0f)};
}

// ---- RGL-EPFL .bsdf --------------------------------------------------------------------------------------

// A file that loads must also build its warps and evaluate and sample without a NaN.
void runRgl(std::span<const std::uint8_t> input) {
  const RglBsdf material(loadRglBsdf(writeScratchFile("input.bsdf", input)));
  const glm::dvec3 wo = glm::normalize(glm::dvec3(0.3, 0.2, 0.9));
  const RglBsdf::Sample s = material.sample(glm::dvec2(0.3, 0.7), wo);
  if (!std::isfinite(s.pdf) || s.pdf < 0.0) throw Error("rgl-vndf sampled a pdf of " + std::to_string(s.pdf));
  const glm::dvec3 f = material.eval(glm::normalize(glm::dvec3(-0.2, 0.1, 0.8)), wo);
  if (!std::isfinite(f.x + f.y + f.z)) throw Error("an RGL material evaluated to a non-finite value");
}

std::vector<Bytes> rglSeeds() {
  const auto file = [](std::uint32_t phiViews, float rgb) {
    RglSynthLayout layout;
    layout.thetaViews = 3, layout.phiViews = phiViews, layout.vndfSize = 4, layout.sampleSize = 3;
    RglSynthPlan plan = planRglSynth(layout);
    const std::vector<glm::dvec3> f(plan.wi.size(), glm::dvec3(rgb));
    const auto path = std::filesystem::temp_directory_path() / "iblx-fuzz-rgl-seed.bsdf";
    writeRglBsdf(path, finishRglSynth(std::move(plan), f));
    std::ifstream in(path, std::ios::binary);
    Bytes bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::filesystem::remove(path);
    return bytes;
  };
  return {file(1, 0.3f), file(3, 0.5f)};
}

// ---- ALTA data files --------------------------------------------------------------------------------------

// A file that loads must also become a grid (found or resampled) whose lookup is finite and non-negative.
void runAltaData(std::span<const std::uint8_t> input) {
  const AltaData data = loadAltaData(writeScratchFile("input.data", input));
  const AltaGrid grid = makeAltaGrid(data, "input.data");
  const glm::dvec3 f = evalAltaGrid(grid, glm::normalize(glm::dvec3(-0.2, 0.1, 0.8)),
                                    glm::normalize(glm::dvec3(0.3, 0.2, 0.9)));
  if (!(f.x >= 0.0 && f.y >= 0.0 && f.z >= 0.0 && std::isfinite(f.x + f.y + f.z)))
    throw Error("an ALTA data grid evaluated to a negative or non-finite value");
}

// Scattered samples, nearly all at one point and one far away: resampling them cost nodes x samples.
Bytes clusteredAltaData() {
  std::string text = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TV_TL_DPHI\n#PARAM_OUT INV_STERADIAN\n";
  for (int i = 0; i < 200; ++i) text += "0.5 0.5 1 0.25\n";
  return textBytes(text + "1.2 1.1 2 0.5\n");
}

std::vector<Bytes> altaDataSeeds() {
  const auto file = [](AltaParam param, std::size_t scattered, bool binary) {
    AltaSynthPlan plan = planAltaSynth(param, AltaOutput::RgbColor, scattered);
    const std::vector<glm::dvec3> f(plan.wi.size(), glm::dvec3(0.25));
    const auto path = std::filesystem::temp_directory_path() / "iblx-fuzz-alta-seed.data";
    writeAltaData(path, finishAltaSynth(std::move(plan), f), binary);
    std::ifstream in(path, std::ios::binary);
    Bytes bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::filesystem::remove(path);
    return bytes;
  };
  return {
      file(AltaParam::RusinThTd, 40, false), file(AltaParam::Cartesian, 30, true),
      textBytes("#DIM 2 3\n#PARAM_IN RUSIN_TH_TD\n#PARAM_OUT RGB_COLOR\n#VS 1\n0 0 1 1 1 0.1\n0 1 2 2 2 0.1\n"
                "1 0 3 3 3 0.1\n1 1 4 4 4 0.1\n"),
      clusteredAltaData(),
      // Blanks and tabs as ALTA's own files have them, CRLF line ends and a comment before #DIM.
      textBytes(
          "# measured; disclaimer\r\n#DIM\t3  1\r\n#PARAM_IN  ISOTROPIC_TV_TL_DPHI \r\n0.1\t0.2 0.3 1\r\n"
          "0.4 0.5\t0.6 2\r\n"),
      // A header line without an end.
      textBytes("#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT " + std::string(4096, 'X'))};
}

// ---- ALTA function files ----------------------------------------------------------------------------------

// A parsed file is also evaluated at a few direction pairs and written back and re-read: the evaluation and
// the writer meet every value the parser accepts.
void runAltaFunc(std::span<const std::uint8_t> input) {
  const AltaFunc f = parseAltaFunc(
      std::string_view(reinterpret_cast<const char*>(input.data()), input.size()), "input.func");
  const glm::dvec3 n(0.0, 0.0, 1.0), a(0.6, 0.0, 0.8), b(-0.28, 0.96, 0.0), c(0.0, -0.6, 0.8);
  for (const auto& [wi, wo] : {std::pair{n, n}, std::pair{a, c}, std::pair{c, a}, std::pair{b, a}}) {
    const glm::dvec3 v = evalAltaFunc(f, wi, wo);
    if (!(v.x >= 0.0 && v.y >= 0.0 && v.z >= 0.0 && std::isfinite(v.x + v.y + v.z)))
      throw std::logic_error("evalAltaFunc returned a negative or non-finite value");
  }
  if (parseAltaFunc(formatAltaFunc(f), "rewritten.func").lobes.size() != f.lobes.size())
    throw std::logic_error("formatAltaFunc does not round-trip");
}

std::vector<Bytes> altaFuncSeeds() {
  const std::string header =
      "#ALTA FUNC HEADER\n#CMD ALTA --func rational_function_chebychev\n#DIM 3 3\n"
      "#PARAM_IN RUSIN_TH_TD_PD\n#ALTA HEADER END\n\n";
  return {textBytes(header +
                    "#FUNC nonlinear_function_diffuse\nkd 0.1\nkd 0.2\nkd 0.3\n\n"
                    "#FUNC nonlinear_function_blinn\nKs 1\nN 10\nKs 2\nN 20\nKs 3\nN 30\n"
                    "#FUNC nonlinear_function_beckmann\nKs 0.5\na 0.2\nKs 0.5\na 0.3\nKs 0.5\na 0.4\n"
                    "#FUNC nonlinear_function_ward\nKs 0.2\nax 0.1\nay 0.3\nKs 0.2\nax 0.1\nay 0.3\nKs 0.2\n"
                    "ax 0.1\nay 0.3\n"),
          textBytes(header + "#FUNC rational_function\n#MIN 0 0 0\n#MAX 1.5707963 1.5707963 3.1415927\n"
                             "#NP 2\n#NQ 2\n0 0 0 1\n1 0 2 0.5\n0 0 0 1\n0 1 0 -0.25\n"
                             "#NP 1\n#NQ 1\n0 0 0 2\n0 0 0 1\n#NP 1\n#NQ 1\n3 2 1 0.5\n0 0 0 1\n"),
          textBytes("#ALTA FUNC HEADER\n#DIM 2 1\n#PARAM_IN COS_TH_TD\n#ALTA HEADER END\n"
                    "#FUNC rational_function_legendre\n#MIN 0 0\n#MAX 1 1\n#NP 1\n#NQ 1\n0 0 1\n0 0 1\n")};
}

// ---- BRDF Explorer .brdf / .bparam ----------------------------------------------------------------------

constexpr std::string_view kBrdfSeed = R"(analytic

# A Lambert-plus-Phong BRDF written for iblx's fuzz corpus.
::begin parameters
color albedo 0.5 0.6 0.7
float shininess 1 1000 50
float ks 0 1 0.2
bool normalized 1
::end parameters

::begin shader
const float PI = 3.14159265358979;
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
{
    if (dot(N, L) <= 0.0 || dot(N, V) <= 0.0) return vec3(0.0);
    vec3 R = reflect(-L, N);
    float s = pow(max(dot(R, V), 0.0), shininess);
    return albedo / PI + vec3(ks * s * (normalized ? (shininess + 2.0) / (2.0 * PI) : 1.0));
}
::end shader

::begin isFunc
vec3 sampleBRDF(float u, float v, vec3 N, vec3 X, vec3 Y, out vec3 wi, out float pdf)
{
    pdf = 0.0;
    wi = N;
    return vec3(0.0);
}
::end isFunc

::begin unknownsection
ignored
::end unknownsection
)";

void runBrdf(std::span<const std::uint8_t> input) {
  readBrdfFile(writeScratchFile("input.brdf", input));
}

std::vector<Bytes> brdfSeeds() {
  return {textBytes(kBrdfSeed),
          textBytes("analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return "
                    "vec3(1.0); }\n::end shader\n")};
}

void runBparam(std::span<const std::uint8_t> input) {
  // The .bparam names its .brdf relative to its own folder: the scratch directory holds one.
  static const auto source = writeScratchFile("source.brdf", textBytes(kBrdfSeed));
  readBrdfFile(writeScratchFile("input.bparam", input));
}

std::vector<Bytes> bparamSeeds() {
  return {textBytes("bparam source.brdf\n\n::begin parameters\ncolor albedo 0.25 0.5 1\nfloat shininess 1 "
                    "1000 120\nfloat ks 0 1 0.5\nbool normalized 0\n::end parameters\n"),
          textBytes("bparam source.brdf\n::begin parameters\nfloat ks 0 1 1e-3\n::end parameters\n")};
}

// ---- OBJ ------------------------------------------------------------------------------------------------

void runObj(std::span<const std::uint8_t> input) {
  readObj(writeScratchFile("input.obj", input));
}

std::vector<Bytes> objSeeds() {
  std::vector<Bytes> seeds;
  // The project's writer: a tetrahedron with per-vertex normals (`f v//vn`).
  TriMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& p : mesh.positions)
    mesh.normals.push_back(glm::length(p) > 0 ? p : glm::dvec3(-1, -1, -1) / std::sqrt(3.0));
  mesh.triangles = {{{0, 2, 1}}, {{0, 1, 3}}, {{0, 3, 2}}, {{1, 2, 3}}};
  const auto path = scratchDirectory() / "seed.obj";
  writeObj(path, mesh, "tetrahedron for iblx's fuzz corpus");
  seeds.push_back(fileBytes(path));
  // Hand-written: texture coordinates, a quad and a pentagon (triangulated), negative (relative) indices,
  // a degenerate face, groups, a material reference and a line element.
  seeds.push_back(
      textBytes("# obj for iblx's fuzz corpus\nmtllib none.mtl\no thing\ng part\nv 0 0 0\nv 1 0 0\n"
                "v 1 1 0\nv 0 1 0\nv 0.5 1.5 0.25\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
                "usemtl red\nf 1/1/1 2/2/1 3/3/1 4/1/1\nf -5 -4 -3 -2 -1\nf 1 1 2\nl 1 2\n"
                "s off\nf 2/2 3/3 5/1\n"));
  return seeds;
}

// ---- Cache files ------------------------------------------------------------------------------------------

void runOtCache(std::span<const std::uint8_t> input) {
  readOtMapCacheFile(writeScratchFile("input.otmap", sealedCacheInput(input)));
}

std::vector<Bytes> otCacheSeeds() {
  // A real entry: a small map solved and stored by the cache itself.
  const int n = 4;
  const std::vector<double> density = {1, 2, 3, 4, 2, 8, 1, 1, 0.5, 1, 1, 6, 1, 1, 2, 3};
  const auto cacheDir = scratchDirectory() / "ot-cache";
  solveOtMapCached(density, n, {}, cacheDir);
  const Bytes entry = fileBytes(otMapCachePath(cacheDir, otMapCacheKey(density, n, {})));
  return {withPrefix({0}, entry), withPrefix({1}, Bytes(entry.begin(), entry.end() - 8))};
}

// Bytes 1 and 2 are the size the scene expects (so size mismatches are one mutation away), then the file.
void runReferenceCache(std::span<const std::uint8_t> input) {
  if (input.size() < 3) throw Error("input too short");
  const int width = input[1] % 17, height = input[2] % 17;
  Bytes modeAndFile = {input[0]};
  modeAndFile.insert(modeAndFile.end(), input.begin() + 3, input.end());
  readReferenceCacheFile(writeScratchFile("input.exr", sealedCacheInput(modeAndFile)), width, height);
}

std::vector<Bytes> referenceCacheSeeds() {
  const auto path = scratchDirectory() / "seed-reference.exr";
  writeReferenceCacheFile(path, 4, 3, testImage(4, 3, false));
  const Bytes entry = fileBytes(path);
  return {withPrefix({0, 4, 3}, entry), withPrefix({1, 4, 3}, Bytes(entry.begin(), entry.end() - 8))};
}

// A minimal valid compute module, laid out by hand (the CPU build has no compiler): OpCapability Shader,
// OpMemoryModel Logical GLSL450, OpEntryPoint GLCompute %1 "main", OpExecutionMode %1 LocalSize 1 1 1,
// %2 = OpTypeVoid, %3 = OpTypeFunction %2, %1 = OpFunction %2 None %3, %4 = OpLabel, OpReturn, OpFunctionEnd.
std::vector<std::uint32_t> minimalSpirv() {
  auto op = [](std::uint32_t opcode, std::uint32_t words) { return words << 16 | opcode; };
  return {0x07230203u, 0x00010500u, 0, 5,         0,           op(17, 2), 1,          op(14, 3), 0,
          1,           op(15, 5),   5, 1,         0x6e69616du, 0,         op(16, 6),  1,         17,
          1,           1,           1, op(19, 2), 2,           op(33, 3), 3,          2,         op(54, 5),
          2,           1,           0, 3,         op(248, 2),  4,         op(253, 1), op(56, 1)};
}

void runSpirvCache(std::span<const std::uint8_t> input) {
  readSpirvCacheFile(writeScratchFile("input.spv", sealedCacheInput(input)));
}

std::vector<Bytes> spirvCacheSeeds() {
  const auto words = minimalSpirv();
  const auto path = scratchDirectory() / "seed.spv";
  writeSpirvCacheFile(path, words);
  const Bytes entry = fileBytes(path);
  return {withPrefix({0}, entry), withPrefix({1}, Bytes(entry.begin(), entry.end() - 8))};
}

}  // namespace

Bytes sealedCacheInput(std::span<const std::uint8_t> input) {
  if (input.empty()) return {};
  const auto rest = input.subspan(1);
  if (input[0] % 2 == 1) return sealCacheBytes(rest);
  return Bytes(rest.begin(), rest.end());
}

std::vector<FuzzTarget> cpuFuzzTargets() {
  return {
      {"exr", "OpenEXR environment map (loadEnvImage)", runExr, exrSeeds},
      {"hdr", "Radiance .hdr environment map (loadEnvImage)", runHdr, hdrSeeds},
      // One input in three or so expands to a 35 MB file.
      {"merl", "MERL .binary measured BRDF (loadMerl)", runMerl, merlSeeds, 8.0},
      {"utia", "UTIA .bin measured BRDF (loadUtia)", runUtia, utiaSeeds},
      {"mit", "MIT CSAIL .dat measured BRDF (loadMitBrdf)", runMit, mitSeeds},
      {"rgl", "RGL-EPFL .bsdf tensor file (loadRglBsdf, then its warps)", runRgl, rglSeeds},
      {"alta-data", "ALTA data file (loadAltaData, then its grid)", runAltaData, altaDataSeeds},
      {"alta-func", "ALTA function file (parseAltaFunc, evalAltaFunc, formatAltaFunc)", runAltaFunc,
       altaFuncSeeds},
      {"brdf", "BRDF Explorer .brdf file (readBrdfFile)", runBrdf, brdfSeeds},
      {"bparam", "BRDF Explorer .bparam file (readBrdfFile)", runBparam, bparamSeeds},
      {"obj", "Wavefront OBJ mesh (readObj)", runObj, objSeeds},
      {"ot-cache", "OT map cache file (readOtMapCacheFile)", runOtCache, otCacheSeeds},
      {"reference-cache", "ground-truth cache file (readReferenceCacheFile)", runReferenceCache,
       referenceCacheSeeds},
      {"spirv-cache", "SPIR-V cache file (readSpirvCacheFile)", runSpirvCache, spirvCacheSeeds},
  };
}

}  // namespace iblx::fuzz
