// Files of the on-disk cache (SPIR-V, OT maps, ground truths): sealed with a checksum, written atomically and
// read back with every check an input gets, so that parallel runs sharing $IBLX_CACHE_DIR never read a
// half-written entry and a damaged one (truncated, bit-flipped, foreign) is detected, reported and rebuilt.
//
// A sealed file is its payload followed by the 64-bit FNV-1a hash (engine/core/hash.h) of the payload, as 8
// little-endian bytes. FNV-1a is not cryptographic: it guards against torn writes and bit rot, not attacks.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace iblx {

// The payload of a sealed file's bytes; throws Error("REASON") (no file name: callers add it) when the bytes
// are too short to hold a seal or the seal does not match.
std::vector<unsigned char> unsealCacheBytes(std::span<const unsigned char> sealed);
// payload || FNV-1a(payload).
std::vector<unsigned char> sealCacheBytes(std::span<const unsigned char> payload);

// Reads a sealed file of at most maxBytes (seal included) and returns its payload. Throws Error("PATH:
// REASON") for a file that is not a regular file, too large, unreadable, torn or bit-flipped.
std::vector<unsigned char> readSealedCacheFile(const std::filesystem::path& path, std::uint64_t maxBytes);
// Writes payload || seal to path atomically (a temporary beside it, then a rename; engine/core/file_io.h),
// creating the directory. Throws Error("cannot write PATH: REASON").
void writeSealedCacheFile(const std::filesystem::path& path, std::span<const unsigned char> payload);

// SPIR-V cache entries (engine/vk/shader_compiler.cpp): a sealed file whose payload is the module's words.
// The module's words from a payload; throws Error("REASON") unless it is a whole number of 32-bit words,
// starts with a SPIR-V header (magic 0x07230203, a version 1.0 to 1.6, a nonzero id bound, schema 0) and
// holds at least one instruction, with every instruction's word count inside the module.
std::vector<std::uint32_t> decodeSpirvCachePayload(std::span<const unsigned char> payload);
// The largest SPIR-V cache file read (the project's largest kernels are a few hundred KiB).
inline constexpr std::uint64_t kMaxSpirvCacheBytes = 64ull << 20;
// readSealedCacheFile + decodeSpirvCachePayload; errors name the file.
std::vector<std::uint32_t> readSpirvCacheFile(const std::filesystem::path& path);
void writeSpirvCacheFile(const std::filesystem::path& path, std::span<const std::uint32_t> words);

}  // namespace iblx
