// Every command's --json output parses as JSON (nlohmann-json), one object per line with the documented keys,
// including figures that are not numbers (written as null), and labels that need escaping.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("iblx_json_test_" + std::to_string(::getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

// The JSON lines of `iblx ARGS` (stdout only); the command must succeed.
std::vector<json> jsonLines(const Scratch& scratch, const std::string& args) {
  const std::string command =
      "IBLX_CACHE_DIR=" + (scratch.dir / "cache").string() + " " + IBLX_BINARY + " " + args + " 2>/dev/null";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  REQUIRE(pipe != nullptr);
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe.get())) out += buffer;
  REQUIRE_MESSAGE(pclose(pipe.release()) == 0, "failed: " << command << "\n" << out);
  std::vector<json> lines;
  std::istringstream stream(out);
  for (std::string line; std::getline(stream, line);) {
    if (line.empty() || line[0] != '{') continue;  // other output (e.g. "wrote ...") is not JSON
    INFO("line: " << line);
    REQUIRE_NOTHROW(lines.push_back(json::parse(line)));
  }
  REQUIRE_MESSAGE(!lines.empty(), "no JSON in: " << out);
  return lines;
}

}  // namespace

TEST_CASE("--json of every command parses, with its keys") {
  Scratch scratch;
  const std::string out = (scratch.dir / "x").string();

  const json render = jsonLines(
      scratch, "render --size 12x12 --spp 2 --passes 2 --json --reference --out " + out + ".exr")[0];
  CHECK(render["method"].is_string());
  CHECK(render["spp"] == 4);
  // The 12x12 sphere: the pixel centres inside the unit disc (x^2 + y^2 < 1 on the image plane).
  int inside = 0;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      const double x = 2.0 * (i + 0.5) / 12 - 1.0, y = 1.0 - 2.0 * (j + 0.5) / 12;
      inside += x * x + y * y < 1.0 ? 1 : 0;
    }
  CHECK(render["object_pixels"] == inside);
  CHECK(render["samples_per_s"].is_number());
  CHECK(render["relmse"].is_number());
  CHECK(render["out"] == out + ".exr");

  const std::vector<json> bench =
      jsonLines(scratch, "bench --size 12x12 --spp 2 --passes 1 --method env-cdf --seq sobol --json");
  CHECK(bench[0]["method"].get<std::string>().find("env-cdf") != std::string::npos);
  CHECK(bench[0]["gpu_samples_per_s"].is_number());

  // A target no run reaches: time_to_target_s is not a number, and must come out as null, not as "nan".
  const std::vector<json> converge = jsonLines(
      scratch,
      "converge --brdf lambert --size 12x12 --method env-cdf --method mis:power --seq random --seeds 1 "
      "--max-spp 8 --target-relmse 1e-12 --no-plots --json --out-dir " +
          (scratch.dir / "c").string());
  REQUIRE(converge.size() == 2);
  for (const json& row : converge) {
    CHECK(row["time_to_target_s"].is_null());
    CHECK(row["mse"].is_number());
    CHECK(row["method"].is_string());  // labels hold commas and parentheses: escaped by the library
    CHECK(!row.contains("mse_spp_over_oracle"));
  }
  // --oracle: each method's variance per sample against the limit of a luminance pdf, which it cannot beat.
  const std::vector<json> oracle =
      jsonLines(scratch,
                "converge --brdf lambert --size 12x12 --method env-cdf --seq random --seeds 1 --max-spp 64 "
                "--oracle --no-plots --json --out-dir " +
                    (scratch.dir / "o").string());
  REQUIRE(oracle.size() == 1);
  CHECK(oracle[0]["oracle_mse_spp"].get<double>() > 0.0);
  CHECK(oracle[0]["mse_spp_over_oracle"].get<double>() > 1.0);
  CHECK(oracle[0]["mse_spp"].get<double>() == doctest::Approx(oracle[0]["mse_spp_over_oracle"].get<double>() *
                                                              oracle[0]["oracle_mse_spp"].get<double>()));
  // oracle_pixels.csv: one row per object pixel, inside the sphere, whose squared errors average to the MSE.
  std::ifstream pixelsCsv(scratch.dir / "o" / "oracle_pixels.csv");
  std::string line;
  REQUIRE(std::getline(pixelsCsv, line));
  CHECK(line == "method,sequence,x,y,oracle_mean,oracle_variance,squared_error_spp");
  int rows = 0;
  double meanSquaredError = 0.0;
  while (std::getline(pixelsCsv, line)) {
    CAPTURE(line);
    const std::size_t afterMethod = line.find("\",random,");
    REQUIRE(afterMethod != std::string::npos);
    int x = -1, y = -1;
    double mean = 0.0, variance = 0.0, squaredError = -1.0;
    REQUIRE(std::sscanf(line.c_str() + afterMethod, "\",random,%d,%d,%lf,%lf,%lf", &x, &y, &mean, &variance,
                        &squaredError) == 5);
    const double px = 2.0 * (x + 0.5) / 12 - 1.0, py = 1.0 - 2.0 * (y + 0.5) / 12;
    CHECK(px * px + py * py < 1.0);
    CHECK(mean > 0.0);
    CHECK(variance > 0.0);
    CHECK(squaredError >= 0.0);
    meanSquaredError += squaredError;
    ++rows;
  }
  CHECK(rows == inside);
  CHECK(meanSquaredError / rows == doctest::Approx(oracle[0]["mse_spp"].get<double>()).epsilon(0.01));

  const std::vector<json> hard = jsonLines(
      scratch, "hardcases --case zero-half --quick --method env-cdf --seq sobol --max-spp 16 --json");
  CHECK(hard[0]["case"] == "zero-half");
  CHECK(hard[0]["pass"].is_boolean());

  const json otmap = jsonLines(scratch, "otmap --size 64 --json --out " + out + ".png")[0];
  CHECK(otmap["n"] == 64);
  CHECK(otmap["levels"].is_array());
  CHECK(otmap["converged"].is_boolean());
}
