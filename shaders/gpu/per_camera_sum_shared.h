// Shared by gpu/per_camera_sum.glsl and the host that sizes its dispatches: each lane sums into
// PER_CAMERA_SLOTS vec4s of shared memory (64 lanes: 16 KiB, Vulkan's least
// maxComputeSharedMemorySize), so a workgroup sums PER_CAMERA_SLOTS / width cameras of `width`
// vec4s each.
#ifndef VKNERF_GPU_PER_CAMERA_SUM_SHARED_H
#define VKNERF_GPU_PER_CAMERA_SUM_SHARED_H

#define PER_CAMERA_SLOTS 16u

#endif
