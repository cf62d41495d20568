#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding for novel views: the mean of the training photos' vectors (nerfstudio's
// choice for a camera that took no training photo), written as one row. One invocation per vec4
// of the vector, summing the photos in order (deterministic).
layout(local_size_x = 16) in;

layout(std430, binding = 0) readonly buffer Table { vec4 table[]; };
layout(std430, binding = 1) writeonly buffer Mean { vec4 mean[]; };

#include "encoding/appearance_mean_shared.h"

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.dimsVec4) return;
  vec4 s = vec4(0.0);
  for (uint c = 0u; c < pc.numCameras; ++c) s += table[c * pc.dimsVec4 + k];
  mean[k] = pc.numCameras > 0u ? s / float(pc.numCameras) : vec4(0.0);
}
