#version 450
// The packed batch's size where later kernels can find it without a CPU round trip: the total
// sample count and a VkDispatchIndirectCommand for a per-sample kernel of `localSize` lanes, the
// groups split over x (at most maxGroupsX) and y.
layout(local_size_x = 1) in;

layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };  // numRays + 1
layout(std430, binding = 1) writeonly buffer Totals { uint totals[4]; };

layout(push_constant) uniform Push {
  uint numRays;
  uint localSize;
  uint maxGroupsX;
} pc;

void main() {
  uint total = offsets[pc.numRays];
  uint groups = total / pc.localSize + (total % pc.localSize != 0u ? 1u : 0u);
  uint gy = groups / pc.maxGroupsX + (groups % pc.maxGroupsX != 0u ? 1u : 0u);
  uint gx = gy == 0u ? 0u : groups / gy + (groups % gy != 0u ? 1u : 0u);
  totals[0] = total;
  totals[1] = gx;
  totals[2] = gy == 0u ? 1u : gy;
  totals[3] = 1u;
}
