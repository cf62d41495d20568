// A batch read through a row index: the fast model's backward runs over the samples a ray kept
// before early termination (shaders/sampling/kept_rows.comp) and reads the forward's rows at
// rowGather[i], while what the backward itself writes is packed (row i). Its training forward runs
// in segments (shaders/sampling/segment_rows.comp): there row i of the batch is read and written at
// rowGather[i]. The kernel's push constants carry `gather` (0: row i is row i, the binding is not read).
// Define ROW_GATHER_BINDING before including.
#ifndef VKNERF_ROW_GATHER_GLSL
#define VKNERF_ROW_GATHER_GLSL

layout(std430, binding = ROW_GATHER_BINDING) readonly buffer RowGather { uint rowGather[]; };

uint gatheredRow(uint row, uint gather) { return gather != 0u ? rowGather[row] : row; }

#endif
