#version 450
// The density (the field's w) of samples [first, first + count) into the grid.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Field { vec4 field[]; };  // rgb, sigma
layout(std430, binding = 1) writeonly buffer Grid { float density[]; };

layout(push_constant) uniform Push {
  uint first;
  uint count;
} pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.count) density[pc.first + i] = field[i].w;
}
