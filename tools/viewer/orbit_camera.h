#pragma once
// Turntable navigation around the scene box centre, starting from a given camera. Dragging turns
// the camera about the world's up axis (yaw) and tilts it over the centre (pitch); the wheel moves it
// towards or away from the centre. The start pose is reproduced exactly (bit for bit) until the
// first input, so a screenshot of the start view equals the command line's render of that camera.
#include <glm/glm.hpp>

#include "vknerf/camera.h"

namespace viewer {

class OrbitCamera {
 public:
  // `up`: the world's up direction (need not be exactly perpendicular to anything).
  OrbitCamera(const vknerf::Camera& start, const glm::vec3& centre, const glm::vec3& up);

  // Mouse motion in window pixels while the left button is held: the scene follows the cursor.
  void drag(double dxPixels, double dyPixels);
  // Scroll wheel steps: positive moves closer.
  void zoom(double steps);
  void reset();

  // The current camera at the start camera's resolution.
  vknerf::Camera camera() const;
  // The same view at 1/factor of the resolution (rounded up), intrinsics scaled to match.
  vknerf::Camera cameraAtScale(uint32_t factor) const;
  // Distance from the camera to the orbit centre.
  float distance() const;

 private:
  glm::mat3 rotation() const;  // applied to the start pose about the centre

  vknerf::Camera start_;
  glm::vec3 centre_, up_, startPos_, startOffset_, pitchAxis_;
  glm::mat3 startRot_;
  float yaw_ = 0, pitch_ = 0, scale_ = 1;
};

// A camera looking at the box centre from 30 degrees above the horizon (+Z up, nerf_synthetic's
// world), far enough for the whole box to fit a ~45 degree field of view: the start view when no
// scene gives one.
vknerf::Camera lookAtBox(const vknerf::Aabb& box, uint32_t size);

}  // namespace viewer
