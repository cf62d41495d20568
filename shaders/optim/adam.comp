#version 450
#extension GL_GOOGLE_include_directive : require
// Adam over a flat float parameter buffer with gradient, first- and second-moment buffers of the
// same size; the gradient is zeroed after the step so the next backward pass can accumulate. This
// kernel steps the first body4 vec4s and the count % 4 leftovers; the vec4s past body4, where a
// zero gradient is skipped, go through the list of the touched ones (adam_touched.comp,
// adam_sparse.comp).
// Each invocation updates 4 parameters. It reads them through rgba32f storage texel buffers: on
// lavapipe those loads are vectorised across lanes while SSBO loads are a per-lane loop (measured
// 2-4x faster for this kernel on a dense step). It writes them through vec4 SSBO views of the same
// memory (bindings 8-11): a store is a per-lane loop either way, and the SSBO's took the step over
// the 800x800 object's 2^17 table from 7.0 to 5.1 ms (docs/performance.md). Each invocation reads
// and writes only its own vec4, so the two views never race. The last invocation handles the
// count % 4 leftovers through float SSBO views of the buffers' tails (bindings 4-7). Bias
// corrections 1 / (1 - beta^t) come from the host, computed in double.
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) uniform readonly imageBuffer P4;
layout(binding = 1, rgba32f) uniform readonly imageBuffer G4;
layout(binding = 2, rgba32f) uniform readonly imageBuffer M4;
layout(binding = 3, rgba32f) uniform readonly imageBuffer V4;
// The tails: each binding starts at most a storage-offset alignment before the leftovers.
layout(std430, binding = 4) buffer ParamsF { float params1[]; };
layout(std430, binding = 5) buffer GradsF { float grads1[]; };
layout(std430, binding = 6) buffer Moment1F { float m1[]; };
layout(std430, binding = 7) buffer Moment2F { float v1[]; };
// The vec4 parts of bindings 0-3, written.
layout(std430, binding = 8) writeonly buffer ParamsW { vec4 p4w[]; };
layout(std430, binding = 9) writeonly buffer GradsW { vec4 g4w[]; };
layout(std430, binding = 10) writeonly buffer Moment1W { vec4 m4w[]; };
layout(std430, binding = 11) writeonly buffer Moment2W { vec4 v4w[]; };

#include "optim/adam_shared.h"

#include "optim/adam_step.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint full = pc.count / 4u;
  if (i < pc.body4) {
    int k = int(i);
    vec4 g = imageLoad(G4, k);
    vec4 p = imageLoad(P4, k), m = imageLoad(M4, k), v = imageLoad(V4, k);
    adamStep(p, m, v, g, bvec4(true));
    p4w[i] = p;
    m4w[i] = m;
    v4w[i] = v;
    g4w[i] = vec4(0.0);
  } else if (i == pc.body4 && pc.count > 4u * full) {
    uint first = pc.tailIndex, n = pc.count - 4u * full;  // 1..3 leftovers
    vec4 p = vec4(0.0), g = vec4(0.0), m = vec4(0.0), v = vec4(0.0);
    for (uint j = 0u; j < n; ++j) {
      p[j] = params1[first + j];
      g[j] = grads1[first + j];
      m[j] = m1[first + j];
      v[j] = v1[first + j];
    }
    bvec4 live = 4u * full >= pc.skipZeroFrom ? notEqual(g, vec4(0.0)) : bvec4(true);
    adamStep(p, m, v, g, live);
    for (uint j = 0u; j < n; ++j) {
      params1[first + j] = p[j];
      m1[first + j] = m[j];
      v1[first + j] = v[j];
      grads1[first + j] = 0.0;
    }
  }
}
