#include "render/camera.hpp"

#include "core/health.hpp"

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

ReachFrame ReachFrame::of(glm::vec3 origin, float aspect) {
  ReachFrame frame;
  frame.origin = origin;
  frame.axes = Camera::defaultAxes();
  frame.t_y = Camera::kFill * std::tan(0.5f * Camera::kFovY);
  frame.t_x = frame.t_y * std::clamp(aspect, 1e-3f, Camera::kFramingAspect);
  return frame;
}

std::array<float, ViewReach::kValues> ViewReach::values() const {
  return {-box.min.x, -box.min.y, -box.min.z, box.max.x, box.max.y, box.max.z, right,
          left,       top,        bottom,     nearest,   x_right,   x_left};
}

ViewReach ViewReach::fromValues(const std::array<float, kValues>& v, float t_x) {
  ViewReach reach;
  reach.box = {{-v[0], -v[1], -v[2]}, {v[3], v[4], v[5]}};
  reach.right = v[6];
  reach.left = v[7];
  reach.top = v[8];
  reach.bottom = v[9];
  reach.nearest = v[10];
  reach.x_right = v[11];
  reach.x_left = v[12];
  reach.t_x = t_x;
  return reach;
}

void ViewReach::include(const ViewReach& other) {
  std::array<float, kValues> v = values();
  const std::array<float, kValues> w = other.values();
  for (int k = 0; k < kValues; ++k)
    v[k] = std::max(v[k], w[k]);
  *this = fromValues(v, t_x);
}

// A sphere of radius r touches a side plane of slope t where its centre is r sqrt(1 + t^2) / t further out
// than a point would: its furthest point along that plane's normal.
void ViewReach::include(glm::vec3 point, float radius, const ReachFrame& frame) {
  t_x = frame.t_x;
  box.include(point - radius);
  box.include(point + radius);
  const glm::vec3 v = point - frame.origin;
  const float x = glm::dot(v, frame.axes.right), y = glm::dot(v, frame.axes.up), z = glm::dot(v, frame.axes.back);
  const float s_x = std::sqrt(1.0f + frame.t_x * frame.t_x), s_y = std::sqrt(1.0f + frame.t_y * frame.t_y);
  right = std::max(right, z + (x + radius * s_x) / frame.t_x);
  left = std::max(left, z + (-x + radius * s_x) / frame.t_x);
  top = std::max(top, z + (y + radius * s_y) / frame.t_y);
  bottom = std::max(bottom, z + (-y + radius * s_y) / frame.t_y);
  nearest = std::max(nearest, z + radius);
  x_right = std::max(x_right, x + radius);
  x_left = std::max(x_left, -x + radius);
}

ViewReach reachOf(const FramingSubject& subject, const ReachFrame& frame) {
  ViewReach reach;
  reach.t_x = frame.t_x;
  for (const glm::vec3& p : subject.points)
    reach.include(p, 0.0f, frame);
  for (const glm::vec4& s : subject.spheres)
    reach.include(glm::vec3(s), s.w, frame);
  return reach;
}

ViewReach reachOf(const std::vector<glm::dvec3>& points, const ReachFrame& frame) {
  ViewReach reach;
  reach.t_x = frame.t_x;
  for (const glm::dvec3& p : points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
        std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) <= kSaneBound)
      reach.include(glm::vec3(p), 0.0f, frame);
  return reach;
}

// With s = t / t' and z + x / t' = (1 - s) z + s (z + x / t): for a wider view (s < 1) a convex combination
// of what was measured, for a narrower one (z + x / t) + (1 / t' - 1 / t) x.
ViewReach reframe(const ViewReach& reach, float t_x) {
  ViewReach out = reach;
  out.t_x = t_x;
  if (reach.empty() || t_x == reach.t_x) return out;
  const float s = reach.t_x / t_x;
  if (s < 1.0f) {
    out.right = (1.0f - s) * reach.nearest + s * reach.right;
    out.left = (1.0f - s) * reach.nearest + s * reach.left;
  } else {
    const float more = 1.0f / t_x - 1.0f / reach.t_x;
    out.right = reach.right + more * reach.x_right;
    out.left = reach.left + more * reach.x_left;
  }
  return out;
}

void Camera::frame(const FramingSubject& subject, float aspect) {
  frame(reachOf(subject, ReachFrame::of(subject.bounds().centre(), aspect)),
        ReachFrame::of(subject.bounds().centre(), aspect));
}

void Camera::frame(const ViewReach& reach, const ReachFrame& frame) {
  const Bounds bounds = reach.empty() ? Bounds{} : reach.box;
  target_ = bounds.centre();
  scene_radius_ = std::max(bounds.radius(), 1e-3f);
  yaw_ = kDefaultYaw;
  pitch_ = kDefaultPitch;
  distance_ = 1.0f;
  if (reach.empty()) return;  // nothing to frame
  // A point at (x, y) across the view and z towards the camera is inside the margin seen from
  // target + (a, b) in the view plane and distance d when |x - a| <= t_x (d - z), and likewise for y:
  // d >= (z + x / t_x) - a / t_x and d >= (z - x / t_x) + a / t_x. With R and L the largest of those
  // terms over the subject (measured from the target), the least d is (R + L) / 2 at a = t_x (R - L) / 2,
  // which centres the subject in the frame (a flat cloth seen from above looms larger at its near edge
  // than at its far one). The reach was measured from frame.origin: each term moves by the target's own.
  const auto& [right, up, back] = frame.axes;
  const float t_x = frame.t_x, t_y = frame.t_y;
  const glm::vec3 c = target_ - frame.origin;
  const float cx = glm::dot(c, right), cy = glm::dot(c, up), cz = glm::dot(c, back);
  const float right_most = reach.right - (cz + cx / t_x), left_most = reach.left - (cz - cx / t_x);
  const float top_most = reach.top - (cz + cy / t_y), bottom_most = reach.bottom - (cz - cy / t_y);
  const float nearest = reach.nearest - cz;
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
