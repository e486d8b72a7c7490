// Input files that cannot stall or flood iblx, and outputs that are either written whole or reported as
// failed: inputs must be regular files and are read within a bound; outputs go to a temporary name in the
// same directory, are checked on write and on close, and are renamed into place.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace iblx {

// Checks, without opening it, that path names a readable regular file: a missing file, a directory, a FIFO, a
// device or a socket is refused at once with Error("cannot open PATH: REASON"). Returns the size in bytes.
std::uint64_t checkInputFile(const std::filesystem::path& path);

// The whole file; one larger than maxBytes is refused with an Error naming the file and the limit, before
// anything is read. The read itself stops at maxBytes, so a file that grows meanwhile cannot flood memory.
std::vector<unsigned char> readInputFile(const std::filesystem::path& path, std::uint64_t maxBytes);
std::string readInputText(const std::filesystem::path& path, std::uint64_t maxBytes);
// The first min(size, maxBytes) bytes of a file, whatever its size: what a format check reads, so that a huge
// file (or one without a newline) costs no more than maxBytes to recognise.
std::string readFileHead(const std::filesystem::path& path, std::uint64_t maxBytes);

// The memory iblx lets one input claim (an image, a table, a G-buffer): 4 GiB, or $IBLX_MEMORY_BUDGET_GIB.
std::uint64_t memoryBudgetBytes();
// Throws Error("WHAT needs N GiB, over iblx's memory budget of B GiB ...") when bytes exceeds the budget, so
// that a size read from a header or a flag is refused before it is allocated.
void checkMemoryBudget(std::string_view what, std::uint64_t bytes);
// Vulkan guarantees every device storage buffers of 2^27 bytes (maxStorageBufferRange's required minimum); a
// table larger than that fits only where the device allows it. A reader calls checkDeviceTable with a table's
// size before it reads the table's body, so that one no buffer of the device holds is refused at once rather
// than after a long read. The device's limit comes from the query of the innermost DeviceTableLimit (a
// command's, for the device it will render on), asked only for tables above 2^27 bytes, since learning it
// means starting the device; without one, no such check is made here (the upload still refuses the table).
class DeviceTableLimit {
 public:
  explicit DeviceTableLimit(std::function<std::uint64_t()> largestBuffer);
  ~DeviceTableLimit();
  DeviceTableLimit(const DeviceTableLimit&) = delete;
  DeviceTableLimit& operator=(const DeviceTableLimit&) = delete;

 private:
  std::function<std::uint64_t()> previous_;
};
inline constexpr std::uint64_t kGuaranteedDeviceBufferBytes = std::uint64_t(1) << 27;
// Throws Error("WHAT needs N MiB, more than the device's largest storage buffer (M MiB)") when it does not
// fit.
void checkDeviceTable(std::string_view what, std::uint64_t bytes);
// "1.5 GiB", "12 MiB", "640 bytes": sizes in messages.
std::string formatBytes(std::uint64_t bytes);

// An output file written atomically: the data goes to a temporary file beside path, and commit() checks the
// write and the close and renames it to path. Destroyed without commit() (an exception, Ctrl-C handled by the
// command) it removes the temporary, so path never holds a partial file and an existing file is kept; a
// process killed outright may leave the hidden temporary (.NAME.tmp-PID-N). The rename replaces a symbolic
// link at path rather than writing through it, and a device (/dev/null) cannot be an output.
class AtomicOutput {
 public:
  explicit AtomicOutput(std::filesystem::path path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // For libraries that write by file name (OpenEXR, stb): they write here, then commit() renames.
  const std::filesystem::path& temporaryPath() const { return temporary_; }
  // A binary stream on the temporary file, opened on first use.
  std::ofstream& stream();
  // Throws Error("cannot write PATH: REASON") if any write or the close failed, or the rename fails.
  void commit();

 private:
  std::filesystem::path path_, temporary_;
  std::ofstream stream_;
  bool opened_ = false, committed_ = false;
};

// Writes bytes to path through an AtomicOutput.
void writeFileAtomically(const std::filesystem::path& path, std::span<const unsigned char> bytes);
void writeFileAtomically(const std::filesystem::path& path, std::string_view text);

}  // namespace iblx
