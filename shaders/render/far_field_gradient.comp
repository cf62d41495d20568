#version 450
#extension GL_GOOGLE_include_directive : require
// The far field's gradient per ray: C = sum w_i c_i + T_final bg, so dL/dbg = dL/dC T_final, with
// T_final = 1 - opacity from the composite (tests/reference/render/far_field.h). A ray with no
// gradient (past the batch's cut) or no light left (opaque) gives the far field nothing.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer DColor { vec4 dColor[]; };  // dL/d(r, g, b, opacity)
layout(std430, binding = 1) readonly buffer Color { vec4 color[]; };    // (r, g, b, opacity)
layout(std430, binding = 2) writeonly buffer DBackground { vec4 dBackground[]; };  // (dL/dbg, 0)

#include "render/far_field_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  dBackground[i] = vec4(dColor[i].rgb * (1.0 - color[i].a), 0.0);
}
