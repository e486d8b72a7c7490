// Run-time GLSL -> SPIR-V compilation with glslang, resolving #include against the embedded shaders/ tree,
// with an on-disk SPIR-V cache keyed by the hash of the prelude, every shader source and the glslang version.
// Cache entries are sealed and written atomically (engine/core/cache_file.h); a damaged one is reported in a
// one-line warning naming it and compiled again.
//
//   ShaderCompiler compiler;
//   auto spirv = compiler.compile("#version 460\n...#include \"integrate.comp\"\n", "integrate");
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace iblx {

class ShaderCompiler {
 public:
  // cacheDir empty: $IBLX_CACHE_DIR, else $XDG_CACHE_HOME/iblx, else ~/.cache/iblx; "-" disables the cache.
  explicit ShaderCompiler(std::filesystem::path cacheDir = {});

  // Adds or replaces a source visible to #include (tests add their probe kernels this way).
  void addSource(const std::string& path, std::string text);

  // Compiles a compute shader whose text is `prelude` (which #includes the kernel and its parts).
  // Throws iblx::Error with glslang's log (file:line of the part) on failure.
  std::vector<uint32_t> compile(const std::string& prelude, const std::string& debugName);

  int cacheHits() const { return cacheHits_; }
  int compilations() const { return compilations_; }

 private:
  std::map<std::string, std::string> sources_;
  std::filesystem::path cacheDir_;
  uint64_t sourcesHash_ = 0;
  int cacheHits_ = 0;
  int compilations_ = 0;
};

}  // namespace iblx
