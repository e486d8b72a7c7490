// An exclusive lock on a file, shared by processes on one machine and, through the NFS lock manager, by the
// machines of a cluster that mount one directory: the ground-truth cache and `iblx study` use it so that
// several tasks needing the same artefact compute it once and the others wait and read it.
#pragma once

#include <filesystem>
#include <string>
#include <utility>

namespace iblx {

// What to do when another process holds the lock: wait for it, or refuse at once.
enum class LockBusy { Wait, Refuse };

class FileLock {
 public:
  // Holds the lock on `path`: an existing directory itself (nothing is created in it), else a file, created
  // if missing and never removed (removing it would let two processes hold locks on different files of one
  // name). `what` names the artefact: while another process holds the lock, LockBusy::Wait prints "waiting
  // for another iblx computing WHAT" and blocks until it is free; LockBusy::Refuse throws Error("WHAT is
  // being written by another iblx ..."). Throws Error naming the path when it cannot be created or locked.
  FileLock(const std::filesystem::path& path, const std::string& what, LockBusy busy = LockBusy::Wait);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  FileLock(FileLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}  // the lock moves with it

 private:
  int fd_ = -1;
};

}  // namespace iblx
