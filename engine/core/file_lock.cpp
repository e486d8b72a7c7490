// Exclusive file locks (engine/core/file_lock.h).
#include "engine/core/file_lock.h"

#include "engine/core/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace iblx {

FileLock::FileLock(const std::filesystem::path& path, const std::string& what, LockBusy busy) {
  std::error_code ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  fd_ = std::filesystem::is_directory(path, ec) ? ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)
                                                : ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error("cannot create the lock file " + path.string() + ": " + std::strerror(errno));
  // flock() on Linux NFS clients is carried out as a whole-file fcntl() lock, which the NFS lock manager
  // shares between machines.
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
  if (errno == EWOULDBLOCK && busy == LockBusy::Refuse) {
    ::close(fd_);
    throw Error(what + " is being written by another iblx (it holds " + path.string() +
                "); wait for it to finish or write elsewhere");
  }
  if (errno == EWOULDBLOCK) {
    std::fprintf(stderr, "iblx: waiting for another iblx computing %s (%s)\n", what.c_str(), path.c_str());
    int result;
    while ((result = ::flock(fd_, LOCK_EX)) != 0 && errno == EINTR) {
    }
    if (result == 0) return;
  }
  const int error = errno;
  ::close(fd_);
  throw Error("cannot lock " + path.string() + ": " + std::strerror(error));
}

FileLock::~FileLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace iblx
