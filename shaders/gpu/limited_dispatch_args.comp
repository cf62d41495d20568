#version 450
#extension GL_GOOGLE_include_directive : require
// Workgroup counts for dispatches cut to a row count that only the device knows (row_limit.glsl):
// entry (c, k) is the VkDispatchIndirectCommand of chunk c (rows [c * chunkRows, (c + 1) * chunkRows)
// of a `count`-row batch, cut to the limit) for a kernel of rowsPerGroup[k] rows per workgroup.
// Chunks wholly past the limit get 0 groups, so a render recorded for its sample capacity launches
// only the workgroups its marched samples need (lavapipe pays a few us per workgroup, idle or not).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Limit { uint limit; };
layout(std430, binding = 1) writeonly buffer Args { uint args[]; };

#include "gpu/limited_dispatch_args_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.chunks * pc.kinds) return;
  uint c = i / pc.kinds, k = i % pc.kinds;
  uint rows = min(pc.count, limit);
  uint base = c * pc.chunkRows;
  uint n = rows > base ? min(pc.chunkRows, rows - base) : 0u;
  uint perGroup = pc.rowsPerGroup[k];
  args[3u * i] = (n + perGroup - 1u) / perGroup;
  args[3u * i + 1u] = 1u;
  args[3u * i + 2u] = 1u;
}
