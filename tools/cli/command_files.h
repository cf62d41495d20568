#pragma once
// The one place every command declares the files it reads and writes, before any work:
//
//   CommandFiles files("eval");
//   files.input(o.model, "model").scene(o.scene).output(o.json, "--json").output(o.csv, "--csv");
//   files.check();          // a clash is a usage error (exit 2); an unwritable output exit 1
//   ... read and check every input ...
//   files.createFolders();  // only then is anything created
//
// An output must never replace an input, nor another output of the same run. Paths are compared as
// the files they name (device and inode), so another spelling, a symlink or a hard link of an input
// clashes as the same path does; a folder output clashes with an input folder it would hold or lie
// in. An empty path is an option not given, and is skipped: each declaration is one line.
#include <string>
#include <vector>

namespace vknerf::cli {

class CommandFiles {
 public:
  explicit CommandFiles(std::string command) : command_(std::move(command)) {}

  // A file or folder the command reads (a model, a camera path, an image, a folder of photos).
  CommandFiles& input(const std::string& path, const std::string& what);
  // A scene argument: a folder, or a transforms JSON / COLMAP model in one. Its folder is an input
  // folder, and an output inside it may not be one of the scene's own files (vknerf/scene_files.h:
  // transforms*.json, COLMAP's cameras/images/points3D, poses_bounds.npy, photos) even when its
  // name is new to this run. A scene not given is guarded as well: check() refuses an output that
  // any scene folder on disk declares, and a folder output in a scene's images/ or sparse/.
  CommandFiles& scene(const std::string& path, const std::string& what = "scene");
  // A file written whole (vknerf/file_output.h).
  CommandFiles& output(const std::string& path, const std::string& what);
  // A folder that files are written into, created by createFolders().
  CommandFiles& outputFolder(const std::string& path, const std::string& what);
  // A folder replaced as a whole (built beside it, then renamed over it): no input may lie in it.
  CommandFiles& replacedFolder(const std::string& path, const std::string& what);

  // Throws UsageError naming both paths when an output is an input or another output, or a folder
  // output holds or lies in an input folder (a replaced folder: holds any input); then vknerf::Error
  // when an output cannot be written (vknerf::checkOutputPath, checkOutputFolder). Creates nothing.
  void check() const;
  // Creates the output folders (and their missing parents). Throws vknerf::Error naming the folder.
  void createFolders() const;

 private:
  enum class Kind { input, scene, output, outputFolder, replacedFolder };
  struct Entry {
    std::string path, what;
    Kind kind;
  };
  CommandFiles& add(const std::string& path, const std::string& what, Kind kind);
  // "<command>: <out> <relation> <other><note>; <advice>", as a UsageError.
  [[noreturn]] void clash(const Entry& out, const std::string& relation, const Entry& other,
                          const std::string& note = "") const;
  void checkOutputAgainst(const Entry& out, const Entry& other) const;
  // Whether `folder` is declared with outputFolder().
  bool declaresFolder(const std::string& folder) const;

  std::string command_;
  std::vector<Entry> entries_;
};

}  // namespace vknerf::cli
