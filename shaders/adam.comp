#version 450
// Adam over a flat float parameter buffer with gradient, first- and second-moment buffers of the
// same size; the gradient is zeroed after the step so the next backward pass can accumulate.
// Each invocation updates 4 parameters through vec4 views (half the per-float SSBO cost of scalar
// access on lavapipe); the last invocation handles the count % 4 leftovers through float views of
// the same bindings. Bias corrections 1 / (1 - beta^t) come from the host, computed in double.
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Params { vec4 params4[]; };
layout(std430, binding = 0) buffer ParamsF { float params1[]; };
layout(std430, binding = 1) buffer Grads { vec4 grads4[]; };
layout(std430, binding = 1) buffer GradsF { float grads1[]; };
layout(std430, binding = 2) buffer Moment1 { vec4 m4[]; };
layout(std430, binding = 2) buffer Moment1F { float m1[]; };
layout(std430, binding = 3) buffer Moment2 { vec4 v4[]; };
layout(std430, binding = 3) buffer Moment2F { float v1[]; };

layout(push_constant) uniform Push {
  float lr;
  float beta1;
  float beta2;
  float epsilon;
  float correction1;  // 1 / (1 - beta1^t)
  float correction2;  // 1 / (1 - beta2^t)
  uint count;         // parameters
  uint skipZero;      // 1: a parameter whose gradient is exactly 0 keeps p, m and v (sparse rows)
} pc;

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
    vec4 g = grads4[i];
    bvec4 live = pc.skipZero != 0u ? notEqual(g, vec4(0.0)) : bvec4(true);
    if (!any(live)) return;  // an untouched sparse row: one load, no stores
    vec4 p = params4[i], m = m4[i], v = v4[i];
    adam(p, m, v, g, live);
    params4[i] = p;
    m4[i] = m;
    v4[i] = v;
    grads4[i] = vec4(0.0);
  } else if (i == full) {
    uint first = 4u * full, n = pc.count - first;  // 1..3 leftovers (the host dispatches this lane only then)
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
