#pragma once
// Whether a scene is the one a checkpoint was trained on, as far as the checkpoint records it. A
// model's weights mean something only inside the scene box they were fitted in: another scene's
// cameras rendered through them give views and points of nothing in particular, without a word.
#include <string>

#include "vknerf/dataset.h"

namespace vknerf {

// Throws vknerf::Error naming `checkpoint` when `scene` (loaded with `options`) is not the scene it
// was trained on: its scene box differs (within float printing precision; a box carved from the
// alpha masks, which moves with the resolution and split the masks are read at, within a tenth of
// its extent), or, for the training split, its number of cameras does. `train --resume` checks the
// same, and the training images' size, which there must match.
void checkTrainedOn(const std::string& checkpoint, const Dataset& scene, const DatasetOptions& options);

// Whether the file at `path` begins as a checkpoint does (its magic); false when it cannot be read.
// The checkpoint's contents are not checked: Model::load and Trainer::resume do that.
bool looksLikeCheckpoint(const std::string& path);

}  // namespace vknerf
