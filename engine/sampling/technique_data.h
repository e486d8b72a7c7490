// What a technique's (or a table-driven BRDF's) builder hands to the GPU: named read-only tables of plain
// bytes and preprocessor definitions for its GLSL part (docs/DESIGN.md §2). A GLSL part declares each table it reads
// by the same name and element width, IBLX_TABLE(name, words) (shaders/lib/table.glsl); the kernel assembler
// (engine/scene/kernel_prelude.h) binds the tables in order and defines each one's set and binding under its
// name and width, so a part that reads a table its builder did not provide, or at another width, fails to
// compile with a message naming the table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

struct TechniqueTable {
  std::string name;         // the GLSL identifier its part declares, e.g. "envCdfGuide"
  std::uint32_t words = 1;  // 32-bit words per element: 1, 2 or 4 (R32 / R32G32 / R32G32B32A32_UINT views)
  std::vector<std::byte> bytes;
};

struct TechniqueData {
  std::vector<TechniqueTable> tables;  // in binding order
  // Sizes known at build time, so most loops over the tables have constant trip counts and unroll; part of
  // the SPIR-V cache key through the prelude.
  std::vector<std::pair<std::string, std::string>> defines;

  // The element width is the element type's: float and uint32 are 1 word, vec2 and uvec2 2, vec4 4.
  template <typename T>
  void add(std::string name, std::span<const T> values) {
    static_assert(sizeof(T) == 4 || sizeof(T) == 8 || sizeof(T) == 16,
                  "a table element is 1, 2 or 4 32-bit words (shaders/lib/table.glsl)");
    const auto* p = reinterpret_cast<const std::byte*>(values.data());
    tables.push_back({std::move(name), std::uint32_t(sizeof(T) / 4), {p, p + values.size_bytes()}});
  }
  template <typename T>
  void add(std::string name, const std::vector<T>& values) {
    add(std::move(name), std::span<const T>(values));
  }
  void define(std::string name, std::string value) {
    defines.emplace_back(std::move(name), std::move(value));
  }
  // An unsigned GLSL constant, e.g. define("ENV_HIER_WIDTH", 512u) -> "512u".
  void define(std::string name, std::uint32_t value) { define(std::move(name), std::to_string(value) + "u"); }
  // The tables' names and widths and the definitions, without the bytes: what a prelude needs once the tables
  // are uploaded.
  TechniqueData layout() const {
    TechniqueData copy;
    for (const TechniqueTable& table : tables) copy.tables.push_back({table.name, table.words, {}});
    copy.defines = defines;
    return copy;
  }
};

// Halvings a branch-free binary search over the intervals [0, n - 2] of n sorted entries takes: ceil(log2(n -
// 1)), 0 for n <= 2. GLSL parts that search with a compile-time trip count get it as a define (lavapipe caps
// the loop iterations of an invocation, so their searches must unroll).
inline std::uint32_t searchSteps(std::size_t n) {
  std::uint32_t k = 0;
  while (n > 2 && (std::size_t(1) << k) < n - 1) ++k;
  return k;
}

}  // namespace iblx
