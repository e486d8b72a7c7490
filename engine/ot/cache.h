// On-disk cache of OT maps (engine/ot/solver.h): a 1024^2 map takes seconds to minutes to solve and
// depends only on the density, n and the solver options, so it is solved once and read back afterwards.
//
// Entries live in the shared cache directory (engine/core/cache_dir.h) as `cacheDir`/otmaps/<key>.otmap, the
// key being a 64-bit FNV-1a hash (engine/core/hash.h) of the cache format version, the density's bytes, n and
// every option that changes the result (not `threads` or `progress`). A file that is missing, truncated,
// corrupt or written for another key is ignored with a one-line warning naming it, and the map is solved
// again and stored; a cache that cannot be written only warns.
#pragma once

#include "engine/ot/solver.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>

namespace iblx {

// The cache key of a solve (see above).
std::uint64_t otMapCacheKey(std::span<const double> density, int n, const OtSolverOptions& options);

// Where the entry of `key` lives under `cacheDir`.
std::filesystem::path otMapCachePath(const std::filesystem::path& cacheDir, std::uint64_t key);

// Reads and validates one cache file: the seal (engine/core/cache_file.h), the header, the exact size, the
// statistics and every value (finite; density positive). key and n, when given, must match the header's.
// Throws Error("PATH: PROBLEM"). solveOtMapCached reads entries this way; the fuzz harness drives it
// directly.
OtMap readOtMapCacheFile(const std::filesystem::path& path, std::optional<std::uint64_t> key = {},
                         std::optional<int> n = {});

// solveOtMap through the cache: the stored map (with the statistics of the solve that produced it, including
// its `seconds`) when `cacheDir`/otmaps holds a valid entry (fromCache set), else a new solve, stored there
// by an atomic rename. An empty cacheDir solves without caching. Throws as solveOtMap does on bad input.
OtMap solveOtMapCached(std::span<const double> density, int n, const OtSolverOptions& options,
                       const std::filesystem::path& cacheDir, bool* fromCache = nullptr);

}  // namespace iblx
