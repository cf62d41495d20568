// Sums per training camera on the device, without float atomics (shaders/rays/camera_gradient.comp,
// shaders/encoding/appearance_gradient.comp): one workgroup of 64 per camera reads every ray's
// camera id, its lanes sum the rows of their own rays, and the lanes' sums are reduced as a tree
// in shared memory. The order of every addition is fixed, so the sum is the same at every run, and
// no host round trip is needed. The cost is rays x cameras id reads, a few per cent of a step at a
// hundred photos.
// The includer declares layout(local_size_x = 64) and a buffer `pixelIds` of uvec2 (camera, pixel)
// per ray.
#ifndef VKNERF_PER_CAMERA_SUM_GLSL
#define VKNERF_PER_CAMERA_SUM_GLSL

// The rays r < n of this workgroup's camera (gl_WorkGroupID.x), each visited by one lane.
#define FOR_EACH_CAMERA_RAY(r, n)                                                  \
  for (uint r = gl_LocalInvocationID.x; r < (n); r += 64u)                         \
    if (pixelIds[r].x == gl_WorkGroupID.x)

shared vec4 perCameraScratch[64];

// The sum of every lane's v, returned to every lane (all 64 lanes must call it).
vec4 perCameraSum(vec4 v) {
  uint lane = gl_LocalInvocationID.x;
  perCameraScratch[lane] = v;
  barrier();
  for (uint s = 32u; s > 0u; s >>= 1u) {
    if (lane < s) perCameraScratch[lane] += perCameraScratch[lane + s];
    barrier();
  }
  vec4 total = perCameraScratch[0];
  barrier();  // every lane has read it: the scratch is free for the next sum
  return total;
}

#endif
