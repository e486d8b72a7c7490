// glslang front end: an Includer over the embedded sources, SPIR-V generation, and the on-disk cache.
#include "engine/vk/shader_compiler.h"

#include "engine/core/cache_dir.h"
#include "engine/core/cache_file.h"
#include "engine/core/environment.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/large_stack.h"
#include "engine/core/log.h"
#include "engine/vk/embedded_shaders.h"
#include "engine/vk/glsl_messages.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>

namespace iblx {
namespace {

// How long glslang may take for one kernel: 300 s, or $IBLX_COMPILE_TIMEOUT_S. The .brdf limits keep real
// compiles far below it, even for a file at the 256 KiB size limit (10 000 constants).
double compileTimeoutSeconds() {
  return environmentNumber("IBLX_COMPILE_TIMEOUT_S", 300.0, 1e7);
}

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
    std::error_code ec;
    if (std::filesystem::exists(cacheFile, ec)) {
      // A sealed entry (engine/core/cache_file.h) whose words are checked as SPIR-V: a torn, damaged or
      // foreign file is reported and compiled again, never handed to the driver.
      try {
        std::vector<uint32_t> words = readSpirvCacheFile(cacheFile);
        ++cacheHits_;
        return words;
      } catch (const Error& e) {
        warn("ignoring the cached SPIR-V " + std::string(e.what()) + "; compiling it again");
      }
    }
  }

  ++compilations_;
  std::vector<uint32_t> spirv;
  // glslang recurses per operator and nesting level; on a thread with a 256 MiB stack (reserved, touched only
  // as used) a pathological .brdf that passed the parser's limits still cannot overflow the process's stack.
  const double timeout = compileTimeoutSeconds();
  runWithStack(
      std::size_t(256) << 20,
      [&] {
        glslang::TShader shader(EShLangCompute);
        const char* strings[] = {prelude.c_str()};
        // glslang writes this name into #line directives around includes, where a quote, backslash or control
        // character (from a file name) would end the string early.
        std::string preludeName = "<" + debugName + " prelude>";
        for (char& c : preludeName)
          if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20) c = '?';
        const char* names[] = {preludeName.c_str()};
        shader.setStringsWithLengthsAndNames(strings, nullptr, names, 1);
        shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
        shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
        shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
        const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
        EmbeddedIncluder includer(sources_);
        if (!shader.parse(GetDefaultResources(), 460, false, messages, includer))
          throw Error(formatGlslLog(shader.getInfoLog(), debugName));
        glslang::TProgram program;
        program.addShader(&shader);
        if (!program.link(messages)) throw Error(formatGlslLog(program.getInfoLog(), debugName + " (link)"));
        glslang::SpvOptions options;
        options.disableOptimizer = false;
        options.optimizeSize = false;
        glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
      },
      timeout,
      [&] {
        std::fprintf(stderr,
                     "iblx: error: compiling %s took more than %.3g s (IBLX_COMPILE_TIMEOUT_S sets the "
                     "limit); a .brdf "
                     "too large for the GLSL compiler?\n",
                     debugName.c_str(), timeout);
      });

  if (!cacheFile.empty()) {
    // Sealed, under a temporary name unique to this process and call, then renamed: concurrent compilers
    // never see a torn file.
    try {
      writeSpirvCacheFile(cacheFile, spirv);
    } catch (const Error& e) {
      static std::atomic<bool> warned{false};
      if (!warned.exchange(true))
        warn(std::string(e.what()) + "; the SPIR-V cache in " + cacheDir_.string() +
             " is not written, shaders will be recompiled");
    }
  }
  return spirv;
}

}  // namespace iblx
