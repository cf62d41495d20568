#version 450
// Rendered pixels into a caller's buffer of RGBA32F texels (see write_render_target.glsl).
#extension GL_GOOGLE_include_directive : require
#include "write_render_target.glsl"
