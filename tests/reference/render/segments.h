#pragma once
// CPU reference for shaders/render/accumulate_segment.comp: a ray rendered segment by segment
// (nerf::SegmentAccumulator). Each segment is composited over black from a transmittance of 1
// (compositeForward with a zero background); this puts it behind what the ray gathered before and
// decides whether the ray goes on.
#include <array>
#include <cstddef>

#include "reference/render/composite.h"

namespace vknerf::ref {

template <class T> struct SegmentedRay {
  std::array<T, 3> rgb{};  // gathered colour (with the background once the ray has ended)
  T transmittance = 1;
  T depth = 0;             // sum w_i t_i, not normalised
  T next = 0;              // where the next segment's march starts; < 0 once the ray has ended
};

// One round for one ray. `samples` is the segment's sample count, (lastT, lastDelta) its last
// sample; the ray goes on when the march filled `cap`, it is not the last round, its
// transmittance is at least minTransmittance and lastT + lastDelta lies before tFar.
template <class T>
void accumulateSegment(SegmentedRay<T>& ray, const RayColor<T>& segment, size_t samples, size_t cap, T lastT,
                       T lastDelta, T tFar, bool last, T minTransmittance, const std::array<T, 3>& background) {
  const T t = ray.transmittance;
  for (int k = 0; k < 3; ++k) ray.rgb[k] += t * segment.rgb[k];
  ray.depth += t * segment.depth;
  ray.transmittance = t * (T(1) - segment.opacity);
  ray.next = -1;
  if (!last && samples == cap && ray.transmittance >= minTransmittance && lastT + lastDelta < tFar)
    ray.next = lastT + lastDelta;
  if (ray.next < 0)
    for (int k = 0; k < 3; ++k) ray.rgb[k] += ray.transmittance * background[k];
}

}  // namespace vknerf::ref
