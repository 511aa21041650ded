#include "render/camera.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace drape {

namespace {
constexpr float kMaxPitch = 1.55f;  // just short of pi/2, where lookAt's up vector degenerates
}

void Camera::frame(const Bounds& bounds, float aspect) {
  target_ = bounds.centre();
  scene_radius_ = std::max(bounds.radius(), 1e-3f);
  const float half_fov_y = 0.5f * kFovY;
  const float half_fov_x = std::atan(std::tan(half_fov_y) * std::max(aspect, 1e-3f));
  // The whole enclosing sphere in view (a tighter fit cuts off the corners nearest the camera), with a
  // small margin so that the silhouette does not touch the window's edge.
  distance_ = 1.05f * scene_radius_ / std::sin(std::min(half_fov_x, half_fov_y));
  yaw_ = kDefaultYaw;
  pitch_ = kDefaultPitch;
}

void Camera::orbit(float d_yaw, float d_pitch) {
  yaw_ = std::remainder(yaw_ + d_yaw, 2.0f * 3.14159265f);
  pitch_ = std::clamp(pitch_ + d_pitch, -kMaxPitch, kMaxPitch);
}

void Camera::pan(float dx, float dy, float viewport_height) {
  const float world_per_pixel = 2.0f * distance_ * std::tan(0.5f * kFovY) / std::max(viewport_height, 1.0f);
  const glm::mat4 v = view();
  const glm::vec3 right{v[0][0], v[1][0], v[2][0]};
  const glm::vec3 up{v[0][1], v[1][1], v[2][1]};
  target_ += (-dx * right + dy * up) * world_per_pixel;
}

void Camera::zoom(float factor) {
  distance_ = std::clamp(distance_ * factor, 1e-3f * scene_radius_, 1e3f * scene_radius_);
}

glm::vec3 Camera::position() const {
  const glm::vec3 offset{std::cos(pitch_) * std::sin(yaw_), std::sin(pitch_), std::cos(pitch_) * std::cos(yaw_)};
  return target_ + distance_ * offset;
}

glm::mat4 Camera::view() const {
  return glm::lookAt(position(), target_, glm::vec3(0.0f, 1.0f, 0.0f));
}

glm::mat4 Camera::projection(float aspect) const {
  // The far plane reaches past the renderer's ground planes (40 scene radii across); near keeps a 1e4
  // depth ratio.
  const float far_plane = distance_ + 30.0f * scene_radius_ + 10.0f;
  const float near_plane = std::max(far_plane * 1e-4f, 0.05f * std::min(distance_, scene_radius_));
  return glm::perspective(kFovY, std::max(aspect, 1e-3f), near_plane, far_plane);
}

Ray Camera::rayThrough(glm::vec2 pixel, glm::ivec2 viewport) const {
  const float aspect = float(viewport.x) / float(std::max(viewport.y, 1));
  const glm::mat4 inverse = glm::inverse(viewProjection(aspect));
  const glm::vec2 ndc{2.0f * pixel.x / float(viewport.x) - 1.0f, 1.0f - 2.0f * pixel.y / float(viewport.y)};
  glm::vec4 near_point = inverse * glm::vec4(ndc, -1.0f, 1.0f);
  glm::vec4 far_point = inverse * glm::vec4(ndc, 1.0f, 1.0f);
  const glm::vec3 a = glm::vec3(near_point) / near_point.w;
  const glm::vec3 b = glm::vec3(far_point) / far_point.w;
  return {position(), glm::normalize(b - a)};
}

}  // namespace drape
