// The default camera over a run, the same rule in `render` and the viewer. It starts on what the look-ahead
// saw (render/framing.hpp: the scene and the cloth over the run's first frames) and, from then on, widens
// whenever the cloth would reach beyond what it holds: never closer, never losing what it showed.
//
// Each frame it first takes what the cloth needs (its reach at the frame before) and, once the cloth has
// gone beyond what it held, eases towards some room past that (a tenth of the distance, and the cloth's
// edges' travel over the next kLeadFrames frames at the speed they moved), a fifth of the way a frame and
// at most 2% of the distance: what is needed is never eased, the rest never jumps, and a cloth moving
// steadily is held before it gets there. A cloth moving about within what the camera holds moves it not
// at all (a lead taken from every outward motion would creep outwards with each swing). Pure maths on the CPU: the
// reach comes from render/reach_probe.hpp, a frame late, so that the viewer never waits for the GPU; `render` also has
// the frame's own reach, and its picture holds that too.
#pragma once

#include "render/camera.hpp"

namespace drape {

class CameraFollow {
 public:
  static constexpr float kRoom = 0.1f;         // of the camera's distance, beyond what is needed, once widening
  static constexpr float kLeadFrames = 10.0f;  // and the cloth's edges' travel over this many frames
  static constexpr float kEase = 0.2f;         // of the way to that room, each frame
  static constexpr float kMaxEase = 0.02f;     // of the camera's distance, each frame, at most

  // Frames `start` (what the look-ahead saw) at this aspect ratio, then scales the distance by `zoom`.
  CameraFollow(const FramingSubject& start, float aspect, float zoom = 1.0f);

  // The frames the reach is measured in: the probe's directions.
  const ReachFrame& frame() const { return frame_; }

  // Moves on to the next frame of the run, given the cloth's reach at the frame before it (empty when it was
  // not measured: the cloth was hidden as blown up, or has just been reset).
  void next(const ViewReach& previous);
  // Forgets how the cloth moved (it has been reset to its start); keeps what the camera holds.
  void forgetMotion();
  // Measures from now on at another aspect ratio; what the camera holds is kept (at least).
  void setAspect(float aspect);

  // The camera for this frame's picture. `now`: the cloth's reach at this very frame, where the caller has it
  // (`render`): the picture holds it too, whatever the motion did.
  Camera camera(const ViewReach* now = nullptr) const;
  // What the camera holds (for tests).
  const ViewReach& held() const { return held_; }

 private:
  float distance() const;  // of the camera framing held_

  FramingSubject start_;
  float zoom_;
  ReachFrame frame_;
  ViewReach held_;  // what the camera must keep in view
  ViewReach goal_;  // where it eases to
  ViewReach last_;  // the cloth's reach at the frame before the current (empty: not known)
};

}  // namespace drape
