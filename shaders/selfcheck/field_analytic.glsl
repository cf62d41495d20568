// CPU twin: tools/cli/kernels/field_analytic_reference.h.
#ifndef VKNERF_FIELD_ANALYTIC_GLSL
#define VKNERF_FIELD_ANALYTIC_GLSL

vec4 analyticField(vec3 p) {
  float r = length(p - vec3(0.1, 0.0, 0.0));
  float sphere = 40.0 * clamp((0.5 - r) / 0.05, 0.0, 1.0);
  vec3 q = abs(p - vec3(-0.45, 0.3, 0.2));
  float fog = 3.0 * clamp((0.3 - max(q.x, max(q.y, q.z))) / 0.05, 0.0, 1.0);
  vec3 rgb = sphere > 0.0 ? vec3(0.5) + 0.5 * p : vec3(0.9, 0.4, 0.1);
  return vec4(rgb, sphere + fog);
}

#endif
