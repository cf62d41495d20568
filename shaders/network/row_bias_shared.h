// The modes of a dense layer's bias per row (shaders/network/row_bias.glsl); on the host,
// nerf::RowBias (src/nerf/network/dense_layer.h).
#ifndef VKNERF_NETWORK_ROW_BIAS_SHARED_H
#define VKNERF_NETWORK_ROW_BIAS_SHARED_H

#define ROW_BIAS_NONE 0u     // no bias per row
#define ROW_BIAS_ONE 1u      // every row adds the table's row 0
#define ROW_BIAS_PER_RAY 2u  // row r adds the table's row rayTable[rowRay[r]].x

#endif
