// The flat invocation index of a dispatch the host split over x and y (Recorder::dispatchFlat: x is
// capped by maxComputeWorkGroupCount[0], 65,535 on many devices, so large counts go on in y).
#ifndef VKNERF_COMMON_FLAT_INDEX_GLSL
#define VKNERF_COMMON_FLAT_INDEX_GLSL

uint flatIndex(uint localSize) {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * localSize + gl_LocalInvocationID.x;
}

#endif
