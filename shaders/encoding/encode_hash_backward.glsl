#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#ifndef HASH_COMPARE_SWAP
#extension GL_EXT_shader_atomic_float : require
#endif
#ifdef HASH_SUBGROUP_MERGE
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
// Multiresolution hash encoding, backward to the table: one invocation per sample scatters
// weight * dL/dfeature into the 8 corner entries of each level with float atomics; grads are
// accumulated (the caller zeroes them once per step). Layouts: src/core/layouts/hash_grid_layout.h.
// With HASH_SUBGROUP_MERGE defined (HashBackwardMode::SubgroupMerged: encode_hash_backward_merged.comp,
// encode_hash_backward_position_merged.comp): when all active lanes of a subgroup hit the same
// entry (consecutive samples of a ray in a coarse level), they add with subgroupAdd and one lane
// issues a single atomic. Modules of their own: the subgroup vote and arithmetic they declare are
// optional in Vulkan (nerf/network/gradient_paths.h).
// With HASH_COMPARE_SWAP defined (HashBackwardMode::CompareSwap: encode_hash_backward_cas.comp,
// encode_hash_backward_position_cas.comp): each add is a compare-and-swap loop on the float's bits
// (gpu/float_bits_add.glsl), for devices without float atomics.
// With HASH_POSITION_GRADIENT defined (encode_hash_backward_position.comp), the same pass also writes
// dL/dp per sample, as encode_hash_position_gradient.comp does, from the corners it already visits.
// The body of encode_hash_backward.comp and encode_hash_backward_position.comp.
#include "encoding/hash_grid.glsl"

layout(local_size_x = 64) in;

#include "encoding/hash_grid_shared.h"
// Levels in groups that read whole vec4s of dL/dfeatures (as encode_hash.comp), so nothing is an
// array indexed by a loop counter.
const uint GROUP = FEATURES >= 4u ? 1u : 4u / FEATURES;
const uint GROUP_VEC4 = FEATURES == 8u ? 2u : 1u;
const uint GROUPS = (LEVELS + GROUP - 1u) / GROUP;

layout(binding = 0, rgba32f) uniform readonly imageBuffer positions;
layout(binding = 1, rgba32f) uniform readonly imageBuffer dFeatures;
#ifdef HASH_COMPARE_SWAP
layout(std430, binding = 2) buffer Grads { uint grads[]; };  // float bits
#include "gpu/float_bits_add.glsl"
#else
layout(std430, binding = 2) buffer Grads { float grads[]; };
#endif
#ifdef HASH_POSITION_GRADIENT
layout(binding = 3, rgba32f) uniform readonly imageBuffer table;
layout(std430, binding = 4) writeonly buffer PositionGradient { vec4 dPositions[]; };
#include "encoding/hash_position_gradient.glsl"
#define ROW_LIMIT_BINDING 5
#else
#define ROW_LIMIT_BINDING 3
#endif
#include "gpu/row_limit.glsl"

#include "encoding/encode_hash_shared.h"

void scatter(uint index, float value) {
#ifdef HASH_SUBGROUP_MERGE
  if (subgroupAllEqual(index)) {
    float s = subgroupAdd(value);
    if (subgroupElect()) atomicAdd(grads[index], s);
    return;
  }
#endif
#ifdef HASH_COMPARE_SWAP
  FLOAT_BITS_ADD(grads, index, value)
#else
  atomicAdd(grads[index], value);
#endif
}

void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= limitedRows(pc.count, pc.limitBase)) return;
  vec3 box = imageLoad(positions, int(row)).xyz, p = hashGridContract(box, CONTRACT);
  uint src = row * pc.strideVec4 + pc.offsetVec4;
#ifdef HASH_POSITION_GRADIENT
  vec3 grad = vec3(0.0);
#endif
  for (uint g = 0u; g < GROUPS; ++g) {
    vec4 d = imageLoad(dFeatures, int(src + g * GROUP_VEC4));
    vec4 d2 = GROUP_VEC4 == 2u ? imageLoad(dFeatures, int(src + g * GROUP_VEC4 + 1u)) : vec4(0.0);
    // A sample behind a ray's early-termination cut has a gradient of exactly 0: its lane issues
    // none of the group's atomics (each is a loop over the active lanes on lavapipe).
    if (all(equal(d, vec4(0.0))) && all(equal(d2, vec4(0.0)))) continue;
    [[unroll]] for (uint lg = 0u; lg < GROUP; ++lg) {
      uint l = g * GROUP + lg;
      if (l < LEVELS) {
        uint res = pc.res[l / 4u][l % 4u];
        bool dense = ((pc.denseMask >> l) & 1u) != 0u;
        uvec3 cell;
        vec3 w;
        hashGridCell(p, res, cell, w);
#ifdef HASH_POSITION_GRADIENT
        vec3 dw = vec3(0.0);  // dL/dw
#endif
        [[unroll]] for (uint k = 0u; k < 8u; ++k) {
          uvec3 corner = cell + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
          uint entry = (l << LOG2_TABLE) + hashGridIndex(corner, res, dense, LOG2_TABLE);
          float wk = hashGridWeight(k, w);
          [[unroll]] for (uint f = 0u; f < FEATURES; ++f)
            scatter(entry * FEATURES + f, wk * (f < 4u ? d[lg * FEATURES + f] : d2[f - 4u]));
#ifdef HASH_POSITION_GRADIENT
          dw += hashEntryDot(entry, lg, d, d2) * hashCornerSlope(k, w);
#endif
        }
#ifdef HASH_POSITION_GRADIENT
        grad += dw * (0.5 * float(res));
#endif
      }
    }
  }
#ifdef HASH_POSITION_GRADIENT
  dPositions[row] = vec4(hashGridContractGradient(box, CONTRACT, hashClampedGradient(p, grad)), 0.0);
#endif
}
