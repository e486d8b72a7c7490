// What the commands share beyond their flags: checks of output paths before any work, the ground truth of
// --reference-file, the warning for non-finite estimates, and progress lines on a terminal.
#pragma once

#include "engine/core/file_io.h"
#include "engine/core/file_lock.h"
#include "engine/scene/scene.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace iblx::cli {

// Fails early (before any rendering) when an output path cannot be written as an image.
void checkImagePath(const std::string& flag, const std::string& path, bool exrOnly = false);
// --out of a tabulation command: ends in `extension` (a `kind` file must...) in a directory that exists.
void checkTableOutput(const std::string& out, const std::string& extension, const std::string& kind);
// The scene a tabulation command evaluates `brdf` in: one pixel, no light (only the BRDF's part runs).
Scene tabulationScene(SceneSpec spec, LoadedBrdf brdf);
// The ground truth of --reference-file (an EXR of `iblx reference`): W x H RGB, every value finite. Errors
// name the flag and file; a size mismatch says "does not match <sizeName> WxH".
std::vector<float> readReferenceFile(const std::filesystem::path& path, int width, int height,
                                     const std::string& sizeName);
// The warning for estimates the GPU replaced by 0 because they were NaN or Inf: with a built-in BRDF that is
// a sampler bug, but a BRDF read from any file can hold values whose products overflow float.
std::string nonFiniteEstimatesMessage(std::uint64_t count, const std::string& brdfArgument);

// Progress line on stderr, only when stderr is a terminal.
void progressLine(const std::string& text);
void endProgressLine();

// An --out-dir that can be made and written, checked without making it: before a ground truth and runs that
// take long, so that an unusable one is reported first and bad input leaves no directory behind.
void checkOutDir(const std::filesystem::path& outDir);
// Creates --out-dir and holds it while the command writes it: a second converge or hardcases writing the same
// directory meanwhile is refused (their files would mix). Throws Error naming the directory.
FileLock claimOutDir(const std::filesystem::path& outDir);
}  // namespace iblx::cli
