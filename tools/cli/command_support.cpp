// What the commands share beyond their flags (command_support.h): output checks, the reference file, the
// non-finite-estimates warning and progress lines.
#include "tools/cli/command_support.h"

#include "engine/core/error.h"
#include "engine/core/file_lock.h"
#include "engine/core/file_names.h"
#include "engine/io/env_image.h"
#include "engine/vk/context.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstring>
#include <cerrno>
#include <unistd.h>

namespace iblx::cli {

void checkTableOutput(const std::string& out, const std::string& extension, const std::string& kind) {
  if (std::filesystem::path(out).extension() != extension)
    throw Error("--out " + out + ": " + kind + " files must end in " + extension);
  const auto outDir = std::filesystem::path(out).parent_path();
  if (!outDir.empty() && !std::filesystem::is_directory(outDir))
    throw Error("--out " + out + ": directory " + outDir.string() + " does not exist");
}

Scene tabulationScene(SceneSpec spec, LoadedBrdf brdf) {
  spec.width = spec.height = 1;
  return makeScene(EnvImage{2, 1, std::vector<float>(6, 0.0f)}, spec, std::move(brdf));
}

void checkImagePath(const std::string& flag, const std::string& path, bool exrOnly) {
  std::filesystem::path p(path);
  const std::string ext = lowerExtension(p);
  if (ext != ".exr" && (exrOnly || ext != ".png"))
    throw Error(flag + " " + path + ": unsupported image format '" + ext + "'; use " +
                (exrOnly ? ".exr" : ".exr or .png"));
  const auto parent = p.parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    throw Error(flag + " " + path + ": directory '" + parent.string() + "' does not exist");
}

std::vector<float> readReferenceFile(const std::filesystem::path& path, int width, int height,
                                     const std::string& sizeName) {
  EnvImage image;
  try {
    image = loadRgbImage(path);
  } catch (const Error& e) {
    throw Error(std::string("--reference-file: ") + e.what());
  }
  if (image.width != width || image.height != height)
    throw Error("--reference-file " + path.string() + ": " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + " does not match " + sizeName + " " + std::to_string(width) +
                "x" + std::to_string(height));
  for (float v : image.rgb)
    if (!std::isfinite(v)) throw Error("--reference-file " + path.string() + ": contains NaN or Inf values");
  return std::move(image.rgb);
}

std::string nonFiniteEstimatesMessage(std::uint64_t count, const std::string& brdfArgument) {
  // Any BRDF read from a file (a .brdf program, an RGL-EPFL material, an ALTA function) can hold values whose
  // products overflow float; only the built-in BRDFs, named without an extension, cannot.
  const bool fromFile = !lowerExtension(brdfArgument).empty();
  return std::to_string(count) + " NaN/Inf sample estimates were replaced by 0 (" +
         (fromFile ? brdfArgument + " may return values beyond float range; otherwise a sampler bug"
                   : "a sampler bug: please report it") +
         ")";
}

void progressLine(const std::string& text) {
  if (isatty(STDERR_FILENO)) std::fprintf(stderr, "\r%s\x1b[K", text.c_str());
}

void endProgressLine() {
  if (isatty(STDERR_FILENO)) std::fprintf(stderr, "\r\x1b[K");
}

// Whether the output directory can be made and written, without making it: checked before the ground truth
// and the runs, which can take long, so that an unusable --out-dir is reported first (and bad input leaves no
// directory behind).
void checkOutDir(const std::filesystem::path& outDir) {
  std::error_code ec;
  std::filesystem::path existing = std::filesystem::absolute(outDir, ec);
  while (!existing.empty() && !std::filesystem::exists(existing, ec) && existing != existing.parent_path())
    existing = existing.parent_path();
  if (!std::filesystem::is_directory(existing, ec))
    throw Error("--out-dir " + outDir.string() + ": cannot create it: " + existing.string() +
                " is not a directory");
  if (::access(existing.c_str(), W_OK) != 0)
    throw Error("--out-dir " + outDir.string() + ": cannot write in " + existing.string() + ": " +
                std::strerror(errno));
}

// Creates the output directory and holds it for this run: a second converge or hardcases writing the same
// directory is refused (their CSV, summary and report would mix).
FileLock claimOutDir(const std::filesystem::path& outDir) {
  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (!std::filesystem::is_directory(outDir))
    throw Error("--out-dir " + outDir.string() + ": cannot create it" + (ec ? ": " + ec.message() : ""));
  return FileLock(outDir, "--out-dir " + outDir.string(), LockBusy::Refuse);
}

}  // namespace iblx::cli
