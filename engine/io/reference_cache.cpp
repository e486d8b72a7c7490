// Sealed ground-truth cache files (engine/io/reference_cache.h).
#include "engine/io/reference_cache.h"

#include "engine/core/cache_file.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/file_lock.h"
#include "engine/core/log.h"
#include "engine/io/env_image.h"
#include "engine/io/image_write.h"

#include <cmath>
#include <optional>
#include <cstdio>
#include <string>

namespace iblx {

namespace {

// The first non-finite value's pixel as "(x, y)", or an empty string.
std::string firstNonFinitePixel(std::span<const float> rgb, int width) {
  for (std::size_t i = 0; i < rgb.size(); ++i)
    if (!std::isfinite(rgb[i])) {
      const std::size_t pixel = i / 3;
      char text[96];
      std::snprintf(text, sizeof text, "%s at pixel (%zu, %zu)", std::isnan(rgb[i]) ? "NaN" : "Inf",
                    pixel % std::size_t(width), pixel / std::size_t(width));
      return text;
    }
  return {};
}

}  // namespace

std::vector<float> readReferenceCacheFile(const std::filesystem::path& path, int width, int height) {
  const std::string file = path.string();
  if (width <= 0 || height <= 0) throw Error(file + ": no ground truth for an empty image");
  // An uncompressed float RGB image plus OpenEXR's headers and offset tables bounds a valid entry's size.
  const std::uint64_t maxBytes = 3 * 4 * std::uint64_t(width) * std::uint64_t(height) +
                                 16 * std::uint64_t(height) + (std::uint64_t(1) << 16);
  // Read once; the seal is checked first, so OpenEXR decodes bytes known to be whole, as the writer left
  // them.
  EnvImage image = decodeExr(readSealedCacheFile(path, maxBytes), file);
  if (image.width != width || image.height != height)
    throw Error(file + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                ", expected " + std::to_string(width) + "x" + std::to_string(height));
  if (const std::string bad = firstNonFinitePixel(image.rgb, width); !bad.empty())
    throw Error(file + ": " + bad);
  return std::move(image.rgb);
}

void writeReferenceCacheFile(const std::filesystem::path& path, int width, int height,
                             std::span<const float> rgb) {
  if (const std::string bad = width > 0 ? firstNonFinitePixel(rgb, width) : ""; !bad.empty())
    throw Error("not caching " + path.string() + ": the ground truth holds " + bad);
  writeSealedCacheFile(path, encodeExr(width, height, rgb));
}

namespace {

// The valid entry at path, or nothing (a missing one silently, a damaged one with a warning).
std::optional<std::vector<float>> readValidEntry(const std::filesystem::path& path, int width, int height) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  // Validated like any input: a torn, damaged, mis-sized or non-finite entry would poison every error
  // measured against it, so it is reported and computed again.
  try {
    return readReferenceCacheFile(path, width, height);
  } catch (const Error& e) {
    warn("ignoring the cached ground truth " + std::string(e.what()) + "; computing it again");
    return std::nullopt;
  }
}

}  // namespace

std::vector<float> readOrComputeCached(const std::filesystem::path& path, int width, int height,
                                       const std::function<std::vector<float>()>& compute, bool* fromCache) {
  if (fromCache) *fromCache = true;
  if (auto cached = readValidEntry(path, width, height)) return std::move(*cached);
  std::optional<FileLock> lock;
  try {
    lock.emplace(std::filesystem::path(path.string() + ".lock"),
                 "the ground truth " + path.filename().string());
  } catch (const Error& e) {  // a read-only cache still serves what it holds; the image is computed here
    warn(std::string(e.what()) + "; computing the ground truth without sharing it");
  }
  // Another process may have stored it while this one waited for the lock.
  if (lock)
    if (auto cached = readValidEntry(path, width, height)) return std::move(*cached);
  if (fromCache) *fromCache = false;
  std::vector<float> rgb = compute();
  try {
    // Sealed and written under a temporary name, then renamed: a concurrent reader never sees half a file.
    writeReferenceCacheFile(path, width, height, rgb);
  } catch (const std::exception& e) {
    warn("cannot store the ground truth in the cache: " + std::string(e.what()));
  }
  return rgb;
}

}  // namespace iblx
