// Tests of the sealed cache files (engine/core/cache_file.h): every truncation and every single-bit flip of a
// sealed file is detected, writes leave no temporary behind, and SPIR-V entries are checked as SPIR-V.
#include "engine/core/cache_file.h"

#include "engine/core/error.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace iblx;

namespace {

struct TempDir {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("iblx-cache-file-test-" + std::to_string(::getpid()));
  TempDir() {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

std::vector<unsigned char> fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The message of the iblx::Error that f throws (tests/io/scratch_files.h).
std::string errorOf(auto&& f) { return test::errorMessage(f); }

// OpCapability Shader; OpMemoryModel Logical GLSL450 after a SPIR-V 1.5 header with id bound 1.
std::vector<std::uint32_t> tinySpirv() {
  return {0x07230203u, 0x00010500u, 0, 1, 0, 2u << 16 | 17, 1, 3u << 16 | 14, 0, 1};
}

std::vector<unsigned char> bytesOf(const std::vector<std::uint32_t>& words) {
  std::vector<unsigned char> bytes(words.size() * 4);
  std::memcpy(bytes.data(), words.data(), bytes.size());
  return bytes;
}

}  // namespace

TEST_CASE("cache file: the seal round-trips and catches every truncation and every bit flip") {
  const std::vector<unsigned char> payload = {'i', 'b', 'l', 'x', 0, 1, 2, 3, 250, 251, 252, 253, 254};
  const std::vector<unsigned char> sealed = sealCacheBytes(payload);
  REQUIRE(sealed.size() == payload.size() + 8);
  CHECK(unsealCacheBytes(sealed) == payload);
  for (std::size_t size = 0; size < sealed.size(); ++size) {
    CAPTURE(size);
    CHECK_THROWS_AS(unsealCacheBytes(std::span(sealed).first(size)), Error);
  }
  for (std::size_t bit = 0; bit < 8 * sealed.size(); ++bit) {
    CAPTURE(bit);
    std::vector<unsigned char> flipped = sealed;
    flipped[bit / 8] ^= static_cast<unsigned char>(1u << (bit % 8));
    CHECK_THROWS_AS(unsealCacheBytes(flipped), Error);
  }
  // An empty payload is still a valid sealed file.
  CHECK(unsealCacheBytes(sealCacheBytes({})).empty());
}

TEST_CASE("cache file: written atomically, read back with the file named in every error") {
  TempDir dir;
  const auto path = dir.path / "sub" / "entry.bin";
  const std::vector<unsigned char> payload(1000, 7);
  writeSealedCacheFile(path, payload);
  CHECK(readSealedCacheFile(path, 1 << 20) == payload);
  // Only the entry itself: no temporary is left beside it.
  CHECK(std::distance(std::filesystem::directory_iterator(path.parent_path()), {}) == 1);

  std::filesystem::resize_file(path, 500);
  const std::string torn = errorOf([&] { readSealedCacheFile(path, 1 << 20); });
  CHECK(torn.find(path.string()) != std::string::npos);
  CHECK(torn.find("checksum mismatch") != std::string::npos);

  writeSealedCacheFile(path, payload);
  CHECK(errorOf([&] { readSealedCacheFile(path, 100); }).find(path.string()) != std::string::npos);
  CHECK(errorOf([&] { readSealedCacheFile(dir.path / "missing", 100); }).find("missing") !=
        std::string::npos);
  // A directory where the entry should be is refused at once, not read.
  CHECK(errorOf([&] { readSealedCacheFile(dir.path / "sub", 100); }).find("sub") != std::string::npos);
}

TEST_CASE("cache file: SPIR-V entries are checked as SPIR-V") {
  const auto words = tinySpirv();
  CHECK(decodeSpirvCachePayload(bytesOf(words)) == words);
  auto broken = [&](auto change) {
    auto w = words;
    change(w);
    return errorOf([&] { decodeSpirvCachePayload(bytesOf(w)); });
  };
  CHECK(broken([](auto& w) { w[0] = 0x03022307u; }).find("magic") != std::string::npos);
  CHECK(broken([](auto& w) { w[1] = 0x00020000u; }).find("version") != std::string::npos);
  CHECK(broken([](auto& w) { w[3] = 0; }).find("bound") != std::string::npos);
  CHECK(broken([](auto& w) { w[4] = 1; }).find("schema") != std::string::npos);
  CHECK(broken([](auto& w) { w.resize(5); }).find("no instructions") != std::string::npos);
  CHECK(broken([](auto& w) { w[5] = 9u << 16 | 17; }).find("word count") != std::string::npos);
  CHECK(broken([](auto& w) { w[7] = 0u << 16 | 14; }).find("word count") != std::string::npos);
  std::vector<unsigned char> odd = bytesOf(words);
  odd.pop_back();
  CHECK(errorOf([&] { decodeSpirvCachePayload(odd); }).find("whole number") != std::string::npos);

  TempDir dir;
  const auto path = dir.path / "spirv" / "k.spv";
  writeSpirvCacheFile(path, words);
  CHECK(readSpirvCacheFile(path) == words);
  // The layout the SPIR-V cache has always had: the words, then FNV-1a of their bytes.
  CHECK(fileBytes(path).size() == words.size() * 4 + 8);
}
