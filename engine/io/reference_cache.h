// Ground-truth images in the on-disk cache (engine/render/reference.h, cachedReference): an OpenEXR file
// sealed with a checksum (engine/core/cache_file.h), so a torn or bit-flipped entry is never served, and
// validated like any input: the size the scene expects and every value finite (a ground truth holding NaN or
// Inf would make every error measured against it meaningless).
#pragma once

#include <filesystem>
#include <functional>
#include <span>
#include <vector>

namespace iblx {

// The cached image at path (width*height*3 floats), or Error("PATH: PROBLEM") when the file is missing,
// unreadable, torn, damaged, another size than width x height, or holds a non-finite value.
std::vector<float> readReferenceCacheFile(const std::filesystem::path& path, int width, int height);

// Writes a ground truth atomically (temporary + rename) and sealed. Throws Error naming the file when it
// cannot be written, or when the image holds a non-finite value (such an image is not worth keeping).
void writeReferenceCacheFile(const std::filesystem::path& path, int width, int height,
                             std::span<const float> rgb);

// The image cached at path when there is a valid one (a damaged entry is reported and replaced), else
// compute()'s, stored there. Computing and storing hold a lock beside the entry (PATH.lock,
// engine/core/file_lock.h): processes that share the cache directory, on one machine or on the machines of
// a cluster, compute each ground truth once; the others wait and read it. `fromCache` says which happened.
std::vector<float> readOrComputeCached(const std::filesystem::path& path, int width, int height,
                                       const std::function<std::vector<float>()>& compute, bool* fromCache);

}  // namespace iblx
