// Error types and the programmer-error assertion used throughout iblx.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace iblx {

// Something a user can fix (a bad file, flag or device): the message names the culprit and the fix.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// The scene needs more than the Vulkan device offers (e.g. a storage buffer larger than
// maxStorageBufferRange): nothing is wrong with the input, and another device may run it.
class DeviceLimitError : public Error {
 public:
  using Error::Error;
};

// The user interrupted a long computation (Ctrl-C): commands exit with status 130 after keeping what is
// complete.
class Interrupted : public Error {
 public:
  using Error::Error;
};

// Text from a file, as a message may quote it: printable ASCII as is, every other byte (a NUL, a control
// character, a byte of a binary file) as \xNN, and at most maxLength characters of the original, then "...".
// A message holding it stays one line that a terminal prints as written.
std::string printableExcerpt(std::string_view text, std::size_t maxLength = 64);

[[noreturn]] void assertionFailed(const char* expression, const char* file, int line);

}  // namespace iblx

#ifdef NDEBUG
#define IBLX_ASSERT(expr) ((void)0)
#else
#define IBLX_ASSERT(expr) ((expr) ? (void)0 : ::iblx::assertionFailed(#expr, __FILE__, __LINE__))
#endif
