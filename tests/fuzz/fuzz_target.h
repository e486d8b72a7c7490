// The fuzz targets of iblx: one per file reader, each driving the reading function directly (no Vulkan
// device). A target's run() treats iblx::Error as the expected outcome of bad input and lets it escape;
// anything else escaping (another exception type, a crash, a sanitizer report, a hang) is a finding.
//
// Two drivers use the same registry: iblx_fuzz (fuzz_runner.cpp), a deterministic mutation runner that any
// compiler builds and ctest runs for a short fixed-seed run, and iblx_libfuzzer (libfuzzer_main.cpp), built
// with clang's -fsanitize=fuzzer by tools/fuzz.sh for long coverage-guided runs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace iblx::fuzz {

using Bytes = std::vector<std::uint8_t>;

struct FuzzTarget {
  std::string_view name;
  std::string_view description;
  // Reads one input; throws iblx::Error when the reader rejects it.
  void (*run)(std::span<const std::uint8_t> input);
  // Valid (and a few deliberately broken) inputs generated in code: the corpus mutations start from.
  std::vector<Bytes> (*seeds)();
  // The runner's iterations are divided by this: a MERL input may expand to a 35 MB file, a GLSL input
  // runs the whole glslang front end.
  double relativeCost = 1.0;
};

// Every target this build has (the GLSL compiler's only when the build has glslang, i.e. not IBLX_CPU_ONLY).
std::span<const FuzzTarget> fuzzTargets();
const FuzzTarget* findFuzzTarget(std::string_view name);

// A private directory for the files the readers take by path, made on first use and removed at exit, and a
// file in it holding `bytes` (readers that dispatch on the extension get the name they need).
const std::filesystem::path& scratchDirectory();
std::filesystem::path writeScratchFile(const std::string& name, std::span<const std::uint8_t> bytes);

// Cache-file targets: input byte 0 chooses whether the rest is sealed again (odd) before it is read, so that
// mutations reach the validation behind the checksum, or read as it is (even), to test the seal itself.
Bytes sealedCacheInput(std::span<const std::uint8_t> input);

}  // namespace iblx::fuzz
