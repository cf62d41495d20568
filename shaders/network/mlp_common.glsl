// Activations shared by the MLP kernels; tests/reference/network/mlp.h is their CPU twin (same clamps).
#ifndef VKNERF_MLP_COMMON_GLSL
#define VKNERF_MLP_COMMON_GLSL

#define MLP_ACT_NONE 0u
#define MLP_ACT_RELU 1u
#define MLP_ACT_SIGMOID 2u

#define MLP_DENSITY_RELU 0u
#define MLP_DENSITY_TRUNC_EXP 1u
#define MLP_DENSITY_SOFTPLUS 2u

// exp() of +-80 stays finite in float; sigmoid(80) already rounds to 1.
vec4 mlpSigmoid(vec4 z) { return 1.0 / (1.0 + exp(-clamp(z, vec4(-80.0), vec4(80.0)))); }
float mlpSigmoid(float z) { return 1.0 / (1.0 + exp(-clamp(z, -80.0, 80.0))); }

vec4 mlpActivate(uint act, vec4 z) {
  if (act == MLP_ACT_RELU) return max(z, vec4(0.0));
  if (act == MLP_ACT_SIGMOID) return mlpSigmoid(z);
  return z;
}

// Truncated exp caps its argument at 15 (sigma <= 3.3e6) and clamps its derivative to [-15, 15].
float mlpDensity(uint kind, float x) {
  if (kind == MLP_DENSITY_TRUNC_EXP) return exp(min(x, 15.0));
  if (kind == MLP_DENSITY_SOFTPLUS) return max(x, 0.0) + log(1.0 + exp(-abs(x)));
  return max(x, 0.0);
}
float mlpDensityGrad(uint kind, float x) {
  if (kind == MLP_DENSITY_TRUNC_EXP) return exp(clamp(x, -15.0, 15.0));
  if (kind == MLP_DENSITY_SOFTPLUS) return mlpSigmoid(x);
  return x > 0.0 ? 1.0 : 0.0;
}

#endif
