#version 450
// Early termination of a packed batch once the field is known: ray r keeps its samples while the
// transmittance in front of them, exp(-sum_{j<i} sigma_j delta_j), is at least the threshold,
// tested as optical depth <= maxOpticalDepth = -ln(threshold) so that no exp() rounding decides.
// Writes the kept count per ray; the prefix sum and march_compact.comp pack the survivors.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 32) in;

layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };  // numRays + 1
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };  // (t, delta)
layout(std430, binding = 2) readonly buffer Field { vec4 field[]; };      // (r, g, b, sigma)
layout(std430, binding = 3) writeonly buffer Kept { uint kept[]; };

layout(push_constant) uniform Push {
  uint numRays;
  float maxOpticalDepth;
} pc;

void main() {
  uint ray = flatIndex(32u);
  if (ray >= pc.numRays) return;
  uint first = offsets[ray], end = offsets[ray + 1u], s = first;
  float depth = 0.0;
  for (; s < end && depth <= pc.maxOpticalDepth; ++s) {
    precise float tau = sanitizeDensity(field[s].w) * samples[s].y;
    depth += tau;
  }
  kept[ray] = s - first;
}
