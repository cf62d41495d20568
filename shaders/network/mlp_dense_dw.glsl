#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// One dense layer, backward to its weights: G[k][n] += sum_rows X[row][k] dZ[row][n] for the
// columns n in [N0, N0 + NW) of a [K4][N4] block at float offset GOFF of the gradient buffer.
// X is one input part (A or B) of the layer, or the constant 1 (ONES: the bias row, K4 = KT = 1).
// The gradient buffer is accumulated into: chunks and parts add up.
//
// Shaped for lavapipe (shared/LAVAPIPE.md): lanes are rows; workgroup y picks a KT x NT tile; each
// invocation sums per-lane outer products over ITERS*U rows (row0 + (it*U + u)*G). The U rows of one
// iteration are summed in loop-local temporaries so the loop-carried accumulators (masked writes in
// llvmpipe) are touched once per U rows. Then the invocations' sums are reduced and added into the
// gradient buffer, one module per way the device allows (nerf/network/gradient_paths.h):
//   DW_WORKGROUP_REDUCE undefined: subgroupAdd, one add per subgroup and entry (subgroup arithmetic);
//                       defined: the workgroup's sums in shared memory, one add per workgroup and entry.
//   DW_COMPARE_SWAP undefined: the add is a float atomicAdd (shaderBufferFloat32AtomicAdd);
//                   defined: a compare-and-swap loop on the float's bits (core uint atomics).
// mlp_dense_dw.comp, mlp_dense_dw_cas.comp, mlp_dense_dw_workgroup.comp, mlp_dense_dw_workgroup_cas.comp.
#ifndef DW_WORKGROUP_REDUCE
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#endif
#ifndef DW_COMPARE_SWAP
#extension GL_EXT_shader_atomic_float : require
#endif

#include "network/mlp_dense_dw_shared.h"
#include "gpu/float_bits_add.glsl"

layout(binding = 0, rgba32f) uniform readonly imageBuffer X;
layout(binding = 1, rgba32f) uniform readonly imageBuffer DZ;
#ifdef DW_COMPARE_SWAP
layout(std430, binding = 2) buffer Grads { uint g[]; };  // float bits
#else
layout(std430, binding = 2) buffer Grads { float g[]; };
#endif
#define ROW_GATHER_BINDING 3
#include "gpu/row_gather.glsl"  // X (the forward's activations) at the gathered rows
#define ROW_LIMIT_BINDING 4
#include "gpu/row_limit.glsl"

// g[i] += s. Other invocations add into the same entry concurrently; only ever one lane of a
// subgroup adds into a given entry at a time (the reductions below), so the compare-and-swap loop
// retries only when another subgroup won the race.
void addGradient(uint i, float s) {
#ifdef DW_COMPARE_SWAP
  FLOAT_BITS_ADD(g, i, s)
#else
  atomicAdd(g[i], s);
#endif
}

#ifdef DW_WORKGROUP_REDUCE
// Entries reduced per round: the workgroup's sums of BATCH entries fill 16 KiB of shared memory
// (the least any Vulkan device has); LOCAL_SIZE_X <= 4096.
const uint BATCH = 4096u / gl_WorkGroupSize.x;
shared float partial[4096];
#endif

void main() {
  uint G = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint row0 = gl_GlobalInvocationID.x;
  // Under a device row limit the rows at and past it add nothing: the others stop sweeping after
  // the last live row. A lane with none left leaves (the rest of its subgroup reduces without it);
  // in the workgroup reduction, which needs every invocation at its barriers, only a whole
  // workgroup with none leaves, and its other lanes sum nothing.
  uint count = limitedRows(pc.count, pc.limitBase);
#ifdef DW_WORKGROUP_REDUCE
  if (gl_WorkGroupID.x * gl_WorkGroupSize.x >= count) return;
  uint iters = row0 < count ? min(pc.iters, (count + U * G - 1u) / (U * G)) : 0u;
#else
  if (row0 >= count) return;
  uint iters = min(pc.iters, (count + U * G - 1u) / (U * G));
#endif
  uint tile = gl_WorkGroupID.y, ntn = NW / NT;
  uint k0 = (tile / ntn) * KT, n0 = N0 + (tile % ntn) * NT;
  float acc[KT][NT];
  [[unroll]] for (uint i = 0; i < KT; i++)
    [[unroll]] for (uint j = 0; j < NT; j++) acc[i][j] = 0.0;
  for (uint it = 0; it < iters; it++) {
    float x[U][KT], d[U][NT];
    [[unroll]] for (uint u = 0; u < U; u++) {
      uint b = row0 + (it * U + u) * G;
      uint bc = min(b, count - 1u);
      float valid = b < count ? 1.0 : 0.0;
      if (ONES) {
        x[u][0] = valid;
      } else {
        uint bx = gatheredRow(bc, pc.gather);
        [[unroll]] for (uint q = 0; q < KT / 4u; q++) {
          vec4 v = imageLoad(X, int(bx * pc.strideX4 + k0 / 4u + q)) * valid;
          x[u][4 * q] = v.x; x[u][4 * q + 1] = v.y; x[u][4 * q + 2] = v.z; x[u][4 * q + 3] = v.w;
        }
      }
      [[unroll]] for (uint q = 0; q < NT / 4u; q++) {
        vec4 v = imageLoad(DZ, int(bc * pc.strideZ4 + n0 / 4u + q));
        d[u][4 * q] = v.x; d[u][4 * q + 1] = v.y; d[u][4 * q + 2] = v.z; d[u][4 * q + 3] = v.w;
      }
    }
    [[unroll]] for (uint i = 0; i < KT; i++)
      [[unroll]] for (uint j = 0; j < NT; j++) {
        float t = x[0][i] * d[0][j];
        [[unroll]] for (uint u = 1; u < U; u++) t += x[u][i] * d[u][j];
        acc[i][j] += t;
      }
  }
  // The reduction runs once per invocation: dynamic loops keep its code (and the JIT time of
  // KT*NT subgroupAdds, each a loop over the lanes in llvmpipe) small.
  float sums[KT * NT];
  [[unroll]] for (uint i = 0; i < KT; i++)
    [[unroll]] for (uint j = 0; j < NT; j++) sums[i * NT + j] = acc[i][j];
#ifdef DW_WORKGROUP_REDUCE
  // Per round, every invocation stores its sums of BATCH entries (entry j's column of the
  // workgroup at partial[j * LOCAL_SIZE_X]); then invocation j sums entry j's column and adds it.
  uint lid = gl_LocalInvocationID.x, local = gl_WorkGroupSize.x;
  [[dont_unroll]] for (uint e0 = 0; e0 < KT * NT; e0 += BATCH) {
    uint n = min(BATCH, KT * NT - e0);
    [[dont_unroll]] for (uint j = 0; j < n; j++) partial[j * local + lid] = sums[e0 + j];
    barrier();
    [[dont_unroll]] for (uint j = lid; j < n; j += local) {
      float s = 0.0;
      [[dont_unroll]] for (uint i = 0; i < local; i++) s += partial[j * local + i];
      uint e = e0 + j;
      addGradient(GOFF + (k0 + e / NT) * N4 + n0 + e % NT, s);
    }
    barrier();
  }
#else
  [[dont_unroll]] for (uint e = 0; e < KT * NT; e++) {
    float s = subgroupAdd(sums[e]);
    if (subgroupElect()) addGradient(GOFF + (k0 + e / NT) * N4 + n0 + e % NT, s);
  }
#endif
}
