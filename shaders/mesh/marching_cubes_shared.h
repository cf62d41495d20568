// The push constants of the mc_*.comp kernels (through mesh/marching_cubes.glsl); on the host, vknerf::glsl::MarchingCubesPush.
#ifndef VKNERF_MESH_MARCHING_CUBES_SHARED_H
#define VKNERF_MESH_MARCHING_CUBES_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(MarchingCubesPush)
  uvec4 n;        // samples per axis (w unused)
  vec4 origin;    // world position of sample (0, 0, 0)
  vec4 spacing;   // between neighbouring samples, per axis
  uint first;     // first edge or cell of this dispatch
  uint count;     // edges or cells in this dispatch
  uint chunk;     // elements per scanned chunk
  float threshold;
PUSH_CONSTANTS_END

#endif
