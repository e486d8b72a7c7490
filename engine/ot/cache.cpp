// The on-disk OT map cache (engine/ot/cache.h).
//
// File layout (little-endian as written by this machine; a file from another byte order fails the magic/key
// checks and is re-solved):
//   8 bytes  magic "IBLXOTM\0"
//   u32      format version (kFormatVersion)
//   u32      n
//   u64      key (must equal the key the file is looked up by)
//   i32 iterations, i32 coarseIterations, f64 seconds, f64 l2, f64 l1, f64 linf, i32 foldedQuads,
//   i32 negativeAreaQuads, u32 converged (0 or 1)
//   f64[2 (n+1)^2] vertices (x, y), f64[n^2] density, f64[n^2] psi
//   u64      FNV-1a of every byte before it (the seal of engine/core/cache_file.h: a torn or bit-flipped file
//            is ignored)
#include "engine/ot/cache.h"

#include "engine/core/cache_dir.h"
#include "engine/core/cache_file.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace iblx {

namespace {

constexpr char kMagic[8] = {'I', 'B', 'L', 'X', 'O', 'T', 'M', '\0'};
// Bump when the file layout changes, so stale entries are never served. A change of the solver's output or of
// the options it takes bumps kOtSolverVersion (solver.h) instead, which the key hashes too.
constexpr std::uint32_t kFormatVersion = 1;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 4 + 4 + 8 * 4 + 4 + 4 + 4;

#if defined(__x86_64__) && defined(__GLIBCXX__)
// A new OtSolverOptions field usually changes this size (not always: padding may absorb a bool): add it to
// otMapCacheKey (or say why it does not change the result) and update the number.
static_assert(sizeof(OtSolverOptions) == 168, "OtSolverOptions changed: review otMapCacheKey");
// Likewise a new OtMap field must be stored (readEntry, writeEntry) and kFormatVersion bumped. (`levels`, the
// per-level diagnostics, is not stored: a cached map reports none.)
static_assert(sizeof(OtMap) == 160, "OtMap changed: review the file layout");
#endif

std::size_t payloadBytes(int n) {
  const std::size_t vertices = std::size_t(n + 1) * std::size_t(n + 1),
                    cells = std::size_t(n) * std::size_t(n);
  return 8 * (2 * vertices + 2 * cells);
}

template <typename T>
void hashField(ContentHash& hash, std::string_view name, T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  if constexpr (std::is_enum_v<T>) {
    const auto underlying = static_cast<std::int64_t>(value);
    hash.add(name).addBytes(&underlying, sizeof underlying);
  } else if constexpr (std::is_same_v<T, bool>) {
    const std::uint8_t byte = value ? 1 : 0;
    hash.add(name).addBytes(&byte, 1);
  } else {
    hash.add(name).addBytes(&value, sizeof value);
  }
}

// Fills a buffer of a size known in advance.
class ByteWriter {
 public:
  explicit ByteWriter(std::size_t size) : bytes_(size) {}
  template <typename T>
  void put(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    putBytes(&value, sizeof value);
  }
  void putBytes(const void* data, std::size_t size) {
    IBLX_ASSERT(size <= bytes_.size() - at_);
    std::memcpy(bytes_.data() + at_, data, size);
    at_ += size;
  }
  std::size_t written() const { return at_; }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
  std::size_t at_ = 0;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const unsigned char> bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    T value;
    getBytes(&value, sizeof value);
    return value;
  }
  void getBytes(void* data, std::size_t size) {
    if (size > bytes_.size() - at_) throw Error("truncated");
    std::memcpy(data, bytes_.data() + at_, size);
    at_ += size;
  }

 private:
  std::span<const unsigned char> bytes_;
  std::size_t at_ = 0;
};

bool allFinite(std::span<const double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// The largest grid a cache file may hold (the otmap command's limit is 1024): bounds what a header can claim.
constexpr int kMaxCachedN = 4096;

std::size_t entryBytes(int n) {
  return kHeaderBytes + payloadBytes(n) + 8;
}

// The map in a cache file's payload (seal removed), or the reason it cannot be used (Error, without the file
// name). key and n: what the entry must have been written for (unset: taken from the header, as the fuzz
// harness reads any entry).
OtMap decodeEntry(std::span<const unsigned char> bytes, std::optional<std::uint64_t> expectedKey,
                  std::optional<int> expectedN) {
  ByteReader reader(bytes);
  char magic[8];
  reader.getBytes(magic, 8);
  if (std::memcmp(magic, kMagic, 8) != 0) throw Error("not an iblx OT map file");
  if (const auto version = reader.get<std::uint32_t>(); version != kFormatVersion)
    throw Error("format version " + std::to_string(version) + ", expected " + std::to_string(kFormatVersion));
  const auto storedN = reader.get<std::uint32_t>();
  if (storedN < 1 || storedN > std::uint32_t(kMaxCachedN))
    throw Error("grid size " + std::to_string(storedN) + " out of range [1, " + std::to_string(kMaxCachedN) +
                "]");
  const int n = int(storedN);
  if (expectedN && n != *expectedN) throw Error("grid size mismatch");
  if (bytes.size() + 8 != entryBytes(n))
    throw Error("size " + std::to_string(bytes.size() + 8) + " bytes, expected " +
                std::to_string(entryBytes(n)));
  if (const auto key = reader.get<std::uint64_t>(); expectedKey && key != *expectedKey)
    throw Error("key mismatch");
  OtMap map;
  map.n = n;
  map.iterations = reader.get<std::int32_t>();
  map.coarseIterations = reader.get<std::int32_t>();
  map.seconds = reader.get<double>();
  map.l2 = reader.get<double>();
  map.l1 = reader.get<double>();
  map.linf = reader.get<double>();
  map.foldedQuads = reader.get<std::int32_t>();
  map.negativeAreaQuads = reader.get<std::int32_t>();
  const auto converged = reader.get<std::uint32_t>();
  const double cells = double(n) * n;
  if (map.iterations < 0 || map.coarseIterations < 0 || map.foldedQuads < 0 || map.negativeAreaQuads < 0 ||
      map.foldedQuads > cells || map.negativeAreaQuads > cells || converged > 1)
    throw Error("bad statistics");
  const double stats[] = {map.seconds, map.l2, map.l1, map.linf};
  if (!allFinite(stats)) throw Error("non-finite statistics");
  // Times and error norms are never negative.
  for (double s : stats)
    if (s < 0.0) throw Error("negative statistics");
  map.converged = converged == 1;
  map.vertices.resize(std::size_t(n + 1) * std::size_t(n + 1));
  reader.getBytes(map.vertices.data(), map.vertices.size() * sizeof(glm::dvec2));
  map.density.resize(std::size_t(n) * std::size_t(n));
  reader.getBytes(map.density.data(), map.density.size() * 8);
  map.psi.resize(map.density.size());
  reader.getBytes(map.psi.data(), map.psi.size() * 8);
  static_assert(sizeof(glm::dvec2) == 16);
  if (!allFinite(std::span(&map.vertices.front().x, 2 * map.vertices.size())) || !allFinite(map.density) ||
      !allFinite(map.psi))
    throw Error("non-finite values");
  // The solved-for density is floored and normalised to mean 1: every cell is positive.
  for (double d : map.density)
    if (!(d > 0.0)) throw Error("a density value that is not positive");
  return map;
}

OtMap readEntry(const std::filesystem::path& path, std::optional<std::uint64_t> key, std::optional<int> n) {
  const std::vector<unsigned char> sealed = readSealedCacheFile(path, entryBytes(n ? *n : kMaxCachedN));
  try {
    return decodeEntry(sealed, key, n);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

void writeEntry(const std::filesystem::path& path, std::uint64_t key, const OtMap& map) {
  const std::size_t cells = std::size_t(map.n) * std::size_t(map.n);
  if (map.n < 1 || map.n > kMaxCachedN ||
      map.vertices.size() != std::size_t(map.n + 1) * std::size_t(map.n + 1) || map.density.size() != cells ||
      map.psi.size() != cells)
    throw Error("the map's arrays do not match its size");
  ByteWriter writer(kHeaderBytes + payloadBytes(map.n));
  writer.putBytes(kMagic, 8);
  writer.put<std::uint32_t>(kFormatVersion);
  writer.put<std::uint32_t>(std::uint32_t(map.n));
  writer.put<std::uint64_t>(key);
  writer.put<std::int32_t>(map.iterations);
  writer.put<std::int32_t>(map.coarseIterations);
  writer.put<double>(map.seconds);
  writer.put<double>(map.l2);
  writer.put<double>(map.l1);
  writer.put<double>(map.linf);
  writer.put<std::int32_t>(map.foldedQuads);
  writer.put<std::int32_t>(map.negativeAreaQuads);
  writer.put<std::uint32_t>(map.converged ? 1 : 0);
  writer.putBytes(map.vertices.data(), map.vertices.size() * sizeof(glm::dvec2));
  writer.putBytes(map.density.data(), map.density.size() * 8);
  writer.putBytes(map.psi.data(), map.psi.size() * 8);
  IBLX_ASSERT(writer.written() == kHeaderBytes + payloadBytes(map.n));
  const std::vector<char>& bytes = writer.bytes();
  // Sealed, under a name unique to this process and call, then renamed: a concurrent reader never sees a
  // torn file, and a damaged one fails the seal.
  writeSealedCacheFile(path, std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()));
}

}  // namespace

std::uint64_t otMapCacheKey(std::span<const double> density, int n, const OtSolverOptions& options) {
  ContentHash hash;
  hash.add(std::string_view("iblx-otmap"));
  hashField(hash, "format", kFormatVersion);
  hashField(hash, "solver", kOtSolverVersion);
  hashField(hash, "n", n);
  hash.add(std::string_view("density")).add(density);
  const OtSolverOptions& o = options;
  hashField(hash, "maxIterations", o.maxIterations);
  hashField(hash, "targetL2", o.targetL2);
  hashField(hash, "targetL1", o.targetL1);
  hashField(hash, "floorFraction", o.floorFraction);
  hashField(hash, "coarseToFine", o.coarseToFine);
  hashField(hash, "coarsestSize", o.coarsestSize);
  hashField(hash, "coarseTargetL2", o.coarseTargetL2);
  hashField(hash, "krylovSteps", o.krylovSteps);
  hashField(hash, "krylovTolerance", o.krylovTolerance);
  hashField(hash, "stageIterations", o.stageIterations);
  hashField(hash, "stageLogError", o.stageLogError);
  hashField(hash, "minStageStep", o.minStageStep);
  hashField(hash, "stageMinStep", o.stageMinStep);
  hashField(hash, "homotopyPower", o.homotopyPower);
  hashField(hash, "maxSmoothingPasses", o.maxSmoothingPasses);
  hashField(hash, "foldGuard", o.foldGuard);
  hashField(hash, "relativeResidual", o.relativeResidual);
  hashField(hash, "boundaryFraction", o.boundaryFraction);
  hashField(hash, "secondOrderCorrection", o.secondOrderCorrection);
  // Not hashed: `threads` (only the order of some float sums) and `progress` (a callback).
  return hash.value();
}

std::filesystem::path otMapCachePath(const std::filesystem::path& cacheDir, std::uint64_t key) {
  return cacheDir / "otmaps" / (hexKey(key) + ".otmap");
}

OtMap readOtMapCacheFile(const std::filesystem::path& path, std::optional<std::uint64_t> key,
                         std::optional<int> n) {
  return readEntry(path, key, n);
}

OtMap solveOtMapCached(std::span<const double> density, int n, const OtSolverOptions& options,
                       const std::filesystem::path& cacheDir, bool* fromCache) {
  if (fromCache) *fromCache = false;
  // Bad input is solveOtMap's to report, and never has an entry.
  if (cacheDir.empty() || n < 1 || density.size() != std::size_t(n) * std::size_t(n))
    return solveOtMap(density, n, options);
  const std::uint64_t key = otMapCacheKey(density, n, options);
  const std::filesystem::path path = otMapCachePath(cacheDir, key);
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    try {
      OtMap map = readEntry(path, key, n);
      if (fromCache) *fromCache = true;
      return map;
    } catch (const Error& e) {
      warn("ignoring the cached OT map " + std::string(e.what()) + "; solving it again");
    }
  }
  OtMap map = solveOtMap(density, n, options);
  try {
    writeEntry(path, key, map);
  } catch (const std::exception& e) {
    warn("cannot store the OT map in the cache " + cacheDir.string() + ": " + e.what());
  }
  return map;
}

}  // namespace iblx
