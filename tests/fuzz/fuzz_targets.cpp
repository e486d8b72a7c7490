// The registry of fuzz targets and the scratch files they read (tests/fuzz/fuzz_target.h).
#include "tests/fuzz/fuzz_target.h"

#include "tests/fuzz/cpu_targets.h"
#ifdef IBLX_FUZZ_HAS_GLSLANG
#include "tests/fuzz/glsl_targets.h"
#endif

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace iblx::fuzz {

namespace {

std::vector<FuzzTarget> allTargets() {
  std::vector<FuzzTarget> targets = cpuFuzzTargets();
#ifdef IBLX_FUZZ_HAS_GLSLANG
  for (const FuzzTarget& t : glslFuzzTargets()) targets.push_back(t);
#endif
  return targets;
}

// Removes the scratch directory when the process ends normally (a crash leaves it for inspection).
struct ScratchDirectory {
  std::filesystem::path path;
  ScratchDirectory() {
    path = std::filesystem::temp_directory_path() / ("iblx-fuzz-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDirectory() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

}  // namespace

std::span<const FuzzTarget> fuzzTargets() {
  static const std::vector<FuzzTarget> targets = allTargets();
  return targets;
}

const FuzzTarget* findFuzzTarget(std::string_view name) {
  for (const FuzzTarget& t : fuzzTargets())
    if (t.name == name) return &t;
  return nullptr;
}

const std::filesystem::path& scratchDirectory() {
  static const ScratchDirectory directory;
  return directory.path;
}

std::filesystem::path writeScratchFile(const std::string& name, std::span<const std::uint8_t> bytes) {
  const std::filesystem::path path = scratchDirectory() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  out.close();
  // Not an iblx::Error: a scratch file that cannot be written is the harness's failure, not the reader's.
  if (!out) throw std::runtime_error("cannot write the fuzz scratch file " + path.string());
  return path;
}

}  // namespace iblx::fuzz
