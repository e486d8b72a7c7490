// Tests of the ALTA data-file reader and writer (engine/io/alta_data.h): text and binary round trips in every
// parametrisation, outputs (grey, RGB, XYZ), confidence intervals skipped, negative values zeroed with a
// count, and every class of malformed file with its message.
#include "engine/io/alta_data.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>

using namespace iblx;
using namespace iblx::test;

namespace {

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string loadMessage(const ScratchDir& dir, const std::string& text) {
  const auto path = dir.file("m.data");
  writeText(path, text);
  return errorMessage([&] { loadAltaData(path); });
}

AltaData sampleData(AltaParam param, AltaOutput output) {
  AltaData d;
  d.param = param;
  d.output = output;
  d.samples = 3;
  for (std::size_t i = 0; i < 3 * std::size_t(altaParamDimension(param)); ++i) d.x.push_back(0.1 * double(i));
  d.rgb = {0.5, 0.25, 0.125, 1.0, 2.0, 3.0, 0.0, 0.0, 0.0};
  return d;
}

}  // namespace

TEST_CASE("alta data: text and binary files round-trip in every parametrisation") {
  ScratchDir dir;
  for (AltaParam param : {AltaParam::RusinThTdPd, AltaParam::RusinThTd, AltaParam::IsotropicTvTlDphi,
                          AltaParam::SphericalTlPlTvPv, AltaParam::Cartesian})
    for (bool binary : {false, true}) {
      CAPTURE(altaParamName(param));
      CAPTURE(binary);
      const AltaData d = sampleData(param, AltaOutput::RgbColor);
      const auto path = dir.file("m.data");
      writeAltaData(path, d, binary);
      CHECK(looksLikeAltaData(path));
      const AltaData back = loadAltaData(path);
      CHECK(back.param == param);
      CHECK(back.output == AltaOutput::RgbColor);
      REQUIRE(back.samples == 3);
      for (std::size_t k = 0; k < d.x.size(); ++k) CHECK(back.x[k] == doctest::Approx(d.x[k]).epsilon(1e-8));
      for (std::size_t k = 0; k < d.rgb.size(); ++k)
        CHECK(back.rgb[k] == doctest::Approx(d.rgb[k]).epsilon(1e-8));
    }
  // One output is grey: the writer stores the mean, the reader copies it to every channel.
  const auto path = dir.file("grey.data");
  writeAltaData(path, sampleData(AltaParam::RusinThTd, AltaOutput::InvSteradianCosine), false);
  const AltaData grey = loadAltaData(path);
  CHECK(grey.output == AltaOutput::InvSteradianCosine);
  CHECK(grey.rgb[0] == doctest::Approx((0.5 + 0.25 + 0.125) / 3.0));
  CHECK(grey.rgb[2] == grey.rgb[0]);
  writeText(dir.file("other.data"), "0.5 0.5\n");
  CHECK_FALSE(looksLikeAltaData(dir.file("other.data")));
  writeText(dir.file("func.func"), "#ALTA FUNC HEADER\n#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n");
  CHECK_FALSE(looksLikeAltaData(dir.file("func.func")));
}

TEST_CASE("alta data: comments, intervals, XYZ and negative values") {
  ScratchDir dir;
  const auto path = dir.file("m.data");
  writeText(
      path,
      "#ALTA DATA HEADER\n# a comment line\n#DIM 2 3\n#PARAM_IN RUSIN_TH_TD\n#PARAM_OUT XYZ_COLOR\n#VS 2\n"
      "#ALTA END HEADER\n0.1 0.2 0.9505 1.0 1.089 0.5 1.5\n\n0.3 0.4 -1 0 0 0 0\n");
  WarningCapture warnings;
  const AltaData d = loadAltaData(path);
  REQUIRE(d.samples == 2);
  // D65 white in XYZ is white in linear sRGB.
  for (int c = 0; c < 3; ++c) CHECK(d.rgb[std::size_t(c)] == doctest::Approx(1.0).epsilon(1e-3));
  CHECK(d.negativeEntries == 2);  // -1 X becomes negative R and B; G turns positive
  REQUIRE(warnings.messages.size() == 1);
  CHECK(contains(warnings.messages[0], "2 of 6 values are negative"));
}

TEST_CASE("alta data: malformed files are refused with the file, the line and the problem") {
  ScratchDir dir;
  const std::string rusin = "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT INV_STERADIAN\n";
  CHECK(contains(loadMessage(dir, "#PARAM_IN RUSIN_TH_TD\n0 0 1\n"),
                 "m.data:1: not an ALTA data file: no #DIM"));
  CHECK(contains(loadMessage(dir, "#DIM 3 1\n0 0 0 1\n"), "no #PARAM_IN line"));
  CHECK(contains(loadMessage(dir, "#DIM 3\n#PARAM_IN RUSIN_TH_TD_PD\n"), "m.data:1: #DIM needs two counts"));
  CHECK(contains(loadMessage(dir, "#DIM 3 1\n#PARAM_IN BOGUS\n"),
                 "m.data:2: unknown #PARAM_IN 'BOGUS'; ALTA's parametrisations are RUSIN_TH_PH_TD_PD, "
                 "RUSIN_TH_TD_PD, RUSIN_TH_TD, RUSIN_VH, COS_TH_TD"));
  CHECK(contains(loadMessage(dir, "#DIM 2 1\n#PARAM_IN RUSIN_TH_TD_PD\n"),
                 "#DIM gives 2 inputs, but RUSIN_TH_TD_PD has 3"));
  CHECK(contains(loadMessage(dir, "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT ENERGY\n"),
                 "m.data:3: #PARAM_OUT ENERGY has no unit"));
  CHECK(contains(loadMessage(dir, "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT RADIANCE\n"),
                 "unknown #PARAM_OUT 'RADIANCE'"));
  CHECK(contains(loadMessage(dir, "#DIM 3 2\n#PARAM_IN RUSIN_TH_TD_PD\n"), "#DIM gives 2 outputs"));
  CHECK(contains(loadMessage(dir, "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT RGB_COLOR\n"),
                 "RGB_COLOR has 3"));
  CHECK(contains(loadMessage(dir, rusin + "#VS 7\n"), "m.data:4: #VS '7' is not a count from 0 to 2"));
  CHECK(contains(loadMessage(dir, rusin + "0 0 0 1\n0 0 1\n"),
                 "m.data:5: a sample has 3 values, but #DIM 3 1 need 4"));
  CHECK(contains(loadMessage(dir, rusin + "0 0 x 1\n"), "m.data:4: 'x' is not a number"));
  CHECK(contains(loadMessage(dir, rusin + "0 0 0 nan\n"),
                 "sample 0 holds nan at value 4, which is not finite"));
  CHECK(contains(loadMessage(dir, rusin + "0 0 0 1e20\n"), "above 1e15"));
  CHECK(contains(loadMessage(dir, rusin), "no samples after the header"));
  CHECK(
      contains(loadMessage(dir, "#ALTA FUNC HEADER\n#DIM 3 1\n"), "an ALTA function file, not a data file"));

  // Binary streams.
  const std::string binary =
      rusin + "#FORMAT binary\n#VERSION 0\n#PRECISION ieee754-double\n#ENDIAN little\n";
  const std::string stream(4 * 8, '\0');
  CHECK(contains(
      loadMessage(dir, binary + "#SAMPLE_COUNT 2\n#BEGIN_STREAM\n" + stream + "\n#END_STREAM\n"),
      "the binary stream holds 45 bytes after #BEGIN_STREAM, but #SAMPLE_COUNT 2 x 4 doubles needs 64"));
  CHECK(contains(loadMessage(dir, binary + "#SAMPLE_COUNT 1\n#BEGIN_STREAM\n" + stream + "garbage\n"),
                 "followed by a line #END_STREAM"));
  CHECK(contains(loadMessage(dir, binary + "#BEGIN_STREAM\n" + stream), "has no #SAMPLE_COUNT"));
  CHECK(contains(loadMessage(dir, rusin + "#FORMAT binary\n#VERSION 0\n#PRECISION ieee754-single\n#ENDIAN "
                                          "little\n#SAMPLE_COUNT 1\n#BEGIN_STREAM\n"),
                 "#PRECISION 'ieee754-single' is not supported (iblx reads ieee754-double)"));
  CHECK(contains(loadMessage(dir, rusin + "#FORMAT binary\n#VERSION 0\n#PRECISION ieee754-double\n#ENDIAN "
                                          "big\n#SAMPLE_COUNT 1\n#BEGIN_STREAM\n"),
                 "#ENDIAN 'big' is not supported"));
  CHECK(contains(loadMessage(dir, binary + "#SAMPLE_COUNT -3\n#BEGIN_STREAM\n"),
                 "#SAMPLE_COUNT '-3' is not a count"));
  CHECK(contains(errorMessage([&] { loadAltaData(dir.file("missing.data")); }), "cannot open"));
}

TEST_CASE("alta data: headers as ALTA's own files write them (blanks, tabs, CRLF, comments) are read") {
  ScratchDir dir;
  const auto path = dir.file("felt.alta");
  writeText(path,
            "# Measured data, converted for ALTA. Disclaimer: for research use.\r\n"
            "#\r\n"
            "#DIM\t3   1\r\n"
            "#PARAM_IN  RUSIN_TH_TD_PD \r\n"
            "#PARAM_OUT\tINV_STERADIAN\r\n"
            "#VS  0\r\n"
            "0.1\t0.2  0.3 0.5\r\n"
            "0.2 0.3 0.4\t0.25\r\n");
  CHECK(looksLikeAltaData(path));
  const AltaData d = loadAltaData(path);
  CHECK(d.param == AltaParam::RusinThTdPd);
  CHECK(d.output == AltaOutput::InvSteradian);
  REQUIRE(d.samples == 2);
  CHECK(d.x[5] == doctest::Approx(0.4));
  CHECK(d.rgb[3] == doctest::Approx(0.25));
}

TEST_CASE("alta data: counts that are not whole and bytes that are not text are reported as written") {
  ScratchDir dir;
  // #DIM 3.5 was read as 3, and #DIM 1e300 reported as -2147483648 inputs.
  CHECK(contains(loadMessage(dir, "#DIM 3.5 1\n#PARAM_IN RUSIN_TH_TD_PD\n0 0 0 1\n"),
                 "m.data:1: #DIM's input count '3.5' is not a whole count from 1 to 6"));
  const std::string huge = loadMessage(dir, "#DIM 1e300 1\n#PARAM_IN RUSIN_TH_TD_PD\n0 0 0 1\n");
  CHECK(contains(huge, "#DIM's input count '1e300' is not a whole count"));
  CHECK_FALSE(contains(huge, "-2147483648"));
  // A NUL byte and binary bytes are escaped: the message is whole, one line, and printable.
  const std::string binary =
      loadMessage(dir, std::string("#DIM 3 1\n#PARAM_IN RUSIN\0TH\x01\xfe\n0 0 0 1\n", 39));
  CHECK(contains(binary, "unknown #PARAM_IN 'RUSIN\\x00TH\\x01\\xfe'; ALTA's parametrisations are"));
  for (char c : binary) CHECK((c >= 0x20 && c < 0x7f));
}

TEST_CASE("alta data: a huge file without a newline is recognised from its first 64 KiB") {
  ScratchDir dir;
  // Sparse: 3 GiB on disk as a hole. The format check used to read the first line whole (all of it).
  const auto path = dir.file("no-newline.bin");
  writeText(path, "#DIM 3 1 ");
  std::filesystem::resize_file(path, std::uint64_t(3) << 30);
  CHECK(readFileHead(path, 64 << 10).size() == (64u << 10));
  CHECK_FALSE(looksLikeAltaData(path));
}

TEST_CASE("alta data: samples whose values outgrow the memory budget are refused before they are parsed") {
  ScratchDir dir;
  // 200 000 short rows: 1.6 MB of text, 200 000 x 8 doubles to store. Under a 4 MiB budget (the text
  // passes) the values do not fit, and the reader says so instead of running out of memory.
  std::string text = "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n";
  for (int i = 0; i < 200000; ++i) text += "0 0 0 1\n";
  setenv("IBLX_MEMORY_BUDGET_GIB", "0.00390625", 1);
  const std::string message = loadMessage(dir, text);
  unsetenv("IBLX_MEMORY_BUDGET_GIB");
  CHECK(contains(message, "m.data: 200000 samples of 4 values, with the file's text needs"));
  CHECK(contains(message, "memory budget"));
}
