#version 450
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum, level 1 of 2+: each workgroup scans one block of 1024 uints (16 per
// invocation) and writes the block's total; scan_add.comp then adds the scanned block totals.
// Inputs past inputCount read as 0, so scanning n counts into n + 1 outputs puts the grand total
// at out[n]. Outputs are clamped to `clampTo` when this is the only level.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer In { uint inputs[]; };
layout(std430, binding = 1) writeonly buffer Out { uint outputs[]; };
layout(std430, binding = 2) writeonly buffer BlockSums { uint blockSums[]; };

#include "gpu/scan_blocks_shared.h"

const uint kInvocations = 64u, kPerInvocation = 16u;
const uint kBlock = kInvocations * kPerInvocation;

// Hillis-Steele over the 64 per-invocation sums: 6 rounds of 2 barriers; no subgroup operations,
// so no assumption about subgroup size or layout. On lavapipe a barrier switches between the
// workgroup's 8-lane slices in turn: 64 invocations with 16 values each took half the time of 256
// with 4 (the scans of an 800x800 render's march offsets, 4097 per tile: 80-83 -> 40-41 ms).
shared uint partial[kInvocations];

void main() {
  uint lid = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * kBlock + lid * kPerInvocation;
  uint v[kPerInvocation];
  uint sum = 0u;
  [[unroll]] for (uint j = 0u; j < kPerInvocation; ++j) {
    uint i = base + j;
    v[j] = i < pc.inputCount ? inputs[i] : 0u;
    sum += v[j];
  }
  partial[lid] = sum;
  barrier();
  for (uint step = 1u; step < kInvocations; step <<= 1u) {
    uint add = lid >= step ? partial[lid - step] : 0u;
    barrier();
    partial[lid] += add;
    barrier();
  }
  uint running = partial[lid] - sum;  // exclusive prefix of this invocation within the block
  [[unroll]] for (uint j = 0u; j < kPerInvocation; ++j) {
    uint i = base + j;
    if (i < pc.outputCount) outputs[i] = min(running, pc.clampTo);
    running += v[j];
  }
  if (pc.writeBlockSums != 0u && lid == kInvocations - 1u) blockSums[gl_WorkGroupID.x] = partial[kInvocations - 1u];
}
