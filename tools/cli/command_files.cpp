#include "command_files.h"

#include <sys/stat.h>

#include <cctype>
#include <filesystem>
#include <optional>

#include "checks.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/scene_files.h"

namespace vknerf::cli {
namespace {

namespace fs = std::filesystem;

// What a path names: the device and inode of the file or folder when it exists; else those of its
// folder and its own name (a file not created yet); else, with no folder either, its absolute path.
struct FileId {
  dev_t dev = 0;
  ino_t ino = 0;
  std::string name;
  bool operator==(const FileId&) const = default;
};

// Absolute and without "." or "..", nor a trailing separator ("scene/" is "scene").
fs::path normal(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec).lexically_normal();
  if (!p.has_filename() && p.has_relative_path()) p = p.parent_path();
  return p;
}

std::optional<FileId> statId(const fs::path& p) {
  struct stat st;
  if (::stat(p.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino, ""};
}

FileId idOf(const std::string& path) {
  const fs::path p = normal(path);
  if (auto id = statId(p)) return *id;
  if (auto folder = statId(p.parent_path())) return {folder->dev, folder->ino, p.filename().string()};
  return {0, 0, p.string()};
}

// What a clash with a scene's own files adds to the message.
constexpr const char* kSceneFiles = " (its poses, COLMAP model, poses_bounds.npy and images)";

bool exists(const std::string& path) { return statId(normal(path)).has_value(); }

bool isFolder(const std::string& path) {
  struct stat st;
  return ::stat(normal(path).c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// True when the existing folder `folder` holds `path` at any depth, symlinks on the way resolved.
bool holds(const std::string& folder, const std::string& path) {
  if (folder.empty()) return false;
  const auto f = statId(normal(folder));
  if (!f) return false;
  std::error_code ec;
  fs::path p = fs::weakly_canonical(normal(path), ec);
  if (ec) p = normal(path);
  for (fs::path q = p.parent_path();; q = q.parent_path()) {
    if (statId(q) == f) return true;
    if (q == q.parent_path()) return false;  // the root
  }
}

// A file that is not a regular one: a device or a pipe, written in place, never replaced.
bool isSpecial(const std::string& path) {
  struct stat st;
  return ::stat(normal(path).c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

// The folder a scene argument names: the scene folder, or the folder of a transforms JSON / COLMAP
// file; "" for a scene that does not exist (reading it fails with its own message).
std::string sceneFolder(const std::string& scene) {
  if (isFolder(scene)) return scene;
  return exists(scene) ? normal(scene).parent_path().string() : "";
}

}  // namespace

CommandFiles& CommandFiles::add(const std::string& path, const std::string& what, Kind kind) {
  if (!path.empty()) entries_.push_back({path, what, kind});
  return *this;
}

CommandFiles& CommandFiles::input(const std::string& path, const std::string& what) { return add(path, what, Kind::input); }
CommandFiles& CommandFiles::scene(const std::string& path, const std::string& what) { return add(path, what, Kind::scene); }
CommandFiles& CommandFiles::output(const std::string& path, const std::string& what) { return add(path, what, Kind::output); }
CommandFiles& CommandFiles::outputFolder(const std::string& path, const std::string& what) {
  return add(path, what, Kind::outputFolder);
}
CommandFiles& CommandFiles::replacedFolder(const std::string& path, const std::string& what) {
  return add(path, what, Kind::replacedFolder);
}

void CommandFiles::clash(const Entry& out, const std::string& relation, const Entry& other, const std::string& note) const {
  const bool input = other.kind == Kind::input || other.kind == Kind::scene;
  const std::string named = (other.what.rfind('-', 0) == 0 ? "" : "the ") + other.what + " " + other.path;
  const std::string advice = !input ? "give each output its own path"
                             : out.kind == Kind::output ? "choose another output"
                                                        : "choose a folder apart from it";
  throw UsageError(command_ + ": " + out.what + " " + out.path + " " + relation + " " + named + note + "; " + advice);
}

void CommandFiles::checkOutputAgainst(const Entry& out, const Entry& other) const {
  const bool outFolder = out.kind != Kind::output;
  const bool otherIsInput = other.kind == Kind::input || other.kind == Kind::scene;
  // Two outputs into one device or pipe (/dev/null, /dev/stdout) are both written, one after the other.
  if (!otherIsInput && isSpecial(out.path) && isSpecial(other.path)) return;
  if (idOf(out.path) == idOf(other.path))
    clash(out, out.kind == Kind::outputFolder ? "is" : "would replace", other,
          isFolder(other.path) ? " (the same folder)" : " (the same file)");
  if (!otherIsInput) return;  // two outputs: only the same path clashes
  const std::string folder = other.kind == Kind::scene ? sceneFolder(other.path) : isFolder(other.path) ? other.path : "";
  if (other.kind == Kind::scene && !folder.empty() && idOf(out.path) == idOf(folder)) clash(out, "is the folder of", other);
  if (outFolder && !folder.empty()) {
    if (holds(out.path, folder)) clash(out, "holds", other);
    if (holds(folder, out.path)) clash(out, "lies inside", other);
  }
  if (out.kind == Kind::replacedFolder && holds(out.path, other.path)) clash(out, "holds", other, ", and is replaced as a whole");
  // A scene's own files, even those this run does not read (another split, the COLMAP model beside
  // the transforms): other names in the scene folder (a model, a report) are fine.
  if (out.kind == Kind::output && other.kind == Kind::scene && !folder.empty() && declaresSceneFile(folder, out.path))
    clash(out, "is one of the files of", other, kSceneFiles);
}

bool CommandFiles::declaresFolder(const std::string& folder) const {
  for (const Entry& e : entries_)
    if (e.kind == Kind::outputFolder && normal(e.path) == normal(folder)) return true;
  return false;
}

void CommandFiles::check() const {
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Entry& out = entries_[i];
    if (out.kind == Kind::input || out.kind == Kind::scene) continue;
    for (size_t j = 0; j < entries_.size(); ++j) {
      const bool otherIsOutput = entries_[j].kind != Kind::input && entries_[j].kind != Kind::scene;
      if (j == i || (otherIsOutput && j < i)) continue;  // each pair of outputs once
      checkOutputAgainst(out, entries_[j]);
    }
  }
  // A scene this run was not given is as much an input: `export cameras -o scene/transforms.json`
  // would replace the poses of a scene that may be read later (vknerf/scene_files.h).
  for (const Entry& out : entries_) {
    if (out.kind == Kind::output)
      if (const auto scene = sceneDeclaring(out.path))
        clash(out, "is one of the files of", {scene->string(), "scene", Kind::scene}, kSceneFiles);
    // Files written into a scene's photo or model folder (or a folder replacing it) would be read
    // as the scene's own.
    if (out.kind == Kind::outputFolder || out.kind == Kind::replacedFolder)
      if (const auto scene = sceneHoldingFolder(out.path))
        clash(out, "lies in the photos or model of", {scene->string(), "scene", Kind::scene});
  }
  for (const Entry& e : entries_) {
    switch (e.kind) {
      case Kind::output:
        // A file in a declared output folder that is still to be made: that folder's check stands
        // for it (it is made by createFolders(), before anything is written).
        if (!exists(normal(e.path).parent_path().string()) && declaresFolder(normal(e.path).parent_path().string())) break;
        checkOutputPath(e.path, e.what);
        break;
      case Kind::outputFolder:
        checkOutputFolder(e.path, e.what);
        break;
      case Kind::replacedFolder:
        // Built beside it, then renamed over it: its own folder must take a new folder. A file
        // there would be replaced by the folder: never what was meant.
        if (exists(e.path) && !isFolder(e.path)) throw Error(e.what + " " + e.path + ": exists and is not a folder");
        checkOutputFolder(normal(e.path).parent_path().string(), e.what + " " + e.path + ": its folder");
        break;
      case Kind::input:
      case Kind::scene:
        break;
    }
  }
}

void CommandFiles::createFolders() const {
  for (const Entry& e : entries_) {
    if (e.kind != Kind::outputFolder) continue;
    std::error_code ec;
    fs::create_directories(e.path, ec);
    if (ec || !isFolder(e.path))
      throw Error(e.what + " " + e.path + ": cannot create it: " + (ec ? ec.message() : "exists and is not a folder"));
  }
}

}  // namespace vknerf::cli
