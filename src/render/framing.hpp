// Where things are over a run, for what the default camera frames and what the renderer's floor and shadow
// map cover: the colliders, and the cloth at every frame the look-ahead ran (the run itself, stepped once
// before the first image, then reset). Pure maths on the CPU; no GL.
#pragma once

#include "core/scene.hpp"
#include "core/solver.hpp"
#include "core/topology.hpp"
#include "render/camera.hpp"

#include <functional>
#include <vector>

namespace drape {

// What the scene stands on: its first plane (a collider), or a floor drawn under everything else, across
// gravity, when it has none.
struct Ground {
  glm::vec3 point{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};  // unit, pointing up
  bool from_scene = false;             // the scene's first plane; false: a neutral floor, drawn only
};

class SceneExtent {
 public:
  // The start: the cloth at rest and the colliders.
  SceneExtent(const Scene& scene, const Topology& topology);

  // The cloth at one more frame of the run. Only the points the default view can see at its edges are kept
  // (the upper convex hulls of the cloth in the view's horizontal and vertical planes, which hold the
  // extremes Camera::frame looks for), so a long run costs a few points a frame.
  void addCloth(const std::vector<glm::dvec3>& x);
  int clothFrames() const { return cloth_frames_; }  // frames added, the start included

  // What the default camera frames: the cloth wherever it was, the colliders (spheres as spheres), and the
  // cloth's footprint on the ground (where its shadow falls).
  FramingSubject subject() const;
  // What casts shadows: the cloth wherever it was and the colliders; the shadow map covers this.
  Bounds casterBounds() const;
  // The scene's first plane, or a neutral floor a little below everything the run reached.
  Ground ground() const;

 private:
  Bounds colliderBounds() const;

  glm::vec3 up_;                   // the ground's normal
  bool scene_ground_ = false;      // the scene has a plane; ground_point_ is its point
  glm::vec3 ground_point_{0.0f};   // the plane's point (scene ground only)
  std::vector<glm::vec3> cloth_;   // outline points of the cloth over the frames added
  std::vector<glm::vec3> shadow_;  // the same, projected on the plane through the origin across up_
  Bounds cloth_bounds_;
  FramingSubject colliders_;  // sphere silhouettes and mesh obstacles' vertices
  int cloth_frames_ = 0;
};

// The frames the default framing looks ahead: the first 2 s of the run, as the viewer frames it. `render`
// looks ahead its own run when that is longer.
int lookAheadFrames(const Scene& scene);

// Steps `solver` `frames` frames from its current state and adds each frame's cloth to `extent` (one read-back
// a frame: a phase before the run, never part of it), then resets the solver. `each` sees every frame's
// positions, the first (frame 0) included. Stops at a blow-up. Returns the frames stepped.
int lookAhead(SceneExtent& extent, Solver& solver, int frames,
              const std::function<void(int frame, const std::vector<glm::dvec3>& x)>& each = {});

}  // namespace drape
