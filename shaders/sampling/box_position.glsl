// A point's field input: the scene box mapped onto [-1, 1]^3, a vec4 with w = 0, in the operation
// order of ref::samplePosition, 2 (x - min) / (max - min) - 1. Every kernel that makes field
// positions (the march's points, the proposal's samples, the vanilla sampler's, the mesh grid's)
// takes them from here, so that a point comes out the same bits whichever kernel made it.
#ifndef VKNERF_SAMPLING_BOX_POSITION_GLSL
#define VKNERF_SAMPLING_BOX_POSITION_GLSL

vec4 boxPosition(vec3 x, vec3 boxMin, vec3 boxMax) { return vec4(2.0 * (x - boxMin) / (boxMax - boxMin) - 1.0, 0.0); }

#endif
