// glslang info logs as one-line messages (engine/vk/glsl_messages.h).
#include "engine/vk/glsl_messages.h"

#include <sstream>
#include <vector>

namespace iblx {

std::string formatGlslLog(const std::string& infoLog, const std::string& context) {
  std::vector<std::string> errors;
  std::istringstream lines(infoLog);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("ERROR: ", 0) != 0) continue;
    line.erase(0, 7);
    // glslang's summary ("2 compilation errors.  No code generated.") names no file.
    if (line.find("compilation error") != std::string::npos ||
        line.find("No code generated") != std::string::npos)
      continue;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    errors.push_back(line);
  }
  if (errors.empty()) {
    std::string text = infoLog;
    for (char& c : text)
      if (c == '\n') c = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return "GLSL compile error in " + context + ": " + text;
  }
  std::string message = errors.front() + " (GLSL compile error in " + context + ")";
  if (errors.size() > 1)
    message +=
        "; " + std::to_string(errors.size() - 1) + (errors.size() == 2 ? " more error" : " more errors");
  return message;
}

}  // namespace iblx
