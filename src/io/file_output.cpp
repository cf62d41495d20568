#include "vknerf/file_output.h"

#include <fcntl.h>
#include <sys/stat.h>
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

void writeInPlace(const std::string& path, const void* data, size_t size) {
  int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) throw Error(path + ": cannot write: " + reason(errno));
  bool ok = writeAll(fd, static_cast<const char*>(data), size);
  int err = errno;
  if (::close(fd) != 0 && ok) ok = false, err = errno;
  if (!ok) throw Error(path + ": write failed: " + reason(err));
}

}  // namespace

void writeFileAtomically(const std::string& path, const void* data, size_t size) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw Error(path + ": cannot write: it is a folder");
    if (!S_ISREG(st.st_mode)) return writeInPlace(path, data, size);
  }
  // A name of our own beside the target (same file system, so the rename is atomic); O_EXCL makes
  // two writers of the same target in one process or several never share a temporary file.
  static std::atomic<unsigned> counter{0};
  std::string tmp;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
    tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);  // mode as the umask allows
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    int err = errno;
    throw Error(path + ": cannot write: " + reason(err) +
                (err == ENOENT ? " (folder " + folderOf(path).string() + " does not exist)" : ""));
  }
  bool ok = writeAll(fd, static_cast<const char*>(data), size) && ::fsync(fd) == 0;
  int err = errno;
  if (::close(fd) != 0 && ok) ok = false, err = errno;
  if (ok && ::rename(tmp.c_str(), path.c_str()) != 0) ok = false, err = errno;
  if (!ok) {
    ::unlink(tmp.c_str());
    throw Error(path + ": write failed: " + reason(err));
  }
}

void checkOutputPath(const std::string& path, const std::string& what) {
  if (path.empty()) throw Error(what + ": the output path is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(what + " " + path + ": is a folder, not a file");
  const fs::path folder = folderOf(path);
  if (!fs::exists(folder, ec)) throw Error(what + " " + path + ": folder " + folder.string() + " does not exist");
  if (!fs::is_directory(folder, ec)) throw Error(what + " " + path + ": " + folder.string() + " is not a folder");
  struct stat st;
  const bool special = ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
  // A special file is written in place: it must itself be writable. A regular file is replaced
  // by a rename: its folder must be writable.
  const std::string probe = special ? path : folder.string();
  if (::access(probe.c_str(), W_OK | (special ? 0 : X_OK)) != 0)
    throw Error(what + " " + path + ": " + (special ? path : "folder " + folder.string()) + " is not writable: " +
                reason(errno));
}

}  // namespace vknerf
