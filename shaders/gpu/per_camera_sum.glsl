// Sums per training camera on the device, without float atomics (shaders/rays/camera_gradient.comp,
// shaders/encoding/appearance_gradient.comp), over a batch in runs of one camera each
// (rays/camera_runs.glsl): a camera's rays are consecutive, so a workgroup of PER_CAMERA_LANES sums
// one camera at a time, reading that camera's rays alone (cameras gl_WorkGroupID.x, then
// + gl_NumWorkGroups.x, ...: any number of cameras in one dispatch). Its lanes add the camera's
// rays, or their rows, in turn into registers, store them in their slots of a shared scratch, and
// the slots are reduced as a tree. The order of every addition is fixed, so the sum is the same at
// every run, and no host round trip is needed. The includer declares
// layout(local_size_x = PER_CAMERA_LANES) and a buffer `pixelIds` of uvec2 (camera, pixel) per ray.
#ifndef VKNERF_PER_CAMERA_SUM_GLSL
#define VKNERF_PER_CAMERA_SUM_GLSL
#include "gpu/per_camera_sum_shared.h"
#include "rays/camera_runs.glsl"

// Lane l's sums: perCameraScratch[l * PER_CAMERA_SLOTS + k], k < the includer's width.
shared vec4 perCameraScratch[PER_CAMERA_LANES * PER_CAMERA_SLOTS];

// Camera c's rays [x, y) among the batch's first n (of the N generated, over C cameras): its run,
// counted from the run of ray 0's camera, which is run 0.
uvec2 perCameraRays(uint c, uint N, uint n, uint C) {
  if (n == 0u) return uvec2(0u);
  uvec2 run = cameraRunRays((c + C - pixelIds[0].x) % C, N, C);
  return min(run, uvec2(n));
}

void perCameraStore(uint k, vec4 sum) { perCameraScratch[gl_LocalInvocationID.x * PER_CAMERA_SLOTS + k] = sum; }

// Adds the lanes' slots as a tree into lane 0's, which then holds the camera's sums at
// perCameraScratch[k] (every lane calls it, after perCameraStore of each of its `width` slots).
void perCameraReduce(uint width) {
  uint lane = gl_LocalInvocationID.x;
  barrier();
  for (uint s = PER_CAMERA_LANES / 2u; s > 0u; s >>= 1u) {
    if (lane < s)
      for (uint k = 0u; k < width; ++k)
        perCameraScratch[lane * PER_CAMERA_SLOTS + k] += perCameraScratch[(lane + s) * PER_CAMERA_SLOTS + k];
    barrier();
  }
}

// After lane 0 has read the sums: the scratch may be stored into again (every lane calls it).
void perCameraDone() { barrier(); }

#endif
