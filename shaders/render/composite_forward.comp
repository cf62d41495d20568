#version 450
// Volume-rendering compositing, forward: one invocation per ray walks its samples front to back.
// w_i = T_i * alpha_i with T_i = exp(-S_i), S_i the exclusive prefix sum of sigma * delta (a product
// of (1 - alpha) would lose the small factors); C = sum w_i c_i + T_final * bg; depth = sum w_i t_i.
// With early termination (composite.glsl) a ray's samples behind the cut get weight 0 and the
// number it composited goes to keptCounts.
#extension GL_GOOGLE_include_directive : require
#include "render/composite.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RayOffsets { uint rayOffsets[]; };  // numRays + 1 (packed layout)
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };         // (t, delta)
layout(binding = 2, rgba32f) uniform readonly imageBuffer field;                // (r, g, b, sigma)
layout(std430, binding = 3) readonly buffer Background { vec4 perRayBackground[]; };
layout(std430, binding = 4) writeonly buffer Color { vec4 color[]; };           // (r, g, b, opacity)
layout(std430, binding = 5) writeonly buffer Depth { float depth[]; };
layout(std430, binding = 6) writeonly buffer Weights { float weights[]; };
layout(std430, binding = 7) writeonly buffer KeptCounts { uint keptCounts[]; };  // per ray, when writeKept

#include "render/composite_shared.h"

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= pc.numRays) return;
  uint begin = pc.samplesPerRay > 0u ? ray * pc.samplesPerRay : rayOffsets[ray];
  uint end = pc.samplesPerRay > 0u ? begin + pc.samplesPerRay : rayOffsets[ray + 1u];
  vec3 bg = pc.useBackgroundBuffer != 0u ? perRayBackground[ray].rgb : pc.background.rgb;

  float prefix = 0.0;
  vec3 rgb = vec3(0.0);
  float d = 0.0;
  float opaque = 0.0;
  uint i = begin;
  for (; i < end && opaque <= pc.maxOpticalDepth; ++i) {
    vec2 s = samples[i];
    vec4 f = imageLoad(field, int(i));
    float x = opticalDepth(f.w, s.y);
    float w = exp(-prefix) * alphaAndSurvival(x).x;
    weights[i] = w;
    rgb += w * f.rgb;
    d += w * s.x;
    prefix += x;
    opaque += terminationDepth(f.w, s.y);
  }
  if (pc.writeKept != 0u) keptCounts[ray] = i - begin;
  for (; i < end; ++i) weights[i] = 0.0;
  // Opacity as 1 - T_final through the same accurate alpha: a faint ray keeps its few 1e-8s.
  vec2 escape = alphaAndSurvival(prefix);
  color[ray] = vec4(rgb + escape.y * bg, escape.x);
  depth[ray] = d;
}
