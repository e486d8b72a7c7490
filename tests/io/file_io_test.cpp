// Bounded inputs and atomic outputs (engine/core/file_io.h), and the writers built on them failing loudly
// on a full device: a file-size limit (RLIMIT_FSIZE) stands in for the full disk, as no test can fill one.
#include "engine/core/file_io.h"
#include "engine/io/brdf_file.h"
#include "engine/io/image_write.h"
#include "engine/io/merl.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cstdio>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace iblx {
namespace {

using test::contains;
using test::errorMessage;
using test::ScratchDir;

// Writes past `bytes` fail with EFBIG (SIGXFSZ ignored) until the guard dies: what a full device looks like
// to a writer.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = saved_;
    limited.rlim_cur = bytes;
    if (setrlimit(RLIMIT_FSIZE, &limited) != 0) throw std::runtime_error("setrlimit failed");
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*previous_)(int) = SIG_DFL;
};

std::size_t entriesIn(const std::filesystem::path& dir) {
  return std::size_t(std::distance(std::filesystem::directory_iterator(dir), {}));
}

std::vector<float> noise(int width, int height) {
  std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
  std::uint32_t state = 12345;
  for (float& v : rgb) {
    state = state * 1664525u + 1013904223u;
    v = float(state >> 8) / float(1 << 24);
  }
  return rgb;
}

}  // namespace

TEST_CASE("checkInputFile refuses what is not a regular file, at once") {
  ScratchDir dir;
  CHECK(contains(errorMessage([&] { checkInputFile(dir.file("none.exr")); }), "none.exr: no such file"));
  CHECK(contains(errorMessage([&] { checkInputFile(dir.file("")); }), "it is a directory"));
  // A FIFO with no writer: opening it would block forever; it must be refused without opening it.
  const auto fifo = dir.file("pipe.hdr");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(contains(errorMessage([&] { checkInputFile(fifo); }), "pipe.hdr: it is a FIFO"));
  CHECK(contains(errorMessage([&] { checkInputFile("/dev/zero"); }), "/dev/zero: it is a device"));
  test::writeBytes(dir.file("five"), {1, 2, 3, 4, 5});
  CHECK(checkInputFile(dir.file("five")) == 5);
}

TEST_CASE("readInputFile refuses a file over its bound before reading it") {
  ScratchDir dir;
  test::writeBytes(dir.file("data"), std::vector<unsigned char>(1000, 7));
  CHECK(readInputFile(dir.file("data"), 1000).size() == 1000);
  const std::string message = errorMessage([&] { readInputFile(dir.file("data"), 999); });
  CHECK(contains(message, "data: the file is 1000 bytes, more than the 999 bytes"));
}

TEST_CASE("memory budget: sizes are checked against it, and IBLX_MEMORY_BUDGET_GIB changes it") {
  CHECK(memoryBudgetBytes() == 4ull << 30);
  CHECK_NOTHROW(checkMemoryBudget("a map", 4ull << 30));
  CHECK(contains(errorMessage([] { checkMemoryBudget("the 16384x16384 image", 12ull << 30); }),
                 "the 16384x16384 image needs 12 GiB, over iblx's memory budget of 4.0 GiB"));
  ::setenv("IBLX_MEMORY_BUDGET_GIB", "0.5", 1);
  CHECK(memoryBudgetBytes() == 1ull << 29);
  ::setenv("IBLX_MEMORY_BUDGET_GIB", "lots", 1);  // unreadable: the default
  CHECK(memoryBudgetBytes() == 4ull << 30);
  ::unsetenv("IBLX_MEMORY_BUDGET_GIB");
}

TEST_CASE(
    "AtomicOutput: the file appears whole on commit, never partly, and an old file survives a failure") {
  ScratchDir dir;
  const auto path = dir.file("out.txt");
  {
    AtomicOutput output(path);
    output.stream() << "first";
    CHECK(!std::filesystem::exists(path));  // not before commit
    output.commit();
  }
  CHECK(test::readBytes(path) == std::vector<unsigned char>{'f', 'i', 'r', 's', 't'});
  try {
    AtomicOutput output(path);
    output.stream() << "second, never committed";
    throw std::runtime_error("interrupted");
  } catch (const std::runtime_error&) {
  }
  CHECK(test::readBytes(path).size() == 5);  // the old file is kept
  CHECK(entriesIn(dir.file("")) == 1);       // and no temporary is left behind
  CHECK(contains(errorMessage([&] { writeFileAtomically(dir.file("no/such/dir.txt"), "x"); }),
                 "cannot write " + dir.file("no/such/dir.txt").string()));
}

TEST_CASE("writers on a full device: each throws naming the file, and leaves no file") {
  ScratchDir dir;
  const std::vector<float> rgb = noise(64, 64);  // incompressible: well over the limit in every format
  const FileSizeLimit limit(4096);
  const auto png = dir.file("image.png"), exr = dir.file("image.exr"), bparam = dir.file("m.bparam"),
             merl = dir.file("m.binary");
  CHECK(contains(errorMessage([&] { writePng(png, 64, 64, rgb, 0.0); }), "cannot write " + png.string()));
  CHECK(contains(errorMessage([&] { writeExr(exr, 64, 64, rgb); }), exr.string()));
  std::vector<ParamDecl> params(200,
                                ParamDecl{.name = "a_rather_long_parameter_name", .type = ParamType::Float});
  CHECK(contains(errorMessage([&] { writeBparam(bparam, "/x.brdf", params, {}); }), bparam.string()));
  CHECK(contains(errorMessage([&] { writeMerl(merl, std::vector<double>(3 * kMerlBins, 0.5)); }),
                 merl.string()));
  CHECK(entriesIn(dir.file("")) == 0);
}

TEST_CASE("atomic output: a failed write is not reported with an errno left by an unrelated call") {
  // The writes fail (EFBIG); then isatty on a regular file sets errno to ENOTTY, as progressLine does when
  // stderr is redirected. The message used to say "Inappropriate ioctl for device".
  ScratchDir dir;
  std::string message;
  {
    const FileSizeLimit limit(4096);
    AtomicOutput output(dir.file("big.csv"));
    output.stream() << std::string(100000, 'x');
    std::FILE* other = std::tmpfile();
    REQUIRE(other != nullptr);
    CHECK(::isatty(::fileno(other)) == 0);
    std::fclose(other);
    message = errorMessage([&] { output.commit(); });
  }
  CHECK(contains(message, "cannot write " + dir.file("big.csv").string()));
  CHECK_FALSE(contains(message, "Inappropriate ioctl"));
}

}  // namespace iblx
