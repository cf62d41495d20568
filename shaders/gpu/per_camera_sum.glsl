// Sums per training camera on the device, without float atomics (shaders/rays/camera_gradient.comp,
// shaders/encoding/appearance_gradient.comp): a workgroup of 64 sums a run of consecutive cameras
// (perCameraGroup(width) of them, from gl_WorkGroupID.x times that). It reads every ray's camera
// id; a lane sums the rows of its own rays whose camera is one of the group's into its slots of a
// shared scratch, and the lanes' slots are reduced as a tree. The order of every addition is fixed,
// so the sum is the same at every run, and no host round trip is needed. A lane meets few rays of
// its group's cameras, so few lanes of a SIMD row are busy at once: the includer sums one row per
// ray here (each ray's samples summed before by a kernel with every lane busy), and a workgroup
// takes as many cameras as its scratch holds, which divides the id reads (rays x cameras / group).
// The includer declares layout(local_size_x = 64) and a buffer `pixelIds` of uvec2 (camera, pixel)
// per ray.
#ifndef VKNERF_PER_CAMERA_SUM_GLSL
#define VKNERF_PER_CAMERA_SUM_GLSL
#include "gpu/per_camera_sum_shared.h"

// Lane l's sums: perCameraScratch[l * PER_CAMERA_SLOTS + slot * width + k] for the group's camera
// `slot`. A shared array, not registers: a lane's sums are indexed at run time, which would spill
// registers (seen on lavapipe).
shared vec4 perCameraScratch[64 * PER_CAMERA_SLOTS];

// The cameras a workgroup sums, each `width` vec4s (1 to PER_CAMERA_SLOTS).
uint perCameraGroup(uint width) { return PER_CAMERA_SLOTS / width; }

// This workgroup's first camera.
uint perCameraFirst(uint width) { return gl_WorkGroupID.x * perCameraGroup(width); }

// Ray r's camera as a slot of this workgroup's cameras: >= perCameraGroup(width) if not one of them.
uint perCameraSlot(uint r, uint width) { return pixelIds[r].x - perCameraFirst(width); }

// Where lane `lane` sums vec4 k of its group's camera `slot`.
uint perCameraIndex(uint lane, uint slot, uint width, uint k) { return lane * PER_CAMERA_SLOTS + slot * width + k; }

// Zeroes this lane's slots (before the sums; every lane calls it).
void perCameraClear() {
  for (uint k = 0u; k < PER_CAMERA_SLOTS; ++k)
    perCameraScratch[gl_LocalInvocationID.x * PER_CAMERA_SLOTS + k] = vec4(0.0);
}

// Adds the lanes' slots as a tree into lane 0's, which then hold camera slot s's sums at
// perCameraScratch[s * width + k] (every lane calls it, after its sums).
void perCameraReduce(uint width) {
  uint lane = gl_LocalInvocationID.x, used = perCameraGroup(width) * width;
  barrier();
  for (uint s = 32u; s > 0u; s >>= 1u) {
    if (lane < s)
      for (uint k = 0u; k < used; ++k)
        perCameraScratch[lane * PER_CAMERA_SLOTS + k] += perCameraScratch[(lane + s) * PER_CAMERA_SLOTS + k];
    barrier();
  }
}

#endif
