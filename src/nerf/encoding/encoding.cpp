#include "nerf/encoding/encoding.h"

#include "vknerf/error.h"

namespace vknerf::nerf {

void Encoding::recordBackward(gpu::Recorder&, const EncodedRows&, const EncodingGradients&) {
  throw Error("this encoding has no parameters and no input gradient: it has no backward");
}

}  // namespace vknerf::nerf
