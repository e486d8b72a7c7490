// UTIA files as BRDFs (engine/scene/measured_brdfs.h): recognised by their content whatever their name, their
// colour convention as parameters, and a .bparam that saves it.
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/io/brdf_file.h"
#include "engine/io/utia.h"
#include "engine/scene/brdf_params.h"
#include "engine/scene/scene.h"
#include "engine/scene/measured_brdfs.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <unistd.h>

namespace iblx {
namespace {

// A directory of its own under the system's temporary directory, removed at the end.
struct TemporaryDir {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("iblx-utia-brdf-" + std::to_string(::getpid()));
  TemporaryDir() { std::filesystem::create_directories(path); }
  ~TemporaryDir() { std::filesystem::remove_all(path); }
};

}  // namespace

TEST_CASE(
    "utia brdf: a file of UTIA's size is a UTIA material whatever its name; its convention is parameters") {
  TemporaryDir dir;
  const auto bin = dir.path / "paint.bin";
  writeUtia(bin, std::vector<double>(3 * kUtiaEntries, 0.25));
  const LoadedBrdf loaded = loadBrdfArgument(bin.string());
  CHECK(loaded.info->evalPart == "brdf/utia.glsl");
  CHECK(loaded.info->name == "paint");
  CHECK(loaded.info->bestSampler == "brdf-tab");
  CHECK(loaded.file == bin);
  const ParamValues defaults = resolveParams(*loaded.info, {});
  const UtiaConvention convention = utiaConvention(defaults);
  CHECK(convention.prescale == 1.0);
  CHECK_FALSE(convention.srgb);
  CHECK(convention.scale == 1.0);
  const UtiaConvention given =
      utiaConvention(resolveParams(*loaded.info, {{"srgb", "true"}, {"scale", "100"}}));
  CHECK(given.srgb);
  CHECK(given.scale == 100.0);

  // Another name, the same content.
  const auto renamed = dir.path / "paint.data";
  std::filesystem::copy_file(bin, renamed);
  CHECK(loadBrdfArgument(renamed.string()).info->evalPart == "brdf/utia.glsl");

  // A .bparam keeps the convention.
  const auto bparam = dir.path / "paint.bparam";
  writeBparam(bparam, bin, loaded.info->params, resolveParams(*loaded.info, {{"prescale", "0.5"}}));
  const LoadedBrdf saved = loadBrdfArgument(bparam.string());
  CHECK(saved.info->evalPart == "brdf/utia.glsl");
  CHECK(utiaConvention(resolveParams(*saved.info, {})).prescale == 0.5);
}

TEST_CASE("utia brdf: a .bin of another size is refused with both sizes") {
  TemporaryDir dir;
  const auto bin = dir.path / "short.bin";
  writeFileAtomically(bin, std::string_view("not a material"));
  CHECK_THROWS_WITH_AS(
      loadBrdfArgument(bin.string()),
      doctest::Contains("short.bin: truncated UTIA file: 14 bytes, expected exactly 1990656"), Error);
}

}  // namespace iblx
