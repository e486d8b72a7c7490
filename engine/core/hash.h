// 64-bit FNV-1a content hash for cache keys (SPIR-V, sampling tables). Not cryptographic.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace iblx {

class ContentHash {
 public:
  ContentHash& add(std::string_view bytes) { return addBytes(bytes.data(), bytes.size()); }
  template <typename T>
  ContentHash& add(std::span<const T> values) {
    return addBytes(values.data(), values.size_bytes());
  }
  ContentHash& addBytes(const void* data, std::size_t size) {
    auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) state_ = (state_ ^ p[i]) * 0x100000001b3ull;
    return *this;
  }
  std::uint64_t value() const { return state_; }

 private:
  std::uint64_t state_ = 0xcbf29ce484222325ull;
};

}  // namespace iblx
