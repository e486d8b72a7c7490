// The on-disk OT map cache (engine/sampling/ot_cache.h).
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
//   u64      FNV-1a of every byte before it (a torn or bit-flipped file is ignored)
#include "engine/sampling/ot_cache.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace iblx {

namespace {

constexpr char kMagic[8] = {'I', 'B', 'L', 'X', 'O', 'T', 'M', '\0'};
// Bump when the file layout, the key's contents or the solver's output for the same options change, so stale
// entries are never served. (The solver has no version number of its own yet; one in ot_solver.h, hashed into
// the key, would let solver changes invalidate entries without touching this file.)
constexpr std::uint32_t kFormatVersion = 1;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 4 + 4 + 8 * 4 + 4 + 4 + 4;

#if defined(__x86_64__) && defined(__GLIBCXX__)
// A new OtSolverOptions field usually changes this size (not always: padding may absorb a bool): add it to
// otMapCacheKey (or say why it does not change the result) and update the number.
static_assert(sizeof(OtSolverOptions) == 184, "OtSolverOptions changed: review otMapCacheKey");
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
  explicit ByteReader(const std::vector<char>& bytes) : bytes_(bytes) {}
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
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

bool allFinite(std::span<const double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// The map stored at `path` for `key` and n, or the reason it cannot be used (Error).
OtMap readEntry(const std::filesystem::path& path, std::uint64_t key, int n) {
  const std::size_t expected = kHeaderBytes + payloadBytes(n) + 8;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("cannot read its size");
  if (size != expected)
    throw Error("size " + std::to_string(size) + " bytes, expected " + std::to_string(expected));
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes(expected);
  if (!in.read(bytes.data(), std::streamsize(expected))) throw Error("truncated");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + expected - 8, 8);
  if (stored != ContentHash().addBytes(bytes.data(), expected - 8).value()) throw Error("checksum mismatch");

  ByteReader reader(bytes);
  char magic[8];
  reader.getBytes(magic, 8);
  if (std::memcmp(magic, kMagic, 8) != 0) throw Error("not an iblx OT map file");
  if (const auto version = reader.get<std::uint32_t>(); version != kFormatVersion)
    throw Error("format version " + std::to_string(version) + ", expected " + std::to_string(kFormatVersion));
  if (reader.get<std::uint32_t>() != std::uint32_t(n)) throw Error("grid size mismatch");
  if (reader.get<std::uint64_t>() != key) throw Error("key mismatch");
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
  return map;
}

void writeEntry(const std::filesystem::path& path, std::uint64_t key, const OtMap& map) {
  const std::size_t cells = std::size_t(map.n) * std::size_t(map.n);
  if (map.n < 1 || map.vertices.size() != std::size_t(map.n + 1) * std::size_t(map.n + 1) ||
      map.density.size() != cells || map.psi.size() != cells)
    throw Error("the map's arrays do not match its size");
  ByteWriter writer(kHeaderBytes + payloadBytes(map.n) + 8);
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
  writer.put<std::uint64_t>(ContentHash().addBytes(writer.bytes().data(), writer.written()).value());
  const std::vector<char>& bytes = writer.bytes();

  std::filesystem::create_directories(path.parent_path());
  // A name unique to this process and call, then an atomic rename: a concurrent reader never sees a torn
  // file.
  static std::atomic<std::uint64_t> counter{0};
  const std::filesystem::path temporary =
      path.string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(temporary, ec);
      throw Error("cannot write " + temporary.string());
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw Error("cannot rename to " + path.string());
  }
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
  hashField(hash, "conjugateJacobian", o.conjugateJacobian);
  hashField(hash, "krylovSteps", o.krylovSteps);
  hashField(hash, "directNewton", o.directNewton);
  hashField(hash, "krylovTolerance", o.krylovTolerance);
  hashField(hash, "stageIterations", o.stageIterations);
  hashField(hash, "stageLogError", o.stageLogError);
  hashField(hash, "minStageStep", o.minStageStep);
  hashField(hash, "stageMinStep", o.stageMinStep);
  hashField(hash, "homotopyPower", o.homotopyPower);
  hashField(hash, "maxSmoothingPasses", o.maxSmoothingPasses);
  hashField(hash, "foldGuard", o.foldGuard);
  hashField(hash, "merit", o.merit);
  hashField(hash, "logNewton", o.logNewton);
  hashField(hash, "relativeResidual", o.relativeResidual);
  hashField(hash, "boundaryFraction", o.boundaryFraction);
  hashField(hash, "secondOrderCorrection", o.secondOrderCorrection);
  // Not hashed: `threads` (only the order of some float sums) and `progress` (a callback).
  return hash.value();
}

std::filesystem::path otMapCachePath(const std::filesystem::path& cacheDir, std::uint64_t key) {
  return cacheDir / "otmaps" / (hexKey(key) + ".otmap");
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
    } catch (const std::exception& e) {
      warn("ignoring the cached OT map " + path.string() + " (" + e.what() + "); solving again");
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
