#pragma once
// Every file vknerf writes (checkpoints, images, depth maps, JSON and CSV reports, videos) goes
// through writeFileAtomically or, when another program fills it (ffmpeg), a TemporaryFile: the
// target then holds either its previous content or all of the new bytes, never a truncated file;
// every failure (full disk, missing folder, no permission) is an error rather than a silent 0-byte
// file; and no temporary file outlives the process, whether it ends by an error or by a signal.
#include <signal.h>
#include <spawn.h>
#include <sys/types.h>

#include <cstddef>
#include <string>
#include <string_view>

namespace vknerf {

// Writes to a temporary file beside `path`, checks every write and the close, flushes it to disk
// (fsync) and renames it over `path`. A target that exists and is not a regular file (a terminal,
// a pipe, /dev/null, /dev/full) is written in place with the same checks, since a special file
// cannot be replaced by a rename. On failure the temporary file is removed and vknerf::Error
// names `path` and the reason.
void writeFileAtomically(const std::string& path, const void* data, size_t size);
inline void writeFileAtomically(const std::string& path, std::string_view text) {
  writeFileAtomically(path, text.data(), text.size());
}

// A new, empty temporary file for the output `target`, to be filled by this process (fd()) or by a
// program given path(), and made the output by commit(). Until then it is removed on every way out:
// by the destructor (an error, an exception) and by removeTemporaryFiles() (a signal).
class TemporaryFile {
 public:
  // Creates "<target>.tmp.<pid>.<n><suffix>" beside a regular (or not yet existing) target, so that
  // the final rename stays on one file system; beside a special target (/dev/null, a pipe), which
  // is written in place, it goes in the temporary directory instead. Throws vknerf::Error naming
  // `target` when the folder does not take new files.
  explicit TemporaryFile(const std::string& target, const std::string& suffix = "");
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  const std::string& path() const { return path_; }
  int fd() const { return fd_; }  // open for writing
  // The program filling the file: a signal stops it before removing the file, so that the program
  // cannot create it again.
  void setWriter(pid_t pid);
  // Syncs the file and renames it over the target, or copies it into a target that is not a regular
  // file and removes it. Throws vknerf::Error naming the target; the temporary file is then removed.
  void commit();
  // Removes the file now (its writer, if any, must have stopped).
  void discard();

 private:
  std::string target_, path_;
  int fd_ = -1;
  int slot_ = -1;  // its entry in the list removeTemporaryFiles() reads
};

// Removes every TemporaryFile of this process not yet committed, stopping (SIGKILL) and reaping
// the programs filling them first. Async-signal-safe: for a signal handler about to end the process.
// It first waits for every TemporaryFilesBusy to end, and no new one begins after it is called.
void removeTemporaryFiles() noexcept;

// A step that a signal must not cut in two: between creating a file and listing it for removal, or
// between starting the program that fills a TemporaryFile and naming it (setWriter), a signal
// handled on another thread would remove the file and leave that program to create it again. While
// one lives, removeTemporaryFiles() waits, and SIGINT and SIGTERM are held in this thread (so that
// no handler waits on the thread it interrupted). A program started meanwhile would inherit that
// mask: start it with attributes given to withNoSignalHeld.
class TemporaryFilesBusy {
 public:
  TemporaryFilesBusy();
  ~TemporaryFilesBusy();
  // Sets an empty signal mask for the program started with these attributes.
  static void withNoSignalHeld(posix_spawnattr_t& attributes);
  TemporaryFilesBusy(const TemporaryFilesBusy&) = delete;
  TemporaryFilesBusy& operator=(const TemporaryFilesBusy&) = delete;

 private:
  sigset_t before_;  // this thread's mask before
};

// SIGINT and SIGTERM remove the temporary files (removeTemporaryFiles), then end the process as the
// signal would have (exit status 128 + signal in a shell). A command with handlers of its own
// (`train` saves first) replaces these and calls removeTemporaryFiles() itself before exiting.
void removeTemporaryFilesOnSignals();

// Checks, before any work is spent, that writeFileAtomically(path, ...) can succeed as far as can be
// told up front: `path` is not a folder, its folder exists and takes a new file (one is created and
// removed: permissions alone do not tell, for root or in /proc). Throws vknerf::Error naming `path`
// and the reason. `what` names the output in the message ("model", "--json").
void checkOutputPath(const std::string& path, const std::string& what);

// The same for a folder that files are written into: it is a folder that takes new files, or it
// does not exist yet and its nearest existing ancestor is a folder that takes a new folder.
// Creates nothing that stays.
void checkOutputFolder(const std::string& path, const std::string& what);

}  // namespace vknerf
