#version 450
// Exclusive prefix sum, level 1 of 2+: each workgroup scans one block of 1024 uints (4 per
// invocation) and writes the block's total; scan_add.comp then adds the scanned block totals.
// Inputs past inputCount read as 0, so scanning n counts into n + 1 outputs puts the grand total
// at out[n]. Outputs are clamped to `clampTo` when this is the only level.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer In { uint inputs[]; };
layout(std430, binding = 1) writeonly buffer Out { uint outputs[]; };
layout(std430, binding = 2) writeonly buffer BlockSums { uint blockSums[]; };

layout(push_constant) uniform Push {
  uint inputCount;
  uint outputCount;
  uint clampTo;
  uint writeBlockSums;
} pc;

const uint kPerInvocation = 4u;
const uint kBlock = 256u * kPerInvocation;

// Hillis-Steele over the 256 per-invocation sums: 8 barrier rounds, which cost next to nothing
// next to the loads; no subgroup operations, so no assumption about subgroup size or layout.
shared uint partial[256];

void main() {
  uint lid = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * kBlock + lid * kPerInvocation;
  uint v[kPerInvocation];
  uint sum = 0u;
  for (uint j = 0u; j < kPerInvocation; ++j) {
    uint i = base + j;
    v[j] = i < pc.inputCount ? inputs[i] : 0u;
    sum += v[j];
  }
  partial[lid] = sum;
  barrier();
  for (uint step = 1u; step < 256u; step <<= 1u) {
    uint add = lid >= step ? partial[lid - step] : 0u;
    barrier();
    partial[lid] += add;
    barrier();
  }
  uint running = partial[lid] - sum;  // exclusive prefix of this invocation within the block
  for (uint j = 0u; j < kPerInvocation; ++j) {
    uint i = base + j;
    if (i < pc.outputCount) outputs[i] = min(running, pc.clampTo);
    running += v[j];
  }
  if (pc.writeBlockSums != 0u && lid == 255u) blockSums[gl_WorkGroupID.x] = partial[255];
}
