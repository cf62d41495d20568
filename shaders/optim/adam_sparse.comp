#version 450
#extension GL_GOOGLE_include_directive : require
// Adam over the sparse part of a table, pass 2: steps the vec4s adam_touched.comp listed, one an
// invocation, dispatched for the list's length on the device (row_limit.glsl); within a vec4 a
// parameter whose gradient is exactly 0 keeps p, m and v, as everywhere in the sparse part. The
// listed gradients are zeroed; the others were zero already. Reads through texel buffers, writes
// through vec4 SSBO views of the same memory, as adam.comp (why there).
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) uniform readonly imageBuffer P4;
layout(binding = 1, rgba32f) uniform readonly imageBuffer G4;
layout(binding = 2, rgba32f) uniform readonly imageBuffer M4;
layout(binding = 3, rgba32f) uniform readonly imageBuffer V4;
layout(std430, binding = 4) readonly buffer Touched { uint touched[]; };
layout(std430, binding = 5) writeonly buffer ParamsW { vec4 p4w[]; };
layout(std430, binding = 6) writeonly buffer GradsW { vec4 g4w[]; };
layout(std430, binding = 7) writeonly buffer Moment1W { vec4 m4w[]; };
layout(std430, binding = 8) writeonly buffer Moment2W { vec4 v4w[]; };
#define ROW_LIMIT_BINDING 9
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
  p4w[k] = p;
  m4w[k] = m;
  v4w[k] = v;
  g4w[k] = vec4(0.0);
}
