// glslang front end: an Includer over the embedded sources, SPIR-V generation, and the on-disk cache.
#include "engine/vk/shader_compiler.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"
#include "engine/vk/embedded_shaders.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <random>
#include <unistd.h>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>

namespace iblx {
namespace {

std::once_flag gGlslangInit;

class EmbeddedIncluder : public glslang::TShader::Includer {
 public:
  explicit EmbeddedIncluder(const std::map<std::string, std::string>& sources) : sources_(sources) {}

  IncludeResult* includeLocal(const char* headerName, const char*, size_t) override {
    return find(headerName);
  }
  IncludeResult* includeSystem(const char* headerName, const char*, size_t) override {
    return find(headerName);
  }
  void releaseInclude(IncludeResult* result) override { delete result; }

 private:
  IncludeResult* find(const std::string& name) {
    auto it = sources_.find(name);
    if (it == sources_.end()) return nullptr;  // glslang reports "Could not process include directive"
    // glslang's interface hands ownership back through releaseInclude, so a raw new is unavoidable here.
    return new IncludeResult(it->first, it->second.data(), it->second.size(), nullptr);
  }
  const std::map<std::string, std::string>& sources_;
};

}  // namespace

ShaderCompiler::ShaderCompiler(std::filesystem::path cacheDir) {
  std::call_once(gGlslangInit, [] { glslang::InitializeProcess(); });
  for (const auto& shader : embeddedShaders()) sources_[std::string(shader.path)] = std::string(shader.text);
  cacheDir_ = cacheDir.empty() ? defaultCacheDir() : cacheDir == "-" ? std::filesystem::path() : cacheDir;
}

void ShaderCompiler::addSource(const std::string& path, std::string text) {
  sources_[path] = std::move(text);
}

std::vector<uint32_t> ShaderCompiler::compile(const std::string& prelude, const std::string& debugName) {
  // Hashing every source (not only those included) over-invalidates a little but can never serve stale
  // SPIR-V.
  ContentHash hash;
  hash.add(prelude).add(glslang::GetGlslVersionString()).add("spv1.5-vk1.2");
  for (const auto& [path, text] : sources_) hash.add(path).add(text);
  const std::filesystem::path cacheFile =
      cacheDir_.empty() ? std::filesystem::path() : cacheDir_ / "spirv" / (hexKey(hash.value()) + ".spv");

  if (!cacheFile.empty()) {
    std::ifstream in(cacheFile, std::ios::binary);
    if (in) {
      // Layout: SPIR-V words, then the 64-bit content hash of those words (a torn or foreign file is
      // ignored).
      std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
      if (bytes.size() > 8 && (bytes.size() - 8) % 4 == 0) {
        std::vector<uint32_t> words((bytes.size() - 8) / 4);
        std::memcpy(words.data(), bytes.data(), bytes.size() - 8);
        uint64_t stored = 0;
        std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
        if (words[0] == 0x07230203u &&
            stored == ContentHash().add(std::span<const uint32_t>(words)).value()) {
          ++cacheHits_;
          return words;
        }
      }
    }
  }

  ++compilations_;
  glslang::TShader shader(EShLangCompute);
  const char* strings[] = {prelude.c_str()};
  const std::string preludeName = "<" + debugName + " prelude>";
  const char* names[] = {preludeName.c_str()};
  shader.setStringsWithLengthsAndNames(strings, nullptr, names, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
  EmbeddedIncluder includer(sources_);
  if (!shader.parse(GetDefaultResources(), 460, false, messages, includer))
    throw Error("GLSL compile error in " + debugName + ":\n" + shader.getInfoLog());
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) throw Error("GLSL link error in " + debugName + ":\n" + program.getInfoLog());

  std::vector<uint32_t> spirv;
  glslang::SpvOptions options;
  options.disableOptimizer = false;
  options.optimizeSize = false;
  glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);

  if (!cacheFile.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(cacheFile.parent_path(), ec);
    // A name unique to this process and call, then an atomic rename: concurrent compilers never see a torn
    // file.
    static std::atomic<uint64_t> counter{0};
    const auto temp = cacheFile.string() + ".tmp." + std::to_string(::getpid()) + "." +
                      std::to_string(counter++) + "." + std::to_string(std::random_device{}());
    std::ofstream out(temp, std::ios::binary);
    out.write(reinterpret_cast<const char*>(spirv.data()), std::streamsize(spirv.size() * 4));
    const uint64_t check = ContentHash().add(std::span<const uint32_t>(spirv)).value();
    out.write(reinterpret_cast<const char*>(&check), sizeof check);
    out.close();
    if (out) std::filesystem::rename(temp, cacheFile, ec);
    if (!out || ec) {
      std::filesystem::remove(temp, ec);
      static bool warned = false;
      if (!warned)
        warn("cannot write the SPIR-V cache in " + cacheDir_.string() + "; shaders will be recompiled");
      warned = true;
    }
  }
  return spirv;
}

}  // namespace iblx
