// Every --json output and JSON summary of iblx is written here, through Debian's nlohmann-json: strings are
// escaped by the library, NaN and Inf (which JSON has not) become null and are counted, and objects keep their
// keys in insertion order, one object per line in the style {"key": value, ...} that the tools' scripts read.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace iblx {

using JsonObject = nlohmann::ordered_json;

// One line of JSON (no trailing newline). `nonFinite`, when given, is increased by the number of NaN or
// infinite numbers written as null.
std::string formatJson(const JsonObject& value, std::size_t* nonFinite = nullptr);

// Prints formatJson(value) and a newline to standard output; NaN/Inf figures are reported in one warning.
void printJsonLine(const JsonObject& value);

}  // namespace iblx
