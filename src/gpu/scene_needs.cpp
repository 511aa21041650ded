#include "gpu/scene_needs.hpp"

namespace drape::gpu {

Fusion fusionRule(bool contacts, bool colliders, bool predicts, bool moved_after, bool faces) {
  Fusion f;
  f.collide_last = colliders && moved_after;
  f.collide_in_faces = f.collide_last && faces;
  f.collide_last_pass = f.collide_last && !faces;
  f.collide_in_contacts = colliders && contacts;
  f.collide_in_integrate = colliders && !contacts && !predicts;
  f.collide_pass = colliders && !contacts && predicts;
  f.travel_in_integrate = contacts && !predicts;
  f.travel_pass = contacts && predicts;
  return f;
}

SceneNeeds sceneNeeds(const Scene& scene) {
  const SimParams& sim = scene.sim;
  SceneNeeds n;
  n.contacts = sim.self_collision;
  n.wind = sim.wind.enabled;
  n.tethers = sim.tethers;
  n.spheres = int(scene.spheres.size());
  n.planes = int(scene.planes.size());
  n.meshes = int(scene.meshes.size());
  n.colliders = n.spheres + n.planes + n.meshes > 0;
  n.grid = scene.cloth.isGrid();
  n.integrator = sim.integrator;
  n.predicts = isImplicit(sim.integrator);
  n.sweeps = sim.iterations;
  n.sweep_state = n.predicts && sim.iterations > 1;
  n.gauss_seidel = sim.stretch_scheme == StretchScheme::GaussSeidel;
  n.stretch_passes = sim.stretch_passes;
  n.steps_per_frame = sim.steps_per_frame;
  for (int t = 0; t < kSpringTypeCount; ++t) {
    n.springs[std::size_t(t)] = scene.cloth.springEnabled(SpringType(t));
    if (n.springs[std::size_t(t)]) n.spring_mask |= 1U << unsigned(t);
  }
  n.fusion = fusionRule(n.contacts, n.colliders, n.predicts, n.tethers || n.stretch_passes > 0, false);
  return n;
}

void decideFromCloth(SceneNeeds& n, bool tether_pass, bool faces, bool held) {
  n.faces = faces && n.meshes > 0;
  n.held = held && n.contacts;
  n.fusion = fusionRule(n.contacts, n.colliders, n.predicts, tether_pass || n.stretch_passes > 0 || n.faces, n.faces);
}

}  // namespace drape::gpu
