#include "vknerf/checkpoint_scene.h"

#include "io/checkpoint/checkpoint.h"
#include "io/checkpoint/checkpoint_record.h"

namespace vknerf {

void checkTrainedOn(const std::string& checkpoint, const Dataset& scene, const DatasetOptions& options) {
  auto ck = io::Checkpoint::load(checkpoint);
  io::SceneFacts facts;
  facts.box = scene.bounds;
  // A box carved from the alpha masks moves with the resolution and split the masks are read at
  // (by 6% of the sample scene's height between --downscale 1 and 8): a tenth of its extent.
  if (scene.boundsSource == "cameras+alpha") facts.boxTolerance = 0.1f;
  if (options.split == "train") facts.cameras = uint32_t(scene.cameras.size());
  io::CheckpointRecord(ck).checkScene(facts);
}

bool looksLikeCheckpoint(const std::string& path) { return io::Checkpoint::startsWithMagic(path); }

}  // namespace vknerf
