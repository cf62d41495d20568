#version 450
#extension GL_GOOGLE_include_directive : require
// Rendered pixels [first, first + count) of a view, one invocation per pixel, into an embedding
// application's render target (Model::recordRender). Permutations (CMakeLists.txt, vknerf_add_shader):
// write_render_target: a storage buffer of RGBA32F texels; write_render_target_rgba32f and
// write_render_target_rgba8: a storage image whose format qualifier is TARGET_IMAGE_FORMAT. Image
// formats are fixed in the shader: writing without a format needs a device feature that an
// adopted device may not have enabled.

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Color { vec4 color[]; };  // per ray: rgb over the background, opacity
layout(std430, binding = 1) readonly buffer Depth { float depthSum[]; };  // per ray: sum w_i t_i
#ifdef TARGET_IMAGE
layout(binding = 2, TARGET_IMAGE_FORMAT) uniform writeonly image2D target;
#else
layout(std430, binding = 2) writeonly buffer Target { vec4 texels[]; };  // width * height, row-major
#endif

#include "render/write_render_target_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  vec4 c = color[i];
  vec4 value = c;
  if (pc.channel == 1u) {
    // The same rule as Model::render: expected depth over the rays that hit something.
    float depth = c.a > 1e-4 ? depthSum[i] / c.a : 0.0;
    value = vec4(vec3(depth * pc.depthScale), c.a);
  }
  uint p = pc.first + i;
#ifdef TARGET_IMAGE
#ifdef TARGET_UNORM
  value = clamp(value, 0.0, 1.0);  // the store clamps too; explicit, since depth is not in [0, 1]
#endif
  imageStore(target, ivec2(p % pc.width, p / pc.width), value);
#else
  texels[p] = value;
#endif
}

