#version 450
// Rendered pixels into a caller's R8G8B8A8_UNORM storage image (see write_render_target.glsl).
#extension GL_GOOGLE_include_directive : require
#define TARGET_IMAGE
#define TARGET_IMAGE_FORMAT rgba8
#define TARGET_UNORM
#include "write_render_target.glsl"
