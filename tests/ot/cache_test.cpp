// Tests of the on-disk OT map cache (engine/ot/cache.h): a second solve is read back bit for bit,
// every result-changing input changes the key, a truncated, corrupt or foreign file (or one with impossible
// values behind a valid checksum) is solved again (never a crash), and several processes sharing one cache
// never read a half-written entry.
#include "engine/ot/cache.h"

#include "engine/core/cache_file.h"
#include "engine/core/error.h"
#include "engine/core/log.h"

#include <doctest/doctest.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

using namespace iblx;

namespace {

// A fresh directory removed at the end of the test.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("iblx-otcache-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// Collects warnings instead of printing them.
struct WarningCapture {
  std::vector<std::string> messages;
  LogSink previous;
  WarningCapture() {
    previous = setWarningSink([this](const std::string& m) { messages.push_back(m); });
  }
  ~WarningCapture() { setWarningSink(previous); }
};

std::vector<double> smoothDensity(int n) {
  std::vector<double> d(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u = (i + 0.5) / n, v = (j + 0.5) / n;
      d[std::size_t(j) * n + i] = (0.5 + std::cos(std::numbers::pi * v) * std::cos(std::numbers::pi * v) +
                                   0.3 * std::sin(2 * std::numbers::pi * u)) *
                                  std::sin(std::numbers::pi * v);
    }
  return d;
}

bool sameMap(const OtMap& a, const OtMap& b) {
  return a.n == b.n && a.vertices.size() == b.vertices.size() &&
         std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(glm::dvec2)) == 0 &&
         a.density == b.density && a.psi == b.psi && a.iterations == b.iterations &&
         a.coarseIterations == b.coarseIterations && a.seconds == b.seconds && a.l2 == b.l2 && a.l1 == b.l1 &&
         a.linf == b.linf && a.foldedQuads == b.foldedQuads && a.negativeAreaQuads == b.negativeAreaQuads &&
         a.converged == b.converged;
}

std::vector<std::filesystem::path> entries(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(dir / "otmaps"))
    for (const auto& e : std::filesystem::directory_iterator(dir / "otmaps")) files.push_back(e.path());
  return files;
}

}  // namespace

TEST_CASE("OT cache: the second solve is read from the cache, identical") {
  TempDir dir("hit");
  const int n = 32;
  const std::vector<double> density = smoothDensity(n);
  const OtSolverOptions options;
  bool fromCache = true;
  const OtMap first = solveOtMapCached(density, n, options, dir.path, &fromCache);
  CHECK_FALSE(fromCache);
  CHECK(first.converged);
  const auto files = entries(dir.path);
  REQUIRE(files.size() == 1);  // no temporary left behind
  CHECK(files[0] == otMapCachePath(dir.path, otMapCacheKey(density, n, options)));

  const OtMap second = solveOtMapCached(density, n, options, dir.path, &fromCache);
  CHECK(fromCache);
  CHECK(sameMap(first, second));  // statistics included: `seconds` is the original solve's
  // The progress callback and the thread count do not change the key.
  OtSolverOptions other = options;
  other.threads = 1;
  int calls = 0;
  other.progress = [&](int, double) { ++calls; };
  CHECK(otMapCacheKey(density, n, other) == otMapCacheKey(density, n, options));
  const OtMap third = solveOtMapCached(density, n, other, dir.path, &fromCache);
  CHECK(fromCache);
  CHECK(calls == 0);
  CHECK(sameMap(first, third));
}

TEST_CASE("OT cache: every input that changes the map changes the key") {
  const int n = 16;
  const std::vector<double> density = smoothDensity(n);
  const OtSolverOptions base;
  const std::uint64_t key = otMapCacheKey(density, n, base);
  CHECK(otMapCacheKey(density, n, base) == key);  // deterministic

  std::vector<double> brighter = density;
  brighter[37] *= 1.0 + 1e-15;
  CHECK(otMapCacheKey(brighter, n, base) != key);
  const std::vector<double> square(std::size_t(8) * 32, 1.0);  // same byte count, another n
  CHECK(otMapCacheKey(square, 8, base) != otMapCacheKey(square, 32, base));

  const auto differs = [&](auto change) {
    OtSolverOptions o = base;
    change(o);
    return otMapCacheKey(density, n, o) != key;
  };
  CHECK(differs([](OtSolverOptions& o) { o.floorFraction = 1e-3; }));
  CHECK(differs([](OtSolverOptions& o) { o.maxIterations = 10; }));
  CHECK(differs([](OtSolverOptions& o) { o.targetL2 = 1e-9; }));
  CHECK(differs([](OtSolverOptions& o) { o.targetL1 = 1e-4; }));
  CHECK(differs([](OtSolverOptions& o) { o.coarseToFine = !o.coarseToFine; }));
  CHECK(differs([](OtSolverOptions& o) { o.coarsestSize = 8; }));
  CHECK(differs([](OtSolverOptions& o) { o.coarseTargetL2 = 1e-6; }));
  CHECK(differs([](OtSolverOptions& o) { o.krylovSteps = 10; }));
  CHECK(differs([](OtSolverOptions& o) { o.krylovTolerance = 0.01; }));
  CHECK(differs([](OtSolverOptions& o) { o.stageIterations = 7; }));
  CHECK(differs([](OtSolverOptions& o) { o.stageLogError = 0.1; }));
  CHECK(differs([](OtSolverOptions& o) { o.minStageStep = 1e-2; }));
  CHECK(differs([](OtSolverOptions& o) { o.stageMinStep = 0.5; }));
  CHECK(differs([](OtSolverOptions& o) { o.homotopyPower = 1.0; }));
  CHECK(differs([](OtSolverOptions& o) { o.maxSmoothingPasses = 4; }));
  CHECK(differs([](OtSolverOptions& o) { o.foldGuard = OtFoldGuard::Convex; }));
  CHECK(differs([](OtSolverOptions& o) { o.relativeResidual = !o.relativeResidual; }));
  CHECK(differs([](OtSolverOptions& o) { o.secondOrderCorrection = !o.secondOrderCorrection; }));
  CHECK(differs([](OtSolverOptions& o) { o.boundaryFraction = 0.5; }));
}

TEST_CASE("OT cache: a different floor is another entry") {
  TempDir dir("floor");
  const int n = 16;
  const std::vector<double> density = smoothDensity(n);
  OtSolverOptions options;
  bool fromCache = true;
  const OtMap a = solveOtMapCached(density, n, options, dir.path, &fromCache);
  CHECK_FALSE(fromCache);
  options.floorFraction = 0.5;  // raises the cells near the poles, so the map changes
  const OtMap b = solveOtMapCached(density, n, options, dir.path, &fromCache);
  CHECK_FALSE(fromCache);
  CHECK(entries(dir.path).size() == 2);
  CHECK(a.density != b.density);
}

TEST_CASE("OT cache: a truncated, corrupt or foreign file is solved again and replaced") {
  TempDir dir("corrupt");
  const int n = 16;
  const std::vector<double> density = smoothDensity(n);
  const OtSolverOptions options;
  const OtMap fresh = solveOtMapCached(density, n, options, dir.path);
  const auto path = otMapCachePath(dir.path, otMapCacheKey(density, n, options));
  REQUIRE(std::filesystem::exists(path));
  const auto size = std::filesystem::file_size(path);

  const auto damageAndReload = [&](const std::string& what, auto damage) {
    CAPTURE(what);
    damage();
    WarningCapture warnings;
    bool fromCache = true;
    const OtMap map = solveOtMapCached(density, n, options, dir.path, &fromCache);
    CHECK_FALSE(fromCache);
    REQUIRE(warnings.messages.size() == 1);
    CHECK(warnings.messages[0].find("ignoring the cached OT map") != std::string::npos);
    CHECK(map.converged);
    CHECK(map.vertices.size() == fresh.vertices.size());
    // The entry was rewritten: the next call reads it.
    const OtMap again = solveOtMapCached(density, n, options, dir.path, &fromCache);
    CHECK(fromCache);
    CHECK(sameMap(map, again));
  };
  damageAndReload("truncated", [&] { std::filesystem::resize_file(path, size / 2); });
  damageAndReload("empty", [&] { std::filesystem::resize_file(path, 0); });
  damageAndReload("one byte flipped in the vertices", [&] {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x7f');
  });
  damageAndReload("garbage of the right size", [&] {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    for (std::uintmax_t i = 0; i < size; ++i) f.put(char(i * 31));
  });
}

TEST_CASE("OT cache: another key's valid file under this name is not served") {
  TempDir dir("foreign");
  const int n = 16;
  const std::vector<double> density = smoothDensity(n);
  OtSolverOptions a, b;
  b.floorFraction = 0.5;
  solveOtMapCached(density, n, b, dir.path);
  const auto pathA = otMapCachePath(dir.path, otMapCacheKey(density, n, a));
  std::filesystem::rename(otMapCachePath(dir.path, otMapCacheKey(density, n, b)), pathA);
  WarningCapture warnings;
  bool fromCache = true;
  const OtMap map = solveOtMapCached(density, n, a, dir.path, &fromCache);
  CHECK_FALSE(fromCache);
  REQUIRE(warnings.messages.size() == 1);
  CHECK(warnings.messages[0].find("key mismatch") != std::string::npos);
  CHECK(map.density == solveOtMap(density, n, a).density);
}

TEST_CASE("OT cache: no directory solves without caching; an unwritable one only warns") {
  const int n = 16;
  const std::vector<double> density = smoothDensity(n);
  bool fromCache = true;
  const OtMap map = solveOtMapCached(density, n, {}, {}, &fromCache);
  CHECK_FALSE(fromCache);
  CHECK(map.converged);

  TempDir dir("unwritable");
  std::ofstream(dir.path / "otmaps") << "a file where the directory should be";
  WarningCapture warnings;
  const OtMap stored = solveOtMapCached(density, n, {}, dir.path, &fromCache);
  CHECK_FALSE(fromCache);
  CHECK(stored.converged);
  REQUIRE(warnings.messages.size() == 1);
  CHECK(warnings.messages[0].find("cannot store the OT map") != std::string::npos);

  // Bad input throws as solveOtMap does, cache or not.
  CHECK_THROWS_AS(solveOtMapCached(std::vector<double>(10, 1.0), 4, {}, dir.path), Error);
  CHECK_THROWS_AS(solveOtMapCached(std::vector<double>(16, 0.0), 4, {}, dir.path), Error);
}

namespace {

std::vector<unsigned char> fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Byte offsets in an entry (engine/ot/cache.cpp): the header is 8 + 4 + 4 + 8 bytes of identity,
// then iterations, coarseIterations (i32), seconds, l2, l1, linf (f64), two i32 counts and converged.
constexpr std::size_t kNOffset = 12, kSecondsOffset = 32, kL2Offset = 40, kHeaderBytes = 76;

}  // namespace

TEST_CASE("OT cache: impossible values behind a valid checksum are refused and solved again") {
  TempDir dir("values");
  const int n = 8;
  const std::vector<double> density = smoothDensity(n);
  const OtSolverOptions options;
  solveOtMapCached(density, n, options, dir.path);
  const auto path = otMapCachePath(dir.path, otMapCacheKey(density, n, options));
  const std::vector<unsigned char> payload = unsealCacheBytes(fileBytes(path));
  REQUIRE(payload.size() == kHeaderBytes + 8 * (2 * 81 + 2 * 64));
  const std::uint64_t key = otMapCacheKey(density, n, options);
  CHECK(readOtMapCacheFile(path).density == readOtMapCacheFile(path, key, n).density);
  CHECK_THROWS_AS(readOtMapCacheFile(path, key + 1, n), Error);
  CHECK_THROWS_AS(readOtMapCacheFile(path, key, n + 1), Error);

  const std::size_t densityOffset = kHeaderBytes + 16 * 81;
  const auto damaged = [&](const std::string& what, std::size_t offset, auto value,
                           const std::string& expected) {
    CAPTURE(what);
    std::vector<unsigned char> changed = payload;
    std::memcpy(changed.data() + offset, &value, sizeof value);
    writeBytes(path, sealCacheBytes(changed));
    std::string message;
    try {
      readOtMapCacheFile(path);
    } catch (const Error& e) {
      message = e.what();
    }
    CHECK(message.find(path.string()) != std::string::npos);
    CHECK(message.find(expected) != std::string::npos);
    // solveOtMapCached reports it in one line naming the file, solves again and replaces the entry.
    WarningCapture warnings;
    bool fromCache = true;
    solveOtMapCached(density, n, options, dir.path, &fromCache);
    CHECK_FALSE(fromCache);
    REQUIRE(warnings.messages.size() == 1);
    CHECK(warnings.messages[0].find(path.string()) != std::string::npos);
    CHECK(warnings.messages[0].find('\n') == std::string::npos);
    CHECK_NOTHROW(readOtMapCacheFile(path));
  };
  damaged("NaN density", densityOffset + 8 * 5, std::numeric_limits<double>::quiet_NaN(), "non-finite");
  damaged("negative density", densityOffset, -1.0, "not positive");
  damaged("zero density", densityOffset + 8 * 63, 0.0, "not positive");
  damaged("Inf vertex", kHeaderBytes + 8 * 7, std::numeric_limits<double>::infinity(), "non-finite");
  damaged("negative time", kSecondsOffset, -1.0, "negative statistics");
  damaged("NaN error", kL2Offset, std::numeric_limits<double>::quiet_NaN(), "non-finite statistics");
  damaged("grid size 0", kNOffset, std::uint32_t(0), "grid size 0");
  damaged("huge grid size", kNOffset, std::uint32_t(0x7fffffff), "out of range");
  damaged("other grid size", kNOffset, std::uint32_t(9), "size");
}

// ---- Several processes on one cache --------------------------------------------------------------------
// The test re-runs this executable as child processes (the "child" test case below, which does nothing unless
// the parent set IBLX_OT_CACHE_CHILD). Writers remove an entry and solve it again, over and over, so entries
// are rewritten all the time; readers read the same entries as fast as they can. Atomic writes (temporary,
// then rename) mean a reader finds either no file or a whole one: any other error (a torn file fails its
// checksum or size) fails the child.

namespace {

constexpr int kChildDensities = 3, kChildN = 16;

std::vector<double> childDensity(int which) {
  std::vector<double> d = smoothDensity(kChildN);
  for (std::size_t i = 0; i < d.size(); ++i) d[i] *= 1.0 + 0.5 * which * double(i % 5);
  return d;
}

std::filesystem::path childEntry(const std::filesystem::path& dir, int which) {
  return otMapCachePath(dir, otMapCacheKey(childDensity(which), kChildN, {}));
}

}  // namespace

TEST_CASE("OT cache: concurrency child (runs only inside the test below)") {
  const char* dirVariable = std::getenv("IBLX_OT_CACHE_CHILD");
  const char* roleVariable = std::getenv("IBLX_OT_CACHE_CHILD_ROLE");
  if (dirVariable == nullptr || roleVariable == nullptr) return;
  const std::filesystem::path dir = dirVariable;
  const std::string role = roleVariable;
  WarningCapture warnings;
  if (role == "writer") {
    for (int round = 0; round < 12; ++round) {
      const int which = round % kChildDensities;
      std::error_code ec;
      std::filesystem::remove(childEntry(dir, which), ec);
      const OtMap map = solveOtMapCached(childDensity(which), kChildN, {}, dir);
      CHECK(map.converged);
    }
  } else {
    // Until the writers are done (the parent creates "done"), and at least a few hundred reads.
    int reads = 0, whole = 0;
    while (reads < 300 || !std::filesystem::exists(dir / "done")) {
      const auto path = childEntry(dir, reads++ % kChildDensities);
      try {
        const OtMap map = readOtMapCacheFile(path);
        CHECK(map.n == kChildN);
        ++whole;
      } catch (const Error& e) {
        // Removed by a writer between two reads: fine. Anything else is a torn or damaged entry.
        const std::string message = e.what();
        INFO(message);
        CHECK((message.find("no such file") != std::string::npos ||
               message.find("No such file") != std::string::npos));
      }
      if (reads > 200000) break;
    }
    MESSAGE("reader: " << whole << " whole entries in " << reads << " reads");
  }
  // A torn read inside solveOtMapCached would have warned ("ignoring the cached OT map ...").
  for (const auto& m : warnings.messages) CHECK_MESSAGE(false, m);
}

TEST_CASE("OT cache: several processes sharing one cache never read a half-written entry") {
  TempDir dir("processes");
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<pid_t> children;
  const auto spawn = [&](const std::string& role) {
    std::vector<std::string> environment;
    for (char** e = environ; *e != nullptr; ++e) environment.emplace_back(*e);
    environment.push_back("IBLX_OT_CACHE_CHILD=" + dir.path.string());
    environment.push_back("IBLX_OT_CACHE_CHILD_ROLE=" + role);
    std::vector<char*> envp;
    for (auto& e : environment) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::string filter = "--test-case=OT cache: concurrency child*";
    std::string quiet = "--minimal=true";
    char* argv[] = {const_cast<char*>(self.c_str()), filter.data(), quiet.data(), nullptr};
    pid_t pid = 0;
    REQUIRE(posix_spawn(&pid, self.c_str(), nullptr, nullptr, argv, envp.data()) == 0);
    children.push_back(pid);
  };
  const auto waitFor = [](pid_t pid) {
    int status = 0;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
  };
  spawn("writer");
  spawn("writer");
  spawn("reader");
  spawn("reader");
  CHECK(waitFor(children[0]));
  CHECK(waitFor(children[1]));
  std::ofstream(dir.path / "done") << "writers finished";
  CHECK(waitFor(children[2]));
  CHECK(waitFor(children[3]));
  // Every entry is whole, and no temporary is left behind.
  for (int which = 0; which < kChildDensities; ++which)
    CHECK_NOTHROW(readOtMapCacheFile(childEntry(dir.path, which)));
  CHECK(entries(dir.path).size() == std::size_t(kChildDensities));
}
