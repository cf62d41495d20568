#version 450
#extension GL_GOOGLE_include_directive : require
// One round of a render that marches its rays in segments (src/nerf/render/segment_accumulator.h):
// the compositor has composited each ray's latest segment from a transmittance of 1 over a black
// background; this puts it behind what the ray has gathered so far (the "over" operator):
//   C += T C_seg,  depth += T depth_seg,  T *= 1 - opacity_seg,
// and decides whether the ray goes on. It does while its march filled the round's cap (samples may
// lie past it), its transmittance is still at least minTransmittance (instant-ngp's early
// termination: what lies behind adds less than that times its brightest colour) and the round is
// not the last: its t_near becomes the t after its last sample, where the next march resumes.
// Otherwise t_near becomes -1 (the march gives it no more samples) and its background is added.
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Rays { vec4 rays[]; };                   // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };    // numRays + 1: the march's
layout(std430, binding = 2) readonly buffer Samples { vec2 samples[]; };    // (t, delta)
layout(std430, binding = 3) readonly buffer SegmentColor { vec4 segmentColor[]; };  // (rgb, opacity)
layout(std430, binding = 4) readonly buffer SegmentDepth { float segmentDepth[]; };
layout(std430, binding = 5) readonly buffer Background { vec4 background[]; };
layout(std430, binding = 6) buffer Color { vec4 color[]; };  // (rgb, opacity) gathered so far
layout(std430, binding = 7) buffer Depth { float depth[]; };
layout(std430, binding = 8) buffer Counters {
  uint liveRays;     // rays that go on after this round
  uint shadedSamples; // samples composited
};

#include "render/accumulate_segment_shared.h"

void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.numRays) return;
  if (pc.first == 0u && !(rays[2u * r].w >= 0.0)) return;  // ended in an earlier round
  vec3 rgb = vec3(0.0);
  float T = 1.0, d = 0.0;
  if (pc.first == 0u) {
    vec4 c = color[r];
    rgb = c.rgb, T = 1.0 - c.a, d = depth[r];
  }
  vec4 s = segmentColor[r];
  rgb += T * s.rgb;
  d += T * segmentDepth[r];
  T *= 1.0 - s.a;
  uint end = offsets[r + 1u], n = end - offsets[r];
  if (n > 0u) atomicAdd(shadedSamples, n);
  float next = -1.0;
  if (pc.last == 0u && n == pc.cap && T >= pc.minTransmittance) {
    vec2 lastSample = samples[end - 1u];
    precise float t = lastSample.x + lastSample.y;  // the march's next point (its step, or t_far)
    if (t < rays[2u * r + 1u].w) next = t;
  }
  if (next < 0.0)
    rgb += T * background[r].rgb;
  else
    atomicAdd(liveRays, 1u);
  rays[2u * r].w = next;
  color[r] = vec4(rgb, 1.0 - T);
  depth[r] = d;
}
