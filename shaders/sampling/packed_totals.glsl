// The totals of a packed batch (src/nerf/sampling/packed_layout.h): the sample count and a
// VkDispatchIndirectCommand for a per-sample kernel of `localSize` lanes, the groups split over x
// (at most maxGroupsX) and y. The includer declares `uint totals[4]` in a writable buffer.
#ifndef VKNERF_PACKED_TOTALS_GLSL
#define VKNERF_PACKED_TOTALS_GLSL

void writePackedTotals(uint total, uint localSize, uint maxGroupsX) {
  uint groups = total / localSize + (total % localSize != 0u ? 1u : 0u);
  uint gy = groups / maxGroupsX + (groups % maxGroupsX != 0u ? 1u : 0u);
  uint gx = gy == 0u ? 0u : groups / gy + (groups % gy != 0u ? 1u : 0u);
  totals[0] = total;
  totals[1] = gx;
  totals[2] = gy == 0u ? 1u : gy;
  totals[3] = 1u;
}

#endif
