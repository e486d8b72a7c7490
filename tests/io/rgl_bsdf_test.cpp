// Tests of the tensor-file container and the RGL-EPFL .bsdf tables (engine/io/tensor_file.h,
// engine/io/rgl_bsdf.h): round trips, every class of damaged container and of wrong field with its message,
// negative colours zeroed with a count, and spectra converted to linear sRGB (grey stays grey, a long-wave
// spectrum is red).
#include "engine/io/rgl_bsdf.h"

#include "engine/core/error.h"
#include "engine/io/tensor_file.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

using namespace iblx;
using namespace iblx::test;

namespace {

// A small valid isotropic material: 2 views, 3 x 3 warps, 2 x 2 colour grid.
RglTables smallTables() {
  RglTables t;
  t.description = "test material";
  t.thetaI = {0.0f, 1.0f};
  t.phiI = {0.0f};
  t.ndf = t.sigma = {3, 3, std::vector<float>(9, 1.0f)};
  t.vndf = {3, 3, std::vector<float>(2 * 9, 1.0f)};
  t.luminance = {2, 2, std::vector<float>(2 * 4, 1.0f)};
  t.rgb = {2, 2, std::vector<float>(2 * 3 * 4, 0.5f)};
  return t;
}

TensorFile smallFile() {
  ScratchDir dir;
  writeRglBsdf(dir.file("m.bsdf"), smallTables());
  return readTensorFile(dir.file("m.bsdf"));
}

std::string loadMessage(const TensorFile& file) {
  ScratchDir dir;
  writeTensorFile(dir.file("m.bsdf"), file);
  return errorMessage([&] { loadRglBsdf(dir.file("m.bsdf")); });
}

// The offset of field `name`'s header entry's u64 data offset in the written file.
std::size_t offsetFieldAt(const std::vector<unsigned char>& bytes, const std::string& name) {
  const auto it = std::search(bytes.begin(), bytes.end(), name.begin(), name.end());
  REQUIRE(it != bytes.end());
  const std::size_t at = std::size_t(it - bytes.begin()) + name.size();
  return at + 2 + 1;  // after the u16 dimension count and the u8 dtype
}

}  // namespace

TEST_CASE("rgl .bsdf: tables round-trip through the tensor file") {
  ScratchDir dir;
  const auto path = dir.file("m.bsdf");
  RglTables t = smallTables();
  t.rgb.values[5] = 0.25f;
  writeRglBsdf(path, t);
  CHECK(looksLikeRglBsdf(path));
  const RglTables back = loadRglBsdf(path);
  CHECK(back.description == "test material");
  CHECK(back.thetaI == t.thetaI);
  CHECK(back.rgb.values == t.rgb.values);
  CHECK(back.vndf.width == 3);
  CHECK(back.jacobian);
  CHECK(back.isotropic());
  CHECK(back.reduction() == 1);
  const auto other = dir.file("other.bin");
  writeBytes(other, randomBytes(64, 3));
  CHECK_FALSE(looksLikeRglBsdf(other));
}

TEST_CASE("rgl .bsdf: a damaged container is refused with a message naming the problem") {
  ScratchDir dir;
  const auto path = dir.file("m.bsdf");
  writeRglBsdf(path, smallTables());
  const std::vector<unsigned char> good = readBytes(path);
  const auto messageOf = [&](std::vector<unsigned char> bytes) {
    writeBytes(path, bytes);
    return errorMessage([&] { loadRglBsdf(path); });
  };
  CHECK(contains(messageOf({'t', 'e', 'n'}), "not a tensor file"));
  std::vector<unsigned char> version = good;
  version[12] = 2;
  CHECK(contains(messageOf(version), "version 2.0 is not supported"));
  std::vector<unsigned char> count = good;
  std::memset(count.data() + 14, 0xff, 4);
  CHECK(contains(messageOf(count), "declares 4294967295 fields"));
  CHECK(contains(messageOf(std::vector<unsigned char>(good.begin(), good.begin() + 40)),
                 "ends inside the header"));
  // The rgb field's data placed beyond the end of the file.
  std::vector<unsigned char> outside = good;
  const std::size_t at = offsetFieldAt(outside, "rgb");
  const std::uint64_t far = good.size() - 8;
  std::memcpy(outside.data() + at, &far, 8);
  CHECK(contains(messageOf(outside), "field 'rgb''s data (96 bytes at offset"));
  CHECK(contains(messageOf(outside), "lies outside the"));
  // Truncated data: the last field's bytes cut off.
  CHECK(contains(messageOf(std::vector<unsigned char>(good.begin(), good.end() - 4)), "lies outside the"));
  // A dtype byte that is none of the 11.
  std::vector<unsigned char> dtype = good;
  dtype[offsetFieldAt(dtype, "sigma") - 1] = 42;
  CHECK(contains(messageOf(dtype), "field 'sigma' has dtype 42"));
  CHECK(contains(errorMessage([&] { loadRglBsdf(dir.file("missing.bsdf")); }), "cannot open"));
}

TEST_CASE("tensor file: fields that alias one blob are refused before each copies it") {
  // One 4000-byte blob and three one-value fields; the three are then pointed at the blob with its length:
  // each lies inside the file, together they claim four times what it holds (1,000 such fields reached 6 GB).
  ScratchDir dir;
  const auto path = dir.file("aliased.bsdf");
  TensorFile file;
  file.fields["blob"] = float32Field({1000}, std::vector<float>(1000, 0.5f));
  for (const char* name : {"xa", "xb", "xc"}) file.fields[name] = float32Field({1}, std::vector<float>{1.0f});
  writeTensorFile(path, file);
  std::vector<unsigned char> bytes = readBytes(path);
  std::uint64_t blob = 0;
  std::memcpy(&blob, bytes.data() + offsetFieldAt(bytes, "blob"), 8);
  const std::uint64_t extent = 1000;
  for (const char* name : {"xa", "xb", "xc"}) {
    const std::size_t at = offsetFieldAt(bytes, name);
    std::memcpy(bytes.data() + at, &blob, 8);
    std::memcpy(bytes.data() + at + 8, &extent, 8);  // the one dimension's extent follows the offset
  }
  writeBytes(path, bytes);
  CHECK(contains(errorMessage([&] { readTensorFile(path); }), "-byte file: their data overlap"));
}

TEST_CASE("rgl .bsdf: wrong fields are refused, naming the field") {
  {
    TensorFile f = smallFile();
    f.fields.erase("vndf");
    CHECK(contains(loadMessage(f), "has no field 'vndf'"));
  }
  {
    TensorFile f = smallFile();
    f.fields.erase("rgb");
    CHECK(contains(loadMessage(f), "neither an 'rgb' nor a 'spectra' field"));
  }
  {
    TensorFile f = smallFile();
    f.fields["ndf"].type = TensorType::Float64;
    f.fields["ndf"].bytes.resize(f.fields["ndf"].bytes.size() * 2);
    CHECK(contains(loadMessage(f), "field 'ndf' holds f64 values, expected f32"));
  }
  {
    TensorFile f = smallFile();
    f.fields["luminance"].shape = {1, 2, 4, 1};  // same element count, wrong shape
    CHECK(contains(loadMessage(f), "field 'luminance' has shape [1, 2, 4, 1], expected [1, 2, 1, 1]"));
  }
  {
    TensorFile f = smallFile();
    f.fields["rgb"].shape = {1, 2, 4, 2, 2};
    f.fields["rgb"].bytes.resize(2 * 4 * 4 * 4);
    CHECK(contains(loadMessage(f), "field 'rgb' has shape [1, 2, 4, 2, 2], expected [1, 2, 3, 2, 2]"));
  }
  {
    TensorFile f = smallFile();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(f.fields["vndf"].bytes.data() + 8, &nan, 4);
    CHECK(contains(loadMessage(f), "field 'vndf' entry 2 is not a finite number"));
  }
  {
    TensorFile f = smallFile();
    const float negative = -1.0f;
    std::memcpy(f.fields["luminance"].bytes.data(), &negative, 4);
    CHECK(contains(loadMessage(f), "field 'luminance' entry 0 is negative"));
  }
  {
    TensorFile f = smallFile();
    const float zero = 0.0f;
    std::memcpy(f.fields["sigma"].bytes.data(), &zero, 4);
    CHECK(contains(loadMessage(f), "field 'sigma' (the projected area) holds 0"));
  }
  {
    TensorFile f = smallFile();
    const float theta[2] = {1.0f, 0.5f};
    std::memcpy(f.fields["theta_i"].bytes.data(), theta, 8);
    CHECK(contains(loadMessage(f), "field 'theta_i' must increase"));
  }
  {
    TensorFile f = smallFile();
    const float phi[3] = {0.0f, 1.0f, 2.5f};  // 2.5 rad: not a whole, half or quarter turn
    f.fields["phi_i"] = float32Field({3}, phi);
    CHECK(contains(loadMessage(f), "field 'phi_i' spans 2.5"));
  }
  {
    TensorFile f = smallFile();
    const float big = 1e20f;
    std::memcpy(f.fields["rgb"].bytes.data(), &big, 4);
    CHECK(contains(loadMessage(f), "above the largest value iblx accepts"));
  }
}

TEST_CASE("rgl .bsdf: negative colours are zeroed and counted; the azimuth reduction is read from phi_i") {
  ScratchDir dir;
  RglTables t = smallTables();
  t.rgb.values[0] = -0.5f, t.rgb.values[7] = -1.0f;
  writeRglBsdf(dir.file("m.bsdf"), t);
  WarningCapture warnings;
  const RglTables back = loadRglBsdf(dir.file("m.bsdf"));
  CHECK(back.negativeEntries == 2);
  CHECK(back.rgb.values[0] == 0.0f);
  REQUIRE(warnings.messages.size() == 1);
  CHECK(contains(warnings.messages[0], "2 of 24 colour entries are negative"));

  RglTables half = smallTables();
  half.phiI = {-float(std::numbers::pi), -2.0f, -1.0f, 0.0f};
  half.vndf.values.assign(4 * 2 * 9, 1.0f);
  half.luminance.values.assign(4 * 2 * 4, 1.0f);
  half.rgb.values.assign(4 * 2 * 3 * 4, 1.0f);
  CHECK_FALSE(half.isotropic());
  CHECK(half.reduction() == 2);
}

TEST_CASE("rgl .bsdf: spectra become linear sRGB; a constant spectrum stays grey, a long-wave one is red") {
  std::vector<float> wavelengths;
  for (int k = 0; k <= 80; ++k) wavelengths.push_back(360.0f + 5.0f * float(k));
  const SpectrumToRgb toRgb(wavelengths);
  std::vector<float> flat(wavelengths.size(), 0.3f), red(wavelengths.size());
  for (std::size_t k = 0; k < red.size(); ++k) red[k] = wavelengths[k] > 600.0f ? 1.0f : 0.0f;
  double rgb[3];
  toRgb.convert(flat.data(), 1, rgb);
  for (double c : rgb) CHECK(c == doctest::Approx(0.3).epsilon(1e-6));
  toRgb.convert(red.data(), 1, rgb);
  CHECK(rgb[0] > 5.0 * std::abs(rgb[1]));
  CHECK(rgb[0] > 5.0 * std::abs(rgb[2]));

  // A spectral file: its 'spectra' and 'wavelengths' fields instead of 'rgb'.
  TensorFile f = smallFile();
  f.fields.erase("rgb");
  const float bands[3] = {450.0f, 550.0f, 650.0f};
  f.fields["wavelengths"] = float32Field({3}, bands);
  std::vector<float> spectra(2 * 3 * 4, 0.2f);
  f.fields["spectra"] = float32Field({1, 2, 3, 2, 2}, spectra);
  ScratchDir dir;
  writeTensorFile(dir.file("s.bsdf"), f);
  const RglTables t = loadRglBsdf(dir.file("s.bsdf"));
  CHECK(t.spectralBands == 3);
  REQUIRE(t.rgb.values.size() == 2 * 3 * 4);
  for (float v : t.rgb.values) CHECK(v == doctest::Approx(0.2f).epsilon(1e-5));

  // An infrared spectrum rendered black without a word; it is refused, naming the range.
  const float infrared[3] = {1000.0f, 1100.0f, 1200.0f};
  f.fields["wavelengths"] = float32Field({3}, infrared);
  writeTensorFile(dir.file("ir.bsdf"), f);
  CHECK(contains(errorMessage([&] { loadRglBsdf(dir.file("ir.bsdf")); }),
                 "ir.bsdf: its wavelengths (1000 to 1200 nm) lie outside the visible range (360 to 830 nm)"));
}
