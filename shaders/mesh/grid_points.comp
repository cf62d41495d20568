#version 450
// The field's inputs at samples [first, first + count) of a density grid: the sample's world
// position origin + index * spacing mapped from the scene box onto [-1, 1]^3 (as
// shaders/sampling/sample_points.comp maps a ray's samples). Directions are the caller's.
layout(local_size_x = 256) in;

layout(std430, binding = 0) writeonly buffer Positions { vec4 positions[]; };

layout(push_constant) uniform Push {
  uvec4 n;       // samples per axis (w unused)
  vec4 origin;
  vec4 spacing;
  vec4 boxMin;
  vec4 boxMax;
  uint first;
  uint count;
} pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint s = pc.first + i;
  uvec3 idx = uvec3(s % pc.n.x, (s / pc.n.x) % pc.n.y, s / (pc.n.x * pc.n.y));
  vec3 x = pc.origin.xyz + pc.spacing.xyz * vec3(idx);
  positions[i] = vec4(2.0 * (x - pc.boxMin.xyz) / (pc.boxMax.xyz - pc.boxMin.xyz) - 1.0, 0.0);
}
