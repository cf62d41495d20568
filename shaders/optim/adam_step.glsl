// One Adam update of 4 parameters, in the operation order of ref::adamStep; `live` masks the lanes
// that keep their old values. The includer's push constants `pc` carry lr, beta1, beta2, epsilon
// and the bias corrections (optim/adam_shared.h).
#ifndef VKNERF_ADAM_STEP_GLSL
#define VKNERF_ADAM_STEP_GLSL

void adamStep(inout vec4 p, inout vec4 m, inout vec4 v, vec4 g, bvec4 live) {
  vec4 mn = pc.beta1 * m + (1.0 - pc.beta1) * g;
  vec4 vn = pc.beta2 * v + (1.0 - pc.beta2) * g * g;
  vec4 pn = p - pc.lr * (mn * pc.correction1) / (sqrt(vn * pc.correction2) + pc.epsilon);
  p = mix(p, pn, live);
  m = mix(m, mn, live);
  v = mix(v, vn, live);
}

#endif
