// BRDF Explorer's analytic BRDF files (.brdf) and saved parameter sets (.bparam), with its exact grammar
// (BRDF Explorer's reader, github.com/wdas/brdf BRDFBase::loadBRDF and BRDFAnalytic): the first kept line is
// `analytic` or `bparam <path>`;
// `::begin NAME` / `::end NAME` sections that do not nest; blank lines and lines whose first non-blank
// character is '#' are dropped everywhere, even inside the shader; parameter lines are
// `float NAME MIN MAX DEFAULT`, `bool NAME 0|1` and `color NAME R G B`. Turning the GLSL into a part is
// engine/scene/analytic_brdf.cpp's job; this file only reads and writes text.
#pragma once

#include "engine/core/params.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace iblx {

// The kept lines of a GLSL section (untrimmed, as BRDF Explorer keeps them) with their 1-based line numbers
// in the file, so compile errors can name the file's own lines.
struct BrdfFileSection {
  std::vector<std::string> lines;
  std::vector<int> lineNumbers;
  bool empty() const { return lines.empty(); }
};

struct BrdfFileParam {
  ParamDecl decl;  // colors range over [0, 1] (BRDF Explorer has no bounds for them); bools over {0, 1}
  int line = 0;
};

struct BrdfFile {
  enum class Kind { Analytic, Bparam };
  Kind kind = Kind::Analytic;
  std::string displayName;  // the path as given, used in every message
  std::vector<BrdfFileParam> params;
  BrdfFileSection shader, isFunc;
  // Kind::Bparam: the BRDF file named on the first line, resolved (absolute as is; relative first against the
  // .bparam's folder, then the working directory); `params` then hold the saved values as defaults.
  std::filesystem::path bparamSource;
};

// Limits on a file that is a program handed to the GPU compiler, checked before it is compiled: BRDF
// Explorer's own files are under 20 KiB, with under 20 parameters and short expressions.
inline constexpr std::uint64_t kMaxBrdfFileBytes = 256 * 1024;
inline constexpr std::size_t kMaxBrdfParams = 256;
inline constexpr std::size_t kMaxBrdfStatementOperators = 2000;  // operators between two ';', '{' or '}'
inline constexpr int kMaxBrdfNesting = 64;                       // ( [ { levels

// Reads and parses a .brdf or .bparam file. Throws iblx::Error as "FILE:LINE: problem" for a malformed file
// (unknown first line, unknown parameter type, bad numbers, nested, unterminated or mismatched sections,
// duplicate or invalid parameter names, a .brdf without a shader section) and "FILE: problem" when it cannot
// be read, or exceeds a limit above. An unknown section is skipped with a warning, as BRDF Explorer does.
BrdfFile readBrdfFile(const std::filesystem::path& path);
// The same on text already in memory; `displayName` names it in messages.
BrdfFile parseBrdfText(std::string_view text, const std::string& displayName,
                       const std::filesystem::path& folder = {});

// The .bparam text for `source` with the given values (BRDF Explorer's layout, numbers with 9 significant
// digits so a round trip keeps float values exactly), and writing it to a file.
std::string formatBparam(const std::filesystem::path& source, std::span<const ParamDecl> params,
                         const ParamValues& values);
void writeBparam(const std::filesystem::path& out, const std::filesystem::path& source,
                 std::span<const ParamDecl> params, const ParamValues& values);

}  // namespace iblx
