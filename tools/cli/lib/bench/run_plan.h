#pragma once
// Who runs what in `bench scenes`: the names of the scenes and builds in the table and in file
// names, and the order of the builds on each scene.
#include <cstddef>
#include <string>
#include <vector>

namespace vknerf::bench {

// The scene's folder name: "tabletop" for assets/tabletop, assets/tabletop/ and
// assets/tabletop/transforms_train.json (a file names its folder), "fruit" for fruit/sparse/0 (a COLMAP
// model folder names the scene above it).
std::string sceneName(const std::string& path);

// One short name per binary, distinct, for the table and file names: the nearest folder, walking up
// from each binary, where all the binaries' paths differ ("before" and "bench-scenes" for
// /work/before/build/vknerf and /work/wt/bench-scenes/build/vknerf); a single binary is named by the
// folder above its build folder. A name given as NAME=PATH is kept. Characters other than letters,
// digits, '.', '_' and '-' become '_'. Throws vknerf::Error when two names come out the same.
std::vector<std::string> buildNames(const std::vector<std::string>& binaries);
// PATH of NAME=PATH (a '=' before any '/'), else the argument itself.
std::string buildPath(const std::string& argument);

// The order of `builds` builds on scene `scene` (0-based): forward on even scenes, backward on odd
// ones, so that no build always runs first on a machine that warms up or slows down.
std::vector<size_t> buildOrder(size_t scene, size_t builds);

}  // namespace vknerf::bench
