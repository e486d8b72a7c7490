// Ground-truth images in the on-disk cache (engine/render/reference.h, cachedReference): an OpenEXR file
// sealed with a checksum (engine/core/cache_file.h), so a torn or bit-flipped entry is never served, and
// validated like any input: the size the scene expects and every value finite (a ground truth holding NaN or
// Inf would make every error measured against it meaningless).
#pragma once

#include <filesystem>
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

}  // namespace iblx
