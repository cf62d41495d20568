// Shared by gpu/per_camera_sum.glsl, its includers and the host that checks their widths.
// PER_CAMERA_LANES: the invocations summing one camera. Eight, lavapipe's SIMD width: a camera's
// run is a few dozen rays, and with 64 lanes most of the time went to the tree over the lanes
// (0.8 against 0.35 ms a step for the 100 photos of the sample scene); on a GPU these sums are a
// few per cent of a step either way.
// PER_CAMERA_SLOTS: the vec4s a lane sums into, the most a camera's sum may have.
#ifndef VKNERF_GPU_PER_CAMERA_SUM_SHARED_H
#define VKNERF_GPU_PER_CAMERA_SUM_SHARED_H

#define PER_CAMERA_LANES 8u
#define PER_CAMERA_SLOTS 16u

#endif
