// Test helpers for file I/O: a private temporary directory, raw byte access, warning capture and error text.
#pragma once

#include "engine/core/error.h"
#include "engine/core/log.h"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace iblx::test {

// A fresh directory under temp_directory_path(), removed with everything in it when the object dies.
class ScratchDir {
 public:
  ScratchDir() {
    std::random_device device;
    const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
    for (int attempt = 0; attempt < 100; ++attempt) {
      const auto name = "iblx_io_test_" + std::to_string(now) + "_" + std::to_string(device());
      dir_ = std::filesystem::temp_directory_path() / name;
      if (std::filesystem::create_directory(dir_)) return;
    }
    throw std::runtime_error("cannot create a scratch directory");
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  std::filesystem::path file(const std::string& name) const { return dir_ / name; }

 private:
  std::filesystem::path dir_;
};

inline std::vector<unsigned char> readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void writeBytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Fixed-seed pseudo-random bytes, so a failing "random file" test can be replayed.
inline std::vector<unsigned char> randomBytes(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<unsigned char> bytes(count);
  for (auto& b : bytes) b = static_cast<unsigned char>(rng() & 0xff);
  return bytes;
}

// Collects iblx::warn messages for the lifetime of the object.
class WarningCapture {
 public:
  WarningCapture() {
    previous_ = setWarningSink([this](const std::string& m) { messages.push_back(m); });
  }
  ~WarningCapture() { setWarningSink(previous_); }
  WarningCapture(const WarningCapture&) = delete;
  WarningCapture& operator=(const WarningCapture&) = delete;

  std::vector<std::string> messages;

 private:
  LogSink previous_;
};

// The message of the iblx::Error that f throws, or a marker when it throws something else or nothing.
template <typename F>
std::string errorMessage(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<not an iblx::Error: ") + e.what() + ">";
  } catch (...) {
    return "<unknown exception>";
  }
  return "<no exception>";
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace iblx::test
