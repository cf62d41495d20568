// A batch whose row count is known only on the device (the marcher's sample total, say): the host
// records the dispatch for a capacity with its workgroup count written on the device
// (limited_dispatch_args.comp, src/gpu/dispatch/limited_dispatch.h), and the kernel skips the rows at and
// past the device count, so a render recorded into a caller's command buffer costs the samples it
// marched, not the capacity.
// Define ROW_LIMIT_BINDING before including; the push constants carry `limitBase`: the first row of
// this dispatch within the limited batch (dispatches go in chunks), or ROW_LIMIT_NONE.
#ifndef VKNERF_ROW_LIMIT_GLSL
#define VKNERF_ROW_LIMIT_GLSL

#define ROW_LIMIT_NONE 0xffffffffu

layout(std430, binding = ROW_LIMIT_BINDING) readonly buffer RowLimit { uint rowLimit; };

// The rows of this dispatch to compute: `count`, cut to what is left of the device count past `base`.
uint limitedRows(uint count, uint base) {
  if (base == ROW_LIMIT_NONE) return count;
  uint limit = rowLimit;
  return limit > base ? min(count, limit - base) : 0u;
}

#endif
