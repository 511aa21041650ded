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
// Where a pass moves the points after the collisions (the tethers, the stretch limit, the face contacts), the
// collisions run again after it (collide_last, as CpuSolver's): at the end of the face contacts' kernel when
// there is one, else a collide pass of its own.
struct Fusion {
  bool collide_in_integrate = false;  // forces+integrate+collide (and the one-dispatch path's integrate phase)
  bool collide_in_contacts = false;   // self_collide+collide
  bool collide_pass = false;          // collide, after the constraint sweeps
  bool travel_in_integrate = false;   // forces+integrate+pairs_check
  bool travel_pass = false;           // pairs_check, after the constraint sweeps
  bool collide_last = false;          // the collisions again after the last pass that moves points
  bool collide_in_faces = false;      // collide_faces+collide
  bool collide_last_pass = false;     // collide, after the tethers and the stretch limit
};

// The fusion rule, the one place it is written.
// `moved_after`: a pass moves points after the collisions; `faces`: the face contacts run.
Fusion fusionRule(bool contacts, bool colliders, bool predicts, bool moved_after, bool faces);

struct SceneNeeds {
  bool contacts = false;  // self-collision: the lists and their pass (or the one-dispatch path's in-group grid)
  bool wind = false;
  bool tethers = false;  // the tether pass, where the cloth has pins to tie to
  int spheres = 0, planes = 0, meshes = 0;
  bool colliders = false;  // any of the three
  // Decided by the cloth and the meshes' shapes, not the options: makePlan sets them from ClothCounts.
  bool faces = false;  // collide_faces: some mesh has sharp convex features (core/mesh_features.hpp)
  bool held = false;   // self-collision with pairs held at rest (physics::heldAtRest): HELD_AT_REST
  bool grid = false;   // a grid cloth (its points all weigh the same: UNIFORM_MASS)
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

// From the scene's options alone: tethers count as moving points after the collisions (the plan, which knows
// whether the cloth has pins to tie to, and whether the face contacts run, decides again: decideFromCloth).
SceneNeeds sceneNeeds(const Scene& scene);
// The decisions the cloth's tables make: whether the tethers run, the face contacts, the held pairs.
void decideFromCloth(SceneNeeds& needs, bool tether_pass, bool faces, bool held);

}  // namespace drape::gpu
