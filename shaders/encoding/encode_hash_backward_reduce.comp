#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Hash encoding backward, sort-and-reduce step 3 (HashBackwardMode::SortReduce): sums each entry's
// slots (sorted by entry by encode_hash_backward_scatter.comp) and adds the sum into grads, with no
// float atomics. Every sum is exact in 64-bit fixed point on a grid chosen per entry and feature
// (hash_sort.glsl), so the result does not depend on the slot order the scatter's atomics produced.
//
// One invocation per chunk of CHUNK consecutive slots, never per entry: lavapipe (Mesa 22.3)
// silently ends a shader's loops after 65,535 iterations in total (its loop limiter), and a coarse
// level's entry can hold far more slots than that (every sample of a batch may lie in one cell).
// A chunk bounds every invocation's loops to 3 * CHUNK iterations. Entries wholly inside one chunk
// (nearly all of them on the hashed levels) are finished by that chunk in STAGE 0. An entry that
// spans chunks is "owned" by the chunk holding its first slot, and goes through three stages, one
// dispatch each:
//   STAGE 0: every chunk it touches atomicMax-es its partial max |term| into spanMax[owner]
//            (non-negative floats, inf and NaN order as their bit patterns);
//   STAGE 1: every such chunk adds its fixed-point partial sum, on the grid of the final max, into
//            spanAcc[owner] with two uint atomics (low word, then high word plus the carry out of
//            the low one: the final 64-bit value is exact whatever the interleaving);
//   STAGE 2: the owner converts the sum, adds it into grads and zeroes spanMax/spanAcc for the next
//            pass (they start zeroed when allocated).
#include "encoding/hash_sort.glsl"

layout(local_size_x = 64) in;

#include "encoding/encode_hash_backward_reduce_shared.h"

layout(std430, binding = 0) readonly buffer Cursor { uint cursor[]; };  // end of entry e's slots
// Slots as encode_hash_backward_scatter.comp writes them: RECORD uvec4s, the entry then F values.
const uint RECORD = (FEATURES + 4u) / 4u;
layout(std430, binding = 1) readonly buffer Slots { uvec4 slots[]; };
layout(std430, binding = 2) buffer Grads { float grads[]; };
layout(std430, binding = 3) buffer SpanMax { uint spanMax[]; };  // per owner chunk and feature
layout(std430, binding = 4) buffer SpanAcc { uint spanAcc[]; };  // (low, high) per owner chunk and feature

uint entryBegin(uint e) { return e == 0u ? 0u : cursor[e - 1u]; }
uint slotEntry(uint j) { return slots[j * RECORD].x; }

// Slot j's F values (v[f] for f < FEATURES), read as whole uvec4s.
void slotValues(uint j, out float v[8]) {
  uvec4 q0 = slots[j * RECORD];
  uvec4 q1 = RECORD > 1u ? slots[j * RECORD + 1u] : uvec4(0u);
  uvec4 q2 = RECORD > 2u ? slots[j * RECORD + 2u] : uvec4(0u);
  uint w[12] = uint[12](q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w, q2.x, q2.y, q2.z, q2.w);
  [[unroll]] for (uint f = 0u; f < 8u; ++f) v[f] = uintBitsToFloat(w[1u + f]);
}

// |v| as bits, compared as uints: finite < inf < NaN, exactly (a float max() may drop a NaN).
uint absBits(float v) { return floatBitsToUint(v) & 0x7fffffffu; }

// The entry's sum to add into grads: a NaN if any term was not finite (where a float sum would
// turn inf or NaN too; fixed point cannot hold it), else the fixed-point sum.
float finalSum(uint maxBits, uvec2 acc, int shift) {
  return maxBits >= 0x7f800000u ? uintBitsToFloat(0x7fc00000u) : fromFixed(acc, shift);
}

void main() {
  uint chunk = gl_GlobalInvocationID.x;
  uint begin = chunk * CHUNK;
  // The slots filled: all of the pass's contributions, or fewer when rows past a device row limit
  // contributed nothing (the last entry's end; the rest of the range holds stale slots).
  uint filled = min(pc.slots, cursor[pc.entries - 1u]);
  if (begin >= filled) return;
  uint end = min(begin + CHUNK, filled);

  if (STAGE == 0u) {
    for (uint i = begin; i < end;) {
      uint e = slotEntry(i);
      uint eBegin = entryBegin(e), eEnd = cursor[e];
      uint runEnd = min(eEnd, end);
      uint g = (pc.entryBase + e) * FEATURES;
      if (eEnd - eBegin == 1u) {  // the common case on hashed levels: one term, added as it is
        float v[8];
        slotValues(i, v);
        [[unroll]] for (uint f = 0u; f < FEATURES; ++f) grads[g + f] += v[f];
        i = runEnd;
        continue;
      }
      uint mx[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);  // max |term| as bits (see absBits)
      for (uint j = i; j < runEnd; ++j) {
        float v[8];
        slotValues(j, v);
        [[unroll]] for (uint f = 0u; f < FEATURES; ++f) mx[f] = max(mx[f], absBits(v[f]));
      }
      if (eBegin >= begin && eEnd <= end) {
        int sh[8];
        uvec2 acc[8];
        [[unroll]] for (uint f = 0u; f < FEATURES; ++f)
          sh[f] = fixedShift(uintBitsToFloat(mx[f]), eEnd - eBegin), acc[f] = uvec2(0u);
        for (uint j = i; j < runEnd; ++j) {
          float v[8];
          slotValues(j, v);
          [[unroll]] for (uint f = 0u; f < FEATURES; ++f) acc[f] = add64(acc[f], toFixed(v[f], sh[f]));
        }
        [[unroll]] for (uint f = 0u; f < FEATURES; ++f) grads[g + f] += finalSum(mx[f], acc[f], sh[f]);
      } else {
        uint o = (eBegin / CHUNK) * FEATURES;
        [[unroll]] for (uint f = 0u; f < FEATURES; ++f) atomicMax(spanMax[o + f], mx[f]);
      }
      i = runEnd;
    }
    return;
  }

  if (STAGE == 1u) {
    // Only a chunk's first and last runs can span chunks (they are one run if one entry fills it).
    uint first = slotEntry(begin), last = slotEntry(end - 1u);
    for (uint r = 0u; r < (first == last ? 1u : 2u); ++r) {
      uint e = r == 0u ? first : last;
      uint eBegin = entryBegin(e), eEnd = cursor[e];
      if (eBegin >= begin && eEnd <= end) continue;  // wholly in this chunk: done in stage 0
      uint from = max(eBegin, begin), to = min(eEnd, end);
      uint o = (eBegin / CHUNK) * FEATURES;
      int sh[8];
      uvec2 acc[8];
      [[unroll]] for (uint f = 0u; f < FEATURES; ++f)
        sh[f] = fixedShift(uintBitsToFloat(spanMax[o + f]), eEnd - eBegin), acc[f] = uvec2(0u);
      for (uint j = from; j < to; ++j) {
        float v[8];
        slotValues(j, v);
        [[unroll]] for (uint f = 0u; f < FEATURES; ++f) acc[f] = add64(acc[f], toFixed(v[f], sh[f]));
      }
      [[unroll]] for (uint f = 0u; f < FEATURES; ++f) {
        uint old = atomicAdd(spanAcc[2u * (o + f)], acc[f].x);
        uint carry = old + acc[f].x < old ? 1u : 0u;
        atomicAdd(spanAcc[2u * (o + f) + 1u], acc[f].y + carry);
      }
    }
    return;
  }

  // STAGE 2: the owner of the entry that starts in this chunk and runs past its end.
  uint e = slotEntry(end - 1u);
  uint eBegin = entryBegin(e), eEnd = cursor[e];
  if (eBegin < begin || eEnd <= end) return;
  uint o = chunk * FEATURES, g = (pc.entryBase + e) * FEATURES;
  [[unroll]] for (uint f = 0u; f < FEATURES; ++f) {
    uint mx = spanMax[o + f];
    grads[g + f] += finalSum(mx, uvec2(spanAcc[2u * (o + f)], spanAcc[2u * (o + f) + 1u]),
                             fixedShift(uintBitsToFloat(mx), eEnd - eBegin));
    spanMax[o + f] = 0u;
    spanAcc[2u * (o + f)] = 0u;
    spanAcc[2u * (o + f) + 1u] = 0u;
  }
}
