// Sealed, atomically written cache files (engine/core/cache_file.h).
#include "engine/core/cache_file.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

#include <cstring>
#include <fstream>
#include <string>

namespace iblx {

namespace {

constexpr std::size_t kSealBytes = 8;

std::uint64_t payloadHash(std::span<const unsigned char> payload) {
  return ContentHash().addBytes(payload.data(), payload.size()).value();
}

void putLittleEndian(unsigned char* out, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<unsigned char>(value >> (8 * i));
}

std::uint64_t getLittleEndian(const unsigned char* in) {
  std::uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value |= std::uint64_t(in[i]) << (8 * i);
  return value;
}

}  // namespace

std::vector<unsigned char> unsealCacheBytes(std::span<const unsigned char> sealed) {
  if (sealed.size() < kSealBytes)
    throw Error("truncated (" + std::to_string(sealed.size()) + " bytes, no room for its checksum)");
  const auto payload = sealed.first(sealed.size() - kSealBytes);
  if (getLittleEndian(sealed.data() + payload.size()) != payloadHash(payload))
    throw Error("checksum mismatch (torn or damaged file)");
  return {payload.begin(), payload.end()};
}

std::vector<unsigned char> sealCacheBytes(std::span<const unsigned char> payload) {
  std::vector<unsigned char> sealed(payload.begin(), payload.end());
  unsigned char seal[kSealBytes];
  putLittleEndian(seal, payloadHash(payload));
  sealed.insert(sealed.end(), seal, seal + kSealBytes);
  return sealed;
}

std::vector<unsigned char> readSealedCacheFile(const std::filesystem::path& path, std::uint64_t maxBytes) {
  const std::vector<unsigned char> bytes = readInputFile(path, maxBytes);
  try {
    return unsealCacheBytes(bytes);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

void writeSealedCacheFile(const std::filesystem::path& path, std::span<const unsigned char> payload) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) throw Error("cannot write " + path.string() + ": " + ec.message());
  writeFileAtomically(path, sealCacheBytes(payload));
}

std::vector<std::uint32_t> decodeSpirvCachePayload(std::span<const unsigned char> payload) {
  constexpr std::size_t kHeaderWords = 5;
  if (payload.size() % 4 != 0)
    throw Error("not SPIR-V: " + std::to_string(payload.size()) + " bytes is not a whole number of words");
  std::vector<std::uint32_t> words(payload.size() / 4);
  if (!payload.empty()) std::memcpy(words.data(), payload.data(), payload.size());
  if (words.size() <= kHeaderWords) throw Error("not SPIR-V: no instructions after the header");
  if (words[0] != 0x07230203u) throw Error("not SPIR-V: bad magic number");
  // Version word: 0 | major | minor | 0, major 1, minor 0 to 6.
  const std::uint32_t version = words[1];
  if ((version & 0xff0000ffu) != 0 || ((version >> 16) & 0xffu) != 1 || ((version >> 8) & 0xffu) > 6)
    throw Error("not SPIR-V: unknown version word");
  if (words[3] == 0) throw Error("not SPIR-V: id bound 0");
  if (words[4] != 0) throw Error("not SPIR-V: nonzero schema");
  // Every instruction's first word holds its word count in the high half: they must tile the module exactly.
  for (std::size_t at = kHeaderWords; at < words.size();) {
    const std::uint32_t count = words[at] >> 16;
    if (count == 0 || count > words.size() - at)
      throw Error("not SPIR-V: instruction at word " + std::to_string(at) + " has a bad word count");
    at += count;
  }
  return words;
}

std::vector<std::uint32_t> readSpirvCacheFile(const std::filesystem::path& path) {
  const std::vector<unsigned char> payload = readSealedCacheFile(path, kMaxSpirvCacheBytes);
  try {
    return decodeSpirvCachePayload(payload);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

void writeSpirvCacheFile(const std::filesystem::path& path, std::span<const std::uint32_t> words) {
  writeSealedCacheFile(path,
                       std::span(reinterpret_cast<const unsigned char*>(words.data()), words.size() * 4));
}

}  // namespace iblx
