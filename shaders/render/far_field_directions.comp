#version 450
#extension GL_GOOGLE_include_directive : require
// The learned far field's input: each ray's unit direction, a point on the unit sphere inside the
// hash grid's [-1, 1]^3 (tests/reference/render/far_field.h). One invocation per ray.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };  // (o, t_near), (d, t_far) per ray
layout(std430, binding = 1) writeonly buffer Directions { vec4 directions[]; };

#include "render/far_field_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  directions[i] = vec4(normalize(rays[2u * i + 1u].xyz), 0.0);
}
