// A training batch in runs of one camera each (rays.comp's grouped mode): the batch's N rays are
// cut into C runs, one per camera, run k holding N / C rays, one more for the first N % C runs; run
// k is camera (k + offset) mod C, the offset random per step (so that which cameras get the extra
// rays, and which lose theirs when the sample capacity cuts the batch's tail, changes every step).
// Each ray's camera is still uniform over the cameras, as in the random mode; what the runs buy is
// that a camera's rays are consecutive, so a per-camera sum reads that camera's rays alone
// (gpu/per_camera_sum.glsl). CPU twin: tests/reference/rays/camera_runs.h.
#ifndef VKNERF_CAMERA_RUNS_GLSL
#define VKNERF_CAMERA_RUNS_GLSL

// The run of ray i (i < N). Integers only: no product reaches N * C.
uint cameraRunOfRay(uint i, uint N, uint C) {
  uint base = N / C, extra = N % C, longRays = extra * (base + 1u);
  return i < longRays ? i / (base + 1u) : extra + (i - longRays) / base;
}

// The rays [x, y) of run k (k < C).
uvec2 cameraRunRays(uint k, uint N, uint C) {
  uint base = N / C, extra = N % C;
  uint first = k * base + min(k, extra);
  return uvec2(first, first + base + (k < extra ? 1u : 0u));
}

#endif
