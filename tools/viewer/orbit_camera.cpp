#include "orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace viewer {
namespace {

constexpr float kRadiansPerPixel = 0.01f;
constexpr float kZoomPerStep = 0.9f;               // distance factor per wheel step
constexpr float kMinScale = 0.05f, kMaxScale = 20;  // of the start distance
constexpr float kPoleMargin = 0.05f;               // radians kept from straight above/below the centre

glm::mat3 axisRotation(float angle, const glm::vec3& axis) {
  return glm::mat3(glm::rotate(glm::mat4(1.0f), angle, axis));
}

float polarAngle(const glm::vec3& v, const glm::vec3& up) {
  return std::acos(std::clamp(glm::dot(glm::normalize(v), up), -1.0f, 1.0f));
}

}  // namespace

OrbitCamera::OrbitCamera(const vknerf::Camera& start, const glm::vec3& centre, const glm::vec3& up)
    : start_(start), centre_(centre) {
  const auto& m = start.c2w;  // row-major; columns: right, up, back, position
  startRot_ = glm::mat3(glm::vec3(m[0], m[4], m[8]), glm::vec3(m[1], m[5], m[9]), glm::vec3(m[2], m[6], m[10]));
  startPos_ = glm::vec3(m[3], m[7], m[11]);
  startOffset_ = startPos_ - centre_;
  up_ = glm::length(up) > 1e-6f ? glm::normalize(up) : glm::vec3(0, 0, 1);
  // Tilting about the horizontal axis perpendicular to the offset changes only the elevation. When
  // the camera sits on the up axis, fall back to its own right vector.
  glm::vec3 axis = glm::cross(up_, startOffset_);
  pitchAxis_ = glm::length(axis) > 1e-6f * glm::length(startOffset_) ? glm::normalize(axis) : startRot_[0];
}

void OrbitCamera::drag(double dx, double dy) {
  // The scene follows the cursor: dragging right turns the camera the other way about up, dragging
  // down raises it. Rotating the offset about up x offset by a positive angle lowers it.
  yaw_ -= float(dx) * kRadiansPerPixel;
  const float pitch = pitch_ - float(dy) * kRadiansPerPixel;
  const float polar = polarAngle(axisRotation(pitch, pitchAxis_) * startOffset_, up_);
  if (polar > kPoleMargin && polar < 3.14159265f - kPoleMargin) pitch_ = pitch;  // never flip over a pole
}

void OrbitCamera::zoom(double steps) {
  scale_ = std::clamp(scale_ * std::pow(kZoomPerStep, float(steps)), kMinScale, kMaxScale);
}

void OrbitCamera::reset() { yaw_ = pitch_ = 0, scale_ = 1; }

glm::mat3 OrbitCamera::rotation() const { return axisRotation(yaw_, up_) * axisRotation(pitch_, pitchAxis_); }

float OrbitCamera::distance() const { return glm::length(startOffset_) * scale_; }

vknerf::Camera OrbitCamera::camera() const {
  const glm::mat3 r = rotation();
  const glm::mat3 rot = r * startRot_;
  // start + (new offset - start offset) rather than centre + new offset: with no input the rotation is
  // the identity, the difference is exactly zero and the start camera comes back unchanged.
  const glm::vec3 pos = startPos_ + (r * startOffset_ * scale_ - startOffset_);
  vknerf::Camera cam = start_;
  cam.c2w = {rot[0][0], rot[1][0], rot[2][0], pos.x, rot[0][1], rot[1][1], rot[2][1], pos.y,
             rot[0][2], rot[1][2], rot[2][2], pos.z, 0,         0,         0,         1};
  return cam;
}

vknerf::Camera OrbitCamera::cameraAtScale(uint32_t factor) const {
  vknerf::Camera cam = camera();
  if (factor <= 1) return cam;
  const uint32_t w = (cam.width + factor - 1) / factor, h = (cam.height + factor - 1) / factor;
  const float sx = float(w) / float(cam.width), sy = float(h) / float(cam.height);
  cam.fx *= sx, cam.cx *= sx, cam.fy *= sy, cam.cy *= sy;
  cam.width = w, cam.height = h;
  return cam;
}

vknerf::Camera lookAtBox(const vknerf::Aabb& box, uint32_t size) {
  const glm::vec3 lo(box.min[0], box.min[1], box.min[2]), hi(box.max[0], box.max[1], box.max[2]);
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = 1.5f * glm::length(hi - lo);  // half-diagonal / distance ~ tan(18 deg) < tan(22.6 deg)
  return vknerf::pinholeFromFocal(size, size, 1.2f * float(size),
                                  vknerf::orbitPose({centre.x, centre.y, centre.z}, radius, 30, 0, 1));
}

}  // namespace viewer
