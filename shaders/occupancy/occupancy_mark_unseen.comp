#version 450
// Before training: density -1 (empty for good, emaDensity keeps it) in every cell none of whose 8
// corners any training camera sees, through a pinhole bound that holds its lens (instant-ngp's
// mark_untrained_density_grid). CPU twin: ref::markUnseenEmpty (tests/reference/occupancy/view_bounds.h),
// the same float operations in the same order.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 64) in;

struct ViewBound {
  vec4 row0, row1, row2;  // world -> OpenCV camera: rotation rows, translation in w
  vec4 bounds;            // x/z in [x, y], y/z in [z, w]
};

layout(std430, binding = 0) readonly buffer Views { ViewBound views[]; };
layout(std430, binding = 1) buffer Density { float gridDensity[]; };

#include "occupancy/occupancy_mark_unseen_shared.h"

bool pointSeen(ViewBound b, vec3 p) {
  precise float qx = b.row0.x * p.x + b.row0.y * p.y + b.row0.z * p.z + b.row0.w;
  precise float qy = b.row1.x * p.x + b.row1.y * p.y + b.row1.z * p.z + b.row1.w;
  precise float qz = b.row2.x * p.x + b.row2.y * p.y + b.row2.z * p.z + b.row2.w;
  precise float x0 = b.bounds.x * qz, x1 = b.bounds.y * qz, y0 = b.bounds.z * qz, y1 = b.bounds.w * qz;
  return qz > 0.0 && qx >= x0 && qx <= x1 && qy >= y0 && qy <= y1;
}

void main() {
  uint i = flatIndex(64u);
  if (i >= pc.numCells) return;
  uint r = pc.resolution;
  uint perCascade = r * r * r;
  uint local = i % perCascade;
  uvec3 c = uvec3(local % r, (local / r) % r, local / (r * r));
  float scale = 1.0 / float(1u << (pc.cascades - 1u - i / perCascade));
  vec3 centre = vec3(pc.centre[0], pc.centre[1], pc.centre[2]),
       half_ = vec3(pc.halfExtent[0], pc.halfExtent[1], pc.halfExtent[2]);
  for (uint k = 0u; k < 8u; ++k) {
    uvec3 corner = c + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
    precise vec3 n = (vec3(corner) * (2.0 / float(r)) - 1.0) * scale;
    precise vec3 p = centre + n * half_;
    for (uint v = 0u; v < pc.numViews; ++v)
      if (pointSeen(views[v], p)) return;
  }
  gridDensity[i] = -1.0;
}
