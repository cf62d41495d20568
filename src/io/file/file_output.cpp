#include "vknerf/file_output.h"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "vknerf/error.h"

namespace vknerf {
namespace {

namespace fs = std::filesystem;

std::string reason(int err) { return std::strerror(err); }

// write(2) until done, retrying short writes and EINTR; false with errno set on failure.
bool writeAll(int fd, const char* p, size_t n) {
  while (n > 0) {
    ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += w;
    n -= size_t(w);
  }
  return true;
}

// The folder a new file at `path` goes into ("." for a bare file name).
fs::path folderOf(const std::string& path) {
  fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

bool isSpecialFile(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

// Opens a special file for writing in place (truncating what can be truncated).
int openInPlace(const std::string& path) {
  int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) throw Error(path + ": cannot write: " + reason(errno));
  return fd;
}

void closeChecked(int fd, bool ok, int err, const std::string& path) {
  if (::close(fd) != 0 && ok) ok = false, err = errno;
  if (!ok) throw Error(path + ": write failed: " + reason(err));
}

void writeInPlace(const std::string& path, const void* data, size_t size) {
  const int fd = openInPlace(path);
  const bool ok = writeAll(fd, static_cast<const char*>(data), size);
  closeChecked(fd, ok, errno, path);
}

// The bytes of the file `from` into the special file `path`, every write checked.
void copyInPlace(const std::string& from, const std::string& path) {
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) throw Error(path + ": cannot read back " + from + ": " + reason(errno));
  int fd = -1;
  try {
    fd = openInPlace(path);
  } catch (...) {
    ::close(in);
    throw;
  }
  bool ok = true;
  int err = 0;
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(in, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) ok = false, err = errno;
    if (n <= 0) break;
    if (!writeAll(fd, buf, size_t(n))) {
      ok = false, err = errno;
      break;
    }
  }
  ::close(in);
  closeChecked(fd, ok, err, path);
}

// The temporary files not yet committed, where a signal handler can read them: fixed slots, each
// claimed (kFilling) while its path is copied in and readable once kActive. A path too long for a
// slot is still removed on every other way out.
constexpr int kSlots = 64;
constexpr int kFree = 0, kFilling = 1, kActive = 2;
struct Slot {
  std::atomic<int> state{kFree};
  std::atomic<pid_t> writer{0};
  char path[4096];
};
Slot slots[kSlots];

int registerTemporary(const std::string& path) {
  if (path.size() >= sizeof(Slot::path)) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(slots[i].path, path.c_str(), path.size() + 1);
    slots[i].writer.store(0);
    slots[i].state.store(kActive, std::memory_order_release);
    return i;
  }
  return -1;
}

void unregisterTemporary(int slot) {
  if (slot >= 0) slots[slot].state.store(kFree, std::memory_order_release);
}

// TemporaryFilesBusy sections in progress, and whether removeTemporaryFiles() has begun (then no
// section begins any more). Sequentially consistent: a section counts itself before it reads
// `removing`, the removal sets `removing` before it reads the count, so one of them sees the other.
std::atomic<int> busySections{0};
std::atomic<bool> removing{false};

extern "C" void removeTemporaryFilesAndDie(int sig) {
  removeTemporaryFiles();
  ::signal(sig, SIG_DFL);
  ::raise(sig);  // delivered when the handler returns: the process ends as the signal would have
}

}  // namespace

TemporaryFile::TemporaryFile(const std::string& target, const std::string& suffix) : target_(target) {
  // A name of our own (O_EXCL: two writers of the same target in one process or several never share
  // a temporary file).
  static std::atomic<unsigned> counter{0};
  const std::string stem = isSpecialFile(target)
                               ? (fs::temp_directory_path() / ("vknerf-" + fs::path(target).filename().string())).string()
                               : target;
  for (int attempt = 0; fd_ < 0 && attempt < 100; ++attempt) {
    path_ = stem + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++) + suffix;
    TemporaryFilesBusy created;  // the file is listed before a signal can remove the others
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);  // mode as the umask allows
    if (fd_ >= 0) slot_ = registerTemporary(path_);
    if (fd_ < 0 && errno != EEXIST) break;
  }
  if (fd_ < 0) {
    const int err = errno;
    const fs::path folder = folderOf(path_);
    std::error_code ec;
    std::string where;
    if (err == ENOENT)
      where = fs::is_directory(folder, ec) ? " (folder " + folder.string() + " does not take new files)"
                                           : " (folder " + folder.string() + " does not exist)";
    throw Error(target + ": cannot write: " + reason(err) + where);
  }
}

TemporaryFile::~TemporaryFile() { discard(); }

void TemporaryFile::setWriter(pid_t pid) {
  if (slot_ >= 0) slots[slot_].writer.store(pid);
}

void TemporaryFile::discard() {
  if (fd_ >= 0) ::close(fd_), fd_ = -1;
  if (!path_.empty()) ::unlink(path_.c_str());
  path_.clear();
  unregisterTemporary(slot_);
  slot_ = -1;
}

void TemporaryFile::commit() {
  if (path_.empty()) throw Error(target_ + ": the temporary file is already gone");
  if (slot_ >= 0) slots[slot_].writer.store(0);  // the writer has finished
  try {
    // fsync is per file, not per descriptor: it also syncs what another program wrote.
    bool ok = fd_ >= 0 && ::fsync(fd_) == 0;
    int err = errno;
    if (fd_ >= 0 && ::close(fd_) != 0 && ok) ok = false, err = errno;
    fd_ = -1;
    if (!ok) throw Error(target_ + ": write failed: " + reason(err));
    struct stat st;
    if (::stat(target_.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
      throw Error(target_ + ": cannot write: it is a folder");
    if (isSpecialFile(target_)) {
      copyInPlace(path_, target_);
    } else if (::rename(path_.c_str(), target_.c_str()) != 0) {
      throw Error(target_ + ": write failed: " + reason(errno));
    }
  } catch (...) {
    discard();
    throw;
  }
  discard();  // after a rename: the name is gone already
}

TemporaryFilesBusy::TemporaryFilesBusy() {
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &stop, &before_);
  busySections.fetch_add(1);
  if (!removing.load()) return;
  // A signal is ending the process and its files are being removed: start nothing more (the
  // signal stays held here, so this thread waits for the one handling it to end the process).
  busySections.fetch_sub(1);
  for (;;) ::pause();
}

void TemporaryFilesBusy::withNoSignalHeld(posix_spawnattr_t& attributes) {
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  short flags = 0;
  posix_spawnattr_getflags(&attributes, &flags);
  posix_spawnattr_setflags(&attributes, short(flags | POSIX_SPAWN_SETSIGMASK));
}

TemporaryFilesBusy::~TemporaryFilesBusy() {
  busySections.fetch_sub(1);
  ::pthread_sigmask(SIG_SETMASK, &before_, nullptr);  // a signal held meanwhile is handled now
}

void removeTemporaryFiles() noexcept {
  const int saved = errno;
  removing.store(true);
  // The sections are a few system calls long. sched_yield is a bare system call that takes no lock.
  while (busySections.load() > 0) ::sched_yield();
  for (Slot& s : slots) {
    if (s.state.load(std::memory_order_acquire) != kActive) continue;
    if (const pid_t pid = s.writer.load(); pid > 0) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
      }
    }
    ::unlink(s.path);
  }
  errno = saved;
}

void removeTemporaryFilesOnSignals() {
  struct sigaction sa {};
  sa.sa_handler = removeTemporaryFilesAndDie;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM}) ::sigaction(sig, &sa, nullptr);
}

void writeFileAtomically(const std::string& path, const void* data, size_t size) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw Error(path + ": cannot write: it is a folder");
    if (!S_ISREG(st.st_mode)) return writeInPlace(path, data, size);
  }
  TemporaryFile tmp(path);
  if (!writeAll(tmp.fd(), static_cast<const char*>(data), size))
    throw Error(path + ": write failed: " + reason(errno));  // the destructor removes the file
  tmp.commit();
}

void checkOutputPath(const std::string& path, const std::string& what) {
  if (path.empty()) throw Error(what + ": the output path is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(what + " " + path + ": is a folder, not a file");
  const fs::path folder = folderOf(path);
  if (!fs::exists(folder, ec)) throw Error(what + " " + path + ": folder " + folder.string() + " does not exist");
  if (!fs::is_directory(folder, ec)) throw Error(what + " " + path + ": " + folder.string() + " is not a folder");
  // A special file is written in place: it must itself be writable. A regular file is replaced by a
  // rename: its folder must take the temporary file, which only trying tells for certain.
  if (isSpecialFile(path)) {
    if (::access(path.c_str(), W_OK) != 0) throw Error(what + " " + path + ": is not writable: " + reason(errno));
    return;
  }
  try {
    TemporaryFile probe(path);
  } catch (const Error& e) {
    throw Error(what + " " + e.what());
  }
}

void checkOutputFolder(const std::string& path, const std::string& what) {
  if (path.empty()) throw Error(what + ": the output folder is empty");
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) throw Error(what + " " + path + ": exists and is not a folder");
    try {
      TemporaryFile probe((fs::path(path) / ".vknerf-probe").string());
    } catch (const Error& e) {
      throw Error(what + " " + path + ": the folder does not take new files (" + e.what() + ")");
    }
    return;
  }
  // Created later, with its missing parents: the nearest folder that exists must take a new one.
  fs::path ancestor = fs::absolute(path).lexically_normal();
  while (ancestor.has_relative_path() && ::stat(ancestor.c_str(), &st) != 0) ancestor = ancestor.parent_path();
  if (!S_ISDIR(st.st_mode)) throw Error(what + " " + path + ": " + ancestor.string() + " is not a folder");
  const fs::path probe = ancestor / (".vknerf-probe-" + std::to_string(::getpid()));
  if (::mkdir(probe.c_str(), 0700) != 0)
    throw Error(what + " " + path + ": cannot create a folder in " + ancestor.string() + ": " + reason(errno));
  ::rmdir(probe.c_str());
}

}  // namespace vknerf
