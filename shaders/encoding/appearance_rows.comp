#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, forward: writes each sample's appearance vector into its row of the colour
// network's direction input, columns [offset, offset + dims) beside the SH encoding (the other
// columns untouched). In training the vector is the one of the photo the sample's ray came from
// (sample -> ray: the march's sampleRay, ray -> photo: the batch's pixel ids); in a render every
// sample gets one row of the table (the mean of the photos' vectors, or a chosen photo's).
// One invocation per row. ref: src/reference/encoding/appearance.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Table { vec4 table[]; };
layout(std430, binding = 1) readonly buffer PixelIds { uvec2 pixelIds[]; };  // (camera, pixel) per ray
layout(std430, binding = 2) readonly buffer SampleRay { uint sampleRay[]; };
layout(std430, binding = 3) buffer Features { vec4 features[]; };
#define ROW_LIMIT_BINDING 4
#include "gpu/row_limit.glsl"

#include "encoding/appearance_rows_shared.h"

void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= limitedRows(pc.count, pc.limitBase)) return;
  uint v = pc.fixedRow == APPEARANCE_PER_RAY ? pixelIds[sampleRay[row]].x : pc.fixedRow;
  for (uint k = 0u; k < pc.dimsVec4; ++k)
    features[row * pc.strideVec4 + pc.offsetVec4 + k] = table[v * pc.dimsVec4 + k];
}
