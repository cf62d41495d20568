#version 450
#extension GL_GOOGLE_include_directive : require
// Adam over the sparse part of a table, pass 2: steps the vec4s adam_touched.comp listed, one an
// invocation, dispatched for the list's length on the device (row_limit.glsl); within a vec4 a
// parameter whose gradient is exactly 0 keeps p, m and v, as everywhere in the sparse part. The
// listed gradients are zeroed; the others were zero already.
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) uniform imageBuffer P4;
layout(binding = 1, rgba32f) uniform imageBuffer G4;
layout(binding = 2, rgba32f) uniform imageBuffer M4;
layout(binding = 3, rgba32f) uniform imageBuffer V4;
layout(std430, binding = 4) readonly buffer Touched { uint touched[]; };
#define ROW_LIMIT_BINDING 5
#include "gpu/row_limit.glsl"

#include "optim/adam_sparse_shared.h"
#include "optim/adam_step.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= limitedRows(pc.count, pc.limitBase)) return;
  int k = int(touched[i]);
  vec4 g = imageLoad(G4, k);
  vec4 p = imageLoad(P4, k), m = imageLoad(M4, k), v = imageLoad(V4, k);
  adamStep(p, m, v, g, notEqual(g, vec4(0.0)));
  imageStore(P4, k, p);
  imageStore(M4, k, m);
  imageStore(V4, k, v);
  imageStore(G4, k, vec4(0.0));
}
