#version 450
#extension GL_GOOGLE_include_directive : require
// Adam over a flat float parameter buffer with gradient, first- and second-moment buffers of the
// same size; the gradient is zeroed after the step so the next backward pass can accumulate.
// Each invocation updates 4 parameters through rgba32f storage texel buffers: on lavapipe their
// loads and stores are vectorised across lanes while SSBO access is a per-lane loop (measured
// 2-4x faster for this kernel on a dense step). The last invocation handles the count % 4 leftovers through
// float SSBO views of the buffers' tails (bindings 4-7). Bias corrections 1 / (1 - beta^t) come
// from the host, computed in double.
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) uniform imageBuffer P4;
layout(binding = 1, rgba32f) uniform imageBuffer G4;
layout(binding = 2, rgba32f) uniform imageBuffer M4;
layout(binding = 3, rgba32f) uniform imageBuffer V4;
// The tails: each binding starts at most a storage-offset alignment before the leftovers.
layout(std430, binding = 4) buffer ParamsF { float params1[]; };
layout(std430, binding = 5) buffer GradsF { float grads1[]; };
layout(std430, binding = 6) buffer Moment1F { float m1[]; };
layout(std430, binding = 7) buffer Moment2F { float v1[]; };

#include "optim/adam_shared.h"

// Same operation order as ref::adamStep. `live` masks lanes that must keep their old values.
void adam(inout vec4 p, inout vec4 m, inout vec4 v, vec4 g, bvec4 live) {
  vec4 mn = pc.beta1 * m + (1.0 - pc.beta1) * g;
  vec4 vn = pc.beta2 * v + (1.0 - pc.beta2) * g * g;
  vec4 pn = p - pc.lr * (mn * pc.correction1) / (sqrt(vn * pc.correction2) + pc.epsilon);
  p = mix(p, pn, live);
  m = mix(m, mn, live);
  v = mix(v, vn, live);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint full = pc.count / 4u;
  if (i < full) {
    int k = int(i);
    vec4 g = imageLoad(G4, k);
    bvec4 live = pc.skipZero != 0u ? notEqual(g, vec4(0.0)) : bvec4(true);
    if (!any(live)) return;  // an untouched sparse row: one load, no stores
    vec4 p = imageLoad(P4, k), m = imageLoad(M4, k), v = imageLoad(V4, k);
    adam(p, m, v, g, live);
    imageStore(P4, k, p);
    imageStore(M4, k, m);
    imageStore(V4, k, v);
    imageStore(G4, k, vec4(0.0));
  } else if (i == full && pc.count > 4u * full) {
    uint first = pc.tailIndex, n = pc.count - 4u * full;  // 1..3 leftovers
    vec4 p = vec4(0.0), g = vec4(0.0), m = vec4(0.0), v = vec4(0.0);
    for (uint j = 0u; j < n; ++j) {
      p[j] = params1[first + j];
      g[j] = grads1[first + j];
      m[j] = m1[first + j];
      v[j] = v1[first + j];
    }
    bvec4 live = pc.skipZero != 0u ? notEqual(g, vec4(0.0)) : bvec4(true);
    adam(p, m, v, g, live);
    for (uint j = 0u; j < n; ++j) {
      params1[first + j] = p[j];
      m1[first + j] = m[j];
      v1[first + j] = v[j];
      grads1[first + j] = 0.0;
    }
  }
}
