// What a scene asks of the GPU solver, decided once from its options (sceneNeeds): every other part of
// src/gpu reads these decisions, never the scene's options themselves. GL-free.
#pragma once

#include "core/scene.hpp"

#include <array>

namespace drape::gpu {

// Where the collisions and the self-collision lists' travel check run. Collisions read and write only the
// point's own state, so they run inside the kernel that moved the point last (docs/design.md section 4): the
// self-collision pass when there is one, else Verlet's integration, else (XPBD and VBD, whose sweeps move the
// points after the prediction) a pass of their own. The travel check needs the positions the self-collision
// pass will see: it rides on Verlet's integration, and has a pass of its own after XPBD's or VBD's sweeps.
struct Fusion {
  bool collide_in_integrate = false;  // forces+integrate+collide (and the one-dispatch path's integrate phase)
  bool collide_in_contacts = false;   // self_collide+collide
  bool collide_pass = false;          // collide, after the constraint sweeps
  bool travel_in_integrate = false;   // forces+integrate+pairs_check
  bool travel_pass = false;           // pairs_check, after the constraint sweeps
};

// The fusion rule, the one place it is written.
Fusion fusionRule(bool contacts, bool colliders, bool predicts);

struct SceneNeeds {
  bool contacts = false;  // self-collision: the lists and their pass (or the one-dispatch path's in-group grid)
  bool wind = false;
  bool tethers = false;  // the tether pass, where the cloth has pins to tie to
  int spheres = 0, planes = 0, meshes = 0;
  bool colliders = false;  // any of the three
  bool grid = false;       // a grid cloth (its points all weigh the same: UNIFORM_MASS)
  Integrator integrator = Integrator::Verlet;
  bool predicts = false;     // XPBD or VBD: integrate predicts, constraint sweeps follow
  int sweeps = 1;            // constraint sweeps a substep (simulation.iterations)
  bool sweep_state = false;  // more than one sweep: XPBD keeps its multipliers, VBD the prediction
  bool gauss_seidel = true;  // the stretch scheme: Gauss-Seidel over the colouring, else Jacobi
  int stretch_passes = 0;
  int steps_per_frame = 1;
  std::array<bool, kSpringTypeCount> springs{};  // the spring types enabled
  unsigned spring_mask = 0;                      // the same as bits (1 << SpringType)
  Fusion fusion;
};

SceneNeeds sceneNeeds(const Scene& scene);

}  // namespace drape::gpu
