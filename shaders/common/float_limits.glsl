// The largest finite float, shared by every kernel that clamps to it (FLT_MAX on the host).
#ifndef VKNERF_FLOAT_LIMITS_GLSL
#define VKNERF_FLOAT_LIMITS_GLSL

const float kMaxFloat = 3.402823466e38;

#endif
