#include "render/camera.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace drape {

namespace {
constexpr float kMaxPitch = 1.55f;  // just short of pi/2, where lookAt's up vector degenerates
}

Bounds FramingSubject::bounds() const {
  Bounds b{glm::vec3(1e30f), glm::vec3(-1e30f)};
  for (const glm::vec3& p : points)
    b.include(p);
  for (const glm::vec4& s : spheres) {
    b.include(glm::vec3(s) - s.w);
    b.include(glm::vec3(s) + s.w);
  }
  return b.min.x <= b.max.x ? b : Bounds{};
}

void Camera::frame(const Bounds& bounds, float aspect) {
  FramingSubject corners;
  for (int corner = 0; corner < 8; ++corner)
    corners.points.push_back({corner & 1 ? bounds.max.x : bounds.min.x, corner & 2 ? bounds.max.y : bounds.min.y,
                              corner & 4 ? bounds.max.z : bounds.min.z});
  frame(corners, aspect);
}

ViewAxes Camera::defaultAxes() {
  Camera camera;
  camera.target_ = glm::vec3(0.0f);
  camera.distance_ = 1.0f;
  const glm::vec3 back = camera.position();
  const glm::vec3 right = glm::normalize(glm::cross(-back, glm::vec3(0.0f, 1.0f, 0.0f)));
  return {right, glm::cross(right, -back), back};
}

void Camera::frame(const FramingSubject& subject, float aspect) {
  const Bounds bounds = subject.bounds();
  target_ = bounds.centre();
  scene_radius_ = std::max(bounds.radius(), 1e-3f);
  yaw_ = kDefaultYaw;
  pitch_ = kDefaultPitch;
  distance_ = 1.0f;
  // The view's axes for this direction; they do not depend on the distance.
  const auto [right, up, back] = defaultAxes();
  // A point at (x, y) across the view and z towards the camera is inside the margin seen from
  // target + (a, b) in the view plane and distance d when |x - a| <= t_x (d - z), t_x = kFill
  // tan(fov_x / 2), and likewise for y; a sphere of radius r when its centre is r away from each side
  // plane of that narrowed frustum: t_x (d - z) - |x - a| >= r sqrt(1 + t_x^2). Per axis that is
  // d >= R - a / t_x and d >= L + a / t_x with R and L the largest right and left terms over the
  // subject; the least d is (R + L) / 2 at a = t_x (R - L) / 2, which centres the subject in the frame
  // (a flat cloth seen from above looms larger at its near edge than at its far one).
  const float t_y = kFill * std::tan(0.5f * kFovY);
  const float t_x = t_y * std::clamp(aspect, 1e-3f, kFramingAspect);
  const float s_x = std::sqrt(1.0f + t_x * t_x), s_y = std::sqrt(1.0f + t_y * t_y);
  float right_most = -1e30f, left_most = -1e30f, top_most = -1e30f, bottom_most = -1e30f, nearest = -1e30f;
  auto fit = [&](const glm::vec3& p, float r) {
    const glm::vec3 v = p - target_;
    const float x = glm::dot(v, right), y = glm::dot(v, up), z = glm::dot(v, back);
    right_most = std::max(right_most, z + (x + r * s_x) / t_x);
    left_most = std::max(left_most, z + (-x + r * s_x) / t_x);
    top_most = std::max(top_most, z + (y + r * s_y) / t_y);
    bottom_most = std::max(bottom_most, z + (-y + r * s_y) / t_y);
    nearest = std::max(nearest, z + r);
  };
  for (const glm::vec3& p : subject.points)
    fit(p, 0.0f);
  for (const glm::vec4& s : subject.spheres)
    fit(glm::vec3(s), s.w);
  if (nearest < -1e29f) return;  // nothing to frame
  target_ += 0.5f * t_x * (right_most - left_most) * right + 0.5f * t_y * (top_most - bottom_most) * up;
  const float distance = std::max(0.5f * (right_most + left_most), 0.5f * (top_most + bottom_most));
  // The nearest surface stays well beyond the near plane (projection() puts it at 5% of the radius at
  // most). The shift of the target moved nothing along the view axis, so `nearest` still holds.
  distance_ = std::max(distance, nearest + 0.2f * scene_radius_);
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
