#include "render/camera_follow.hpp"

#include <algorithm>

namespace drape {

namespace {

// The side planes (right, left, top, bottom in ViewReach::values()): what decides where the camera stands,
// and what it eases. The box, the nearest point and x follow what is needed, no more.
bool eased(int k) {
  return k >= 6 && k < 10;
}

}  // namespace

CameraFollow::CameraFollow(const FramingSubject& start, float aspect, float zoom)
    : start_(start), zoom_(zoom), frame_(ReachFrame::of(start.bounds().centre(), aspect)) {
  held_ = reachOf(start_, frame_);
  goal_ = held_;
  last_.t_x = frame_.t_x;
}

void CameraFollow::next(const ViewReach& previous) {
  if (previous.empty()) {
    forgetMotion();
    return;
  }
  const ViewReach seen = reframe(previous, frame_.t_x);
  const std::array<float, ViewReach::kValues> now = seen.values(), was = last_.values();
  std::array<float, ViewReach::kValues> held = held_.values(), goal = goal_.values();
  const float distance = this->distance();
  for (int k = 0; k < ViewReach::kValues; ++k) {
    // Outwards only: an edge moving in needs nothing more.
    const float speed = last_.empty() ? 0.0f : std::max(now[k] - was[k], 0.0f);
    const float need = std::max(held[k], now[k]);
    if (eased(k)) {
      if (need > held[k]) goal[k] = std::max(goal[k], need + kRoom * distance + kLeadFrames * speed);
      if (goal[k] > held[k]) held[k] += std::min(kEase * (goal[k] - held[k]), kMaxEase * distance);
    }
    held[k] = std::max(held[k], need);
  }
  held_ = ViewReach::fromValues(held, frame_.t_x);
  goal_ = ViewReach::fromValues(goal, frame_.t_x);
  last_ = seen;
}

void CameraFollow::forgetMotion() {
  last_ = ViewReach{};
  last_.t_x = frame_.t_x;
}

void CameraFollow::setAspect(float aspect) {
  const ReachFrame frame = ReachFrame::of(frame_.origin, aspect);
  if (frame.t_x == frame_.t_x) return;
  ViewReach held = reachOf(start_, frame);
  held.include(reframe(held_, frame.t_x));
  goal_ = reframe(goal_, frame.t_x);
  goal_.include(held);
  held_ = held;
  last_ = reframe(last_, frame.t_x);
  frame_ = frame;
}

Camera CameraFollow::camera(const ViewReach* now) const {
  ViewReach shown = held_;
  if (now && !now->empty()) shown.include(reframe(*now, frame_.t_x));
  Camera camera;
  camera.frame(shown, frame_);
  camera.zoom(zoom_);
  return camera;
}

float CameraFollow::distance() const {
  Camera camera;
  camera.frame(held_, frame_);
  return camera.distance();
}

}  // namespace drape
