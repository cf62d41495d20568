#version 450
// Rendered pixels into a caller's R32G32B32A32_SFLOAT storage image (see write_render_target.glsl).
#extension GL_GOOGLE_include_directive : require
#define TARGET_IMAGE
#define TARGET_IMAGE_FORMAT rgba32f
#include "write_render_target.glsl"
