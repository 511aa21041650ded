// The cloth's reach (ViewReach, render/camera.hpp) after every frame, for the default camera's follow
// (render/camera_follow.hpp), without a copy of the cloth: for the GPU solver one pass over its own position
// buffer (glsl/render/cloth_reach.comp) whose 52 bytes are copied into a ring the CPU reads through fences,
// so the viewer reads a frame's reach the frame after, without waiting; for a CPU solver, from the positions
// it holds in memory.
#pragma once

#include "core/solver.hpp"
#include "gl/objects.hpp"
#include "render/camera.hpp"

#include <array>

namespace drape {

class GpuSolver;

class ReachProbe {
 public:
  // For a GPU solver, needs its current GL 4.5 context.
  explicit ReachProbe(Solver& solver);

  // Measures the cloth as the solver holds it now (after a stepFrame() or a reset, or at the start).
  void measure(const ReachFrame& frame);
  // The reach measured before the last measure(): on the GPU a frame old, done by the time anyone asks (if
  // not, the wait is for that frame only, never the newest). Empty when there was none since forget().
  ViewReach previous();
  // The reach the last measure() took, waiting for it: `render`'s one small read a picture.
  ViewReach latest();
  // Nothing measured yet (the cloth has been reset).
  void forget();

 private:
  static constexpr int kSlots = 3;
  struct Slot {
    bool measured = false;
    float t_x = 1.0f;
    gl::Fence fence;  // GPU: the copy into the ring is done
    ViewReach cpu;    // CPU solver: the reach itself
  };
  ViewReach read(int slot);

  Solver* solver_;
  GpuSolver* gpu_;
  gl::Program program_;
  gl::Buffer result_;  // RENDER_REACH_VALUES uints
  gl::Buffer ring_;    // kSlots results, mapped for reading
  std::array<Slot, kSlots> slots_;
  int newest_ = -1;
};

}  // namespace drape
