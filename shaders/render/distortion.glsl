#ifndef VKNERF_DISTORTION_GLSL
#define VKNERF_DISTORTION_GLSL
// The distortion loss's normalised distance along a ray (tests/reference/render/distortion_loss.h says
// why): s(t) = (g(t) - g(near)) / (g(far) - g(near)), g(t) = integral_0^t du / step(u) with the
// march's step(t) = clamp(t coneAngle, dtMin, dtMax), coneAngle 0 for the constant step dtMin.

struct MarchSpacing {
  float coneAngle, dtMin, dtMax;
};

// g(t) in closed form (ref::marchCoordinate): linear to dtMin / coneAngle, logarithmic to
// dtMax / coneAngle, linear after.
float marchCoordinate(float t, MarchSpacing m) {
  t = max(t, 0.0);
  if (!(m.coneAngle > 0.0)) return t / m.dtMin;
  float t1 = m.dtMin / m.coneAngle, dtMax = max(m.dtMax, m.dtMin), t2 = dtMax / m.coneAngle;
  if (t <= t1) return t / m.dtMin;
  float toT2 = log(min(t, t2) / t1) / m.coneAngle;
  return 1.0 / m.coneAngle + toT2 + max(t - t2, 0.0) / dtMax;
}

// A ray's g(near) and 1 / (g(far) - g(near)): s(t) = (g(t) - x) * y.
vec2 distortionFrame(float tNear, float tFar, MarchSpacing m) {
  float g0 = marchCoordinate(tNear, m);
  return vec2(g0, 1.0 / max(marchCoordinate(tFar, m) - g0, 1e-30));
}

// The midpoint and length in s of a sample's interval [t, t + delta] (sample_ = (t, delta)).
vec2 distortionInterval(vec2 sample_, vec2 frame, MarchSpacing m) {
  float a = marchCoordinate(sample_.x, m), mid = marchCoordinate(sample_.x + 0.5 * sample_.y, m),
        b = marchCoordinate(sample_.x + sample_.y, m);
  return vec2((mid - frame.x) * frame.y, (b - a) * frame.y);
}

#endif
