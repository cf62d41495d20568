#version 450
// Photometric MSE loss per ray: the target is the training pixel (RGBA8) alpha-blended over that
// ray's background; L = sum over rays and rgb of (pred - target)^2 / (3 R). Writes
// gradScale * dL/dpred (opacity component 0) and one partial sum of squared errors per workgroup,
// reduced in shared memory so no float atomics are needed.
// The training pixels lie in several buffers (cameras[c].size.w names the one holding camera c's
// image, size.z its first pixel there); one dispatch sees kPixelBindings of them, from
// pc.firstBinding on, and handles the rays whose image lies there. Later dispatches of the same
// batch add their sums to the partials the first one wrote.
#extension GL_GOOGLE_include_directive : require
#include "rays/camera.glsl"

layout(local_size_x = 128) in;

layout(std430, binding = 0) readonly buffer Pred { vec4 pred[]; };            // (r, g, b, opacity)
layout(std430, binding = 1) readonly buffer PixelIds { uvec2 pixelIds[]; };   // (camera, pixel)
layout(std430, binding = 2) readonly buffer Cameras { Camera cameras[]; };
layout(std430, binding = 3) readonly buffer Background { vec4 background[]; };
layout(std430, binding = 4) writeonly buffer DPred { vec4 dPred[]; };
layout(std430, binding = 5) buffer Partials { float partials[]; };            // one per workgroup
// RGBA8 pixels, R in the low byte: kPixelBindings (PhotometricLoss::kPixelBindings) buffers.
layout(std430, binding = 6) readonly buffer Pixels0 { uint pixels0[]; };
layout(std430, binding = 7) readonly buffer Pixels1 { uint pixels1[]; };
layout(std430, binding = 8) readonly buffer Pixels2 { uint pixels2[]; };
layout(std430, binding = 9) readonly buffer Pixels3 { uint pixels3[]; };
layout(std430, binding = 10) readonly buffer Pixels4 { uint pixels4[]; };
layout(std430, binding = 11) readonly buffer Pixels5 { uint pixels5[]; };
layout(std430, binding = 12) readonly buffer Pixels6 { uint pixels6[]; };
layout(std430, binding = 13) readonly buffer Pixels7 { uint pixels7[]; };
const uint kPixelBindings = 8u;
// The rays to count when only the device knows them (a training batch cut to whole rays): the rays
// at and past it get no gradient and no error, and the mean is over the rays below it.
#define ROW_LIMIT_BINDING 14
#include "gpu/row_limit.glsl"

#include "loss/loss_photometric_shared.h"

shared float sums[128];

// A switch on separate bindings rather than an array of buffers indexed by a divergent value,
// which would need the descriptor-indexing feature.
uint pixelAt(uint slot, uint i) {
  switch (slot) {
    case 0u: return pixels0[i];
    case 1u: return pixels1[i];
    case 2u: return pixels2[i];
    case 3u: return pixels3[i];
    case 4u: return pixels4[i];
    case 5u: return pixels5[i];
    case 6u: return pixels6[i];
    default: return pixels7[i];
  }
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint l = gl_LocalInvocationID.x;
  float sq = 0.0;
  uint numRays = limitedRows(pc.numRays, pc.limitBase);
  if (i < numRays) {
    uvec2 id = pixelIds[i];
    uvec4 size = cameras[id.x].size;
    uint slot = size.w - pc.firstBinding;  // wraps to a huge value below firstBinding
    if (slot < kPixelBindings) {
      vec4 px = unpackUnorm4x8(pixelAt(slot, size.z + id.y));
      vec3 target = px.rgb * px.a + background[i].rgb * (1.0 - px.a);
      vec3 e = pred[i].rgb - target;
      sq = dot(e, e);
      dPred[i] = vec4(e * (pc.gradScale * 2.0 / (3.0 * float(numRays))), 0.0);
    }
  } else if (i < pc.numRays) {
    dPred[i] = vec4(0.0);  // a ray past the device count: no gradient
  }
  sums[l] = sq;
  barrier();
  for (uint s = gl_WorkGroupSize.x / 2u; s > 0u; s >>= 1u) {
    if (l < s) sums[l] += sums[l + s];
    barrier();
  }
  if (l == 0u) partials[gl_WorkGroupID.x] = (pc.firstBinding == 0u ? 0.0 : partials[gl_WorkGroupID.x]) + sums[0];
}
