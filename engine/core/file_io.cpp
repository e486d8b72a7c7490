// Bounded inputs and atomic outputs (engine/core/file_io.h).
#include "engine/core/file_io.h"

#include "engine/core/environment.h"
#include "engine/core/error.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <utility>

namespace iblx {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void throwCannotOpen(const fs::path& path, const std::string& reason) {
  throw Error("cannot open " + path.string() + ": " + reason);
}

std::string systemReason(int error, const char* fallback) {
  return error != 0 ? std::strerror(error) : fallback;
}

}  // namespace

std::uint64_t checkInputFile(const fs::path& path) {
  // stat, not open: opening a FIFO for reading blocks until a writer appears.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) throwCannotOpen(path, "no such file");
    throwCannotOpen(path, std::strerror(errno));
  }
  if (S_ISDIR(info.st_mode)) throwCannotOpen(path, "it is a directory");
  if (S_ISFIFO(info.st_mode)) throwCannotOpen(path, "it is a FIFO, not a regular file");
  if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode))
    throwCannotOpen(path, "it is a device, not a regular file");
  if (!S_ISREG(info.st_mode)) throwCannotOpen(path, "it is not a regular file");
  if (::access(path.c_str(), R_OK) != 0) throwCannotOpen(path, std::strerror(errno));
  return std::uint64_t(info.st_size);
}

namespace {

// The file opened for reading, refused unless it is a regular file when opened (a file swapped for a FIFO
// after a stat is refused here instead of blocking the open).
std::unique_ptr<std::FILE, int (*)(std::FILE*)> openRegularFile(const fs::path& path) {
  const int descriptor = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) throwCannotOpen(path, std::strerror(errno));
  struct stat opened {};
  if (::fstat(descriptor, &opened) != 0 || !S_ISREG(opened.st_mode)) {
    ::close(descriptor);
    throwCannotOpen(path, "it is not a regular file");
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(::fdopen(descriptor, "rb"), &std::fclose);
  if (!file) {
    ::close(descriptor);
    throwCannotOpen(path, std::strerror(errno));
  }
  return file;
}

// At most `size` bytes into `bytes` (resized to what was read): a file that shrank since its size was taken
// is read as it is now; one that grew is read up to that size.
template <typename Bytes>
void readInto(const fs::path& path, std::uint64_t size, Bytes& bytes) {
  const auto file = openRegularFile(path);
  bytes.resize(static_cast<std::size_t>(size));
  const std::size_t read = std::fread(bytes.data(), 1, bytes.size(), file.get());
  if (std::ferror(file.get())) throwCannotOpen(path, "read error");
  bytes.resize(read);
}

std::uint64_t checkInputSize(const fs::path& path, std::uint64_t maxBytes) {
  const std::uint64_t size = checkInputFile(path);
  if (size > maxBytes) {
    // Exact bytes too: just over a limit, both round to the same figure.
    const std::string sizeText =
        size < 1024 ? formatBytes(size) : formatBytes(size) + " (" + std::to_string(size) + " bytes)";
    throw Error(path.string() + ": the file is " + sizeText + ", more than the " + formatBytes(maxBytes) +
                " this kind of file may have");
  }
  return size;
}

}  // namespace

std::vector<unsigned char> readInputFile(const fs::path& path, std::uint64_t maxBytes) {
  std::vector<unsigned char> bytes;
  readInto(path, checkInputSize(path, maxBytes), bytes);
  return bytes;
}

std::string readInputText(const fs::path& path, std::uint64_t maxBytes) {
  std::string text;
  readInto(path, checkInputSize(path, maxBytes), text);
  return text;
}

std::string readFileHead(const fs::path& path, std::uint64_t maxBytes) {
  std::string head;
  readInto(path, std::min(checkInputFile(path), maxBytes), head);
  return head;
}

std::uint64_t memoryBudgetBytes() {
  constexpr double kGiB = double(1ull << 30);
  return std::uint64_t(environmentNumber("IBLX_MEMORY_BUDGET_GIB", 4.0, 1e6) * kGiB);
}

std::string formatBytes(std::uint64_t bytes) {
  const char* const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024.0 && unit < 4) {
    value /= 1024.0;
    ++unit;
  }
  char buffer[32];
  if (unit == 0)
    std::snprintf(buffer, sizeof buffer, "%llu bytes", static_cast<unsigned long long>(bytes));
  else
    std::snprintf(buffer, sizeof buffer, value < 10.0 ? "%.1f %s" : "%.0f %s", value, units[unit]);
  return buffer;
}

void checkMemoryBudget(std::string_view what, std::uint64_t bytes) {
  const std::uint64_t budget = memoryBudgetBytes();
  if (bytes > budget)
    throw Error(std::string(what) + " needs " + formatBytes(bytes) + ", over iblx's memory budget of " +
                formatBytes(budget) + " (IBLX_MEMORY_BUDGET_GIB raises it)");
}

namespace {
std::function<std::uint64_t()>& deviceTableQuery() {
  static std::function<std::uint64_t()> query;
  return query;
}
}  // namespace

DeviceTableLimit::DeviceTableLimit(std::function<std::uint64_t()> largestBuffer)
    : previous_(std::exchange(deviceTableQuery(), std::move(largestBuffer))) {}

DeviceTableLimit::~DeviceTableLimit() {
  deviceTableQuery() = std::move(previous_);
}

void checkDeviceTable(std::string_view what, std::uint64_t bytes) {
  if (bytes <= kGuaranteedDeviceBufferBytes || !deviceTableQuery()) return;
  const std::uint64_t largest = deviceTableQuery()();
  if (bytes > largest)
    throw Error(std::string(what) + " needs " + formatBytes(bytes) +
                ", more than the device's largest storage buffer (" + formatBytes(largest) + ")");
}

AtomicOutput::AtomicOutput(fs::path path) : path_(std::move(path)) {
  static std::atomic<unsigned> counter{0};
  // Hidden, in the same directory (rename is atomic only within one file system), unique per process and
  // output so that parallel runs writing the same name never share a temporary.
  const fs::path directory = path_.parent_path();
  std::string name = ".";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on a chain of string +
  name.append(path_.filename().string()).append(".tmp-").append(std::to_string(::getpid()));
  name.append("-").append(std::to_string(counter++));
  temporary_ = directory / name;
}

AtomicOutput::~AtomicOutput() {
  if (committed_) return;
  if (stream_.is_open()) stream_.close();
  std::error_code ignored;
  fs::remove(temporary_, ignored);
}

namespace {

// The errno values a failed write or close can leave.
bool isWriteError(int error) {
  return error == ENOSPC || error == EDQUOT || error == EFBIG || error == EIO || error == EROFS;
}

}  // namespace

std::ofstream& AtomicOutput::stream() {
  if (!opened_) {
    opened_ = true;
    errno = 0;
    stream_.open(temporary_, std::ios::binary | std::ios::trunc);
    if (!stream_)
      throw Error("cannot write " + path_.string() + ": " + systemReason(errno, "cannot create the file"));
  }
  return stream_;
}

void AtomicOutput::commit() {
  if (opened_) {
    // errno still holds the reason of a write that already failed; otherwise the flush sets it.
    if (stream_) {
      errno = 0;
      stream_.flush();
    }
    const bool written = bool(stream_);
    int writeError = errno;
    errno = 0;
    stream_.close();
    if (!written || !stream_) {
      // A stream keeps no reason for a failed write, and errno may have been set since by anything else
      // (isatty on a redirected stderr leaves ENOTTY): only a write's own errors are taken from it, and a
      // full file system is asked for directly.
      if (!isWriteError(writeError)) writeError = isWriteError(errno) ? errno : 0;
      struct statvfs space {};
      if (writeError == 0 &&
          ::statvfs(temporary_.parent_path().empty() ? "." : temporary_.parent_path().c_str(), &space) == 0 &&
          space.f_bavail == 0)
        writeError = ENOSPC;
      throw Error("cannot write " + path_.string() + ": " +
                  systemReason(writeError, "write failed (is the disk full?)"));
    }
  }
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw Error("cannot write " + path_.string() + ": " + std::strerror(errno));
  committed_ = true;
}

void writeFileAtomically(const fs::path& path, std::span<const unsigned char> bytes) {
  AtomicOutput output(path);
  output.stream().write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  output.commit();
}

void writeFileAtomically(const fs::path& path, std::string_view text) {
  writeFileAtomically(path, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

}  // namespace iblx
