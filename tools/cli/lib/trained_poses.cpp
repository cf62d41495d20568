#include "lib/trained_poses.h"

#include <unordered_map>

namespace vknerf::nerf {

size_t useTrainedPoses(std::vector<Camera>& cameras, const std::vector<std::string>& names,
                       const std::vector<TrainedCamera>& trained) {
  std::unordered_map<std::string, const Camera*> byName;
  for (const TrainedCamera& t : trained)
    if (!t.name.empty()) byName.emplace(t.name, &t.camera);
  size_t used = 0;
  for (size_t i = 0; i < cameras.size() && i < names.size(); ++i) {
    const auto it = byName.find(names[i]);
    if (it == byName.end()) continue;
    cameras[i].c2w = it->second->c2w;
    ++used;
  }
  return used;
}

}  // namespace vknerf::nerf
