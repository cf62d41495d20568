// Sums per training camera on the device, without float atomics (shaders/rays/camera_gradient.comp,
// shaders/encoding/appearance_gradient.comp): one workgroup of 64 per camera reads every ray's
// camera id, its lanes sum the rows of their own rays into their slots of a shared scratch, and
// the lanes' slots are reduced as a tree. The order of every addition is fixed, so the sum is the
// same at every run, and no host round trip is needed. The cost is rays x cameras id reads, a few
// per cent of a step at a hundred photos.
// The includer defines PER_CAMERA_VEC4 (the vec4s each lane sums, at most 16: the scratch is then
// 16 KiB, Vulkan's least maxComputeSharedMemorySize), declares layout(local_size_x = 64) and a
// buffer `pixelIds` of uvec2 (camera, pixel) per ray.
#ifndef VKNERF_PER_CAMERA_SUM_GLSL
#define VKNERF_PER_CAMERA_SUM_GLSL

// The rays r < n of this workgroup's camera (gl_WorkGroupID.x), each visited by one lane.
#define FOR_EACH_CAMERA_RAY(r, n)                                                  \
  for (uint r = gl_LocalInvocationID.x; r < (n); r += 64u)                         \
    if (pixelIds[r].x == gl_WorkGroupID.x)

// Lane l's sums: perCameraScratch[l * PER_CAMERA_VEC4 + k]. A shared array, not registers: a lane's
// sums are indexed at run time, which would spill registers (seen on lavapipe).
shared vec4 perCameraScratch[64 * PER_CAMERA_VEC4];

// Zeroes this lane's slots (before the sums; every lane calls it).
void perCameraClear() {
  for (uint k = 0u; k < PER_CAMERA_VEC4; ++k) perCameraScratch[gl_LocalInvocationID.x * PER_CAMERA_VEC4 + k] = vec4(0.0);
}

// Adds the lanes' first `width` slots as a tree into lane 0's (every lane calls it, after its sums).
void perCameraReduce(uint width) {
  uint lane = gl_LocalInvocationID.x;
  barrier();
  for (uint s = 32u; s > 0u; s >>= 1u) {
    if (lane < s)
      for (uint k = 0u; k < width; ++k)
        perCameraScratch[lane * PER_CAMERA_VEC4 + k] += perCameraScratch[(lane + s) * PER_CAMERA_VEC4 + k];
    barrier();
  }
}

#endif
