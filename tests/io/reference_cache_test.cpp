// Tests of the ground-truth cache files (engine/io/reference_cache.h): a cached ground truth is validated
// like any input. In particular one holding NaN or Inf is refused with the file and the pixel named (it used
// to be served as is, and `converge` then printed `null` errors and a meaningless time-to-target).
#include "engine/io/reference_cache.h"

#include "engine/core/cache_file.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/io/env_image.h"
#include "engine/io/image_write.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

using namespace iblx;
using namespace iblx::test;

namespace {

std::vector<float> gradient(int width, int height) {
  std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.125f * float(i);
  return rgb;
}

}  // namespace

TEST_CASE("reference cache: an entry round-trips exactly") {
  ScratchDir dir;
  const auto path = dir.file("references/0123456789abcdef.exr");
  const auto rgb = gradient(5, 3);
  writeReferenceCacheFile(path, 5, 3, rgb);
  CHECK(readReferenceCacheFile(path, 5, 3) == rgb);
  CHECK(std::distance(std::filesystem::directory_iterator(path.parent_path()), {}) == 1);
}

TEST_CASE("reference cache: an entry is one sealed EXR whose bytes decode in memory as they read from disk") {
  ScratchDir dir;
  const auto path = dir.file("entry.exr");
  const auto rgb = gradient(6, 4);
  writeReferenceCacheFile(path, 6, 4, rgb);
  const std::vector<unsigned char> payload = readSealedCacheFile(path, 1 << 20);
  CHECK(payload == encodeExr(6, 4, rgb));
  const EnvImage decoded = decodeExr(payload, "entry");
  CHECK(decoded.width == 6);
  CHECK(decoded.height == 4);
  CHECK(decoded.rgb == rgb);
  // A truncated payload is refused as a file would be, naming what was decoded.
  const std::vector<unsigned char> torn(payload.begin(),
                                        payload.begin() + std::ptrdiff_t(payload.size() / 2));
  CHECK(contains(errorMessage([&] { decodeExr(torn, "entry"); }), "corrupt or truncated EXR file entry"));
}

TEST_CASE("reference cache: a cached ground truth holding NaN or Inf is refused, naming file and pixel") {
  ScratchDir dir;
  const auto path = dir.file("nan.exr");
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    CAPTURE(bad);
    auto rgb = gradient(4, 2);
    rgb[3 * (1 * 4 + 2) + 1] = bad;  // pixel (2, 1), green
    // Written as an older iblx or another tool could have left it: a valid, sealed EXR.
    writeSealedCacheFile(path, encodeExr(4, 2, rgb));
    const std::string message = errorMessage([&] { readReferenceCacheFile(path, 4, 2); });
    CHECK(contains(message, path.string()));
    CHECK(contains(message, std::isnan(bad) ? "NaN" : "Inf"));
    CHECK(contains(message, "pixel (2, 1)"));
    // Nor is such an image stored.
    CHECK(contains(errorMessage([&] { writeReferenceCacheFile(dir.file("out.exr"), 4, 2, rgb); }),
                   "not caching"));
    CHECK_FALSE(std::filesystem::exists(dir.file("out.exr")));
  }
}

TEST_CASE("reference cache: torn, bit-flipped, unsealed or mis-sized entries are refused") {
  ScratchDir dir;
  const auto path = dir.file("entry.exr");
  const auto rgb = gradient(8, 4);
  writeReferenceCacheFile(path, 8, 4, rgb);
  const auto good = readBytes(path);

  CHECK(contains(errorMessage([&] { readReferenceCacheFile(path, 8, 5); }), "8x4, expected 8x5"));

  auto refused = [&](const std::vector<unsigned char>& bytes) {
    writeBytes(path, bytes);
    const std::string message = errorMessage([&] { readReferenceCacheFile(path, 8, 4); });
    CHECK(contains(message, path.string()));
    return message;
  };
  CHECK(contains(refused({good.begin(), good.begin() + std::ptrdiff_t(good.size() / 2)}), "checksum"));
  for (std::size_t at : {std::size_t(10), good.size() / 2, good.size() - 20, good.size() - 1}) {
    CAPTURE(at);
    auto flipped = good;
    flipped[at] ^= 0x10;
    CHECK(contains(refused(flipped), "checksum"));
  }
  const std::string empty = refused({});
  CHECK((contains(empty, "empty") || contains(empty, "truncated")));
  // An unsealed EXR (the layout before the seal) is not trusted either.
  writeExr(path, 8, 4, rgb);
  CHECK(contains(errorMessage([&] { readReferenceCacheFile(path, 8, 4); }), "checksum"));
}

TEST_CASE(
    "reference cache: processes needing one ground truth compute it once; the others wait and read it") {
  // Each thread opens the lock file itself, so flock() makes them wait on one another as separate processes
  // (or the nodes of a cluster sharing the directory) would.
  ScratchDir dir;
  const auto path = dir.file("references/00000000000000aa.exr");
  const auto rgb = gradient(6, 4);
  std::atomic<int> computed{0};
  std::vector<std::vector<float>> results(4);
  std::vector<int> fromCache(4, -1);
  std::vector<std::thread> tasks;
  for (std::size_t t = 0; t < results.size(); ++t)
    tasks.emplace_back([&, t] {
      bool cached = false;
      results[t] = readOrComputeCached(
          path, 6, 4,
          [&] {
            ++computed;
            std::this_thread::sleep_for(
                std::chrono::milliseconds(200));  // long enough for the others to wait
            return rgb;
          },
          &cached);
      fromCache[t] = cached;
    });
  for (auto& task : tasks) task.join();
  CHECK(computed.load() == 1);
  for (std::size_t t = 0; t < results.size(); ++t) CHECK(results[t] == rgb);
  CHECK(std::count(fromCache.begin(), fromCache.end(), 1) == 3);
  CHECK(readReferenceCacheFile(path, 6, 4) == rgb);
}

TEST_CASE("reference cache: a damaged entry is computed again and replaced") {
  ScratchDir dir;
  const auto path = dir.file("references/00000000000000bb.exr");
  std::filesystem::create_directories(path.parent_path());
  writeFileAtomically(path, std::string("not an EXR"));
  const auto rgb = gradient(3, 2);
  bool cached = true;
  int computed = 0;
  CHECK(readOrComputeCached(
            path, 3, 2,
            [&] {
              ++computed;
              return rgb;
            },
            &cached) == rgb);
  CHECK(computed == 1);
  CHECK_FALSE(cached);
  CHECK(readOrComputeCached(
            path, 3, 2,
            [&] {
              ++computed;
              return rgb;
            },
            &cached) == rgb);
  CHECK(computed == 1);
  CHECK(cached);
}
