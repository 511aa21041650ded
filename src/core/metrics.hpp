// Measurements of a cloth state, shared by the summary of `drape simulate`, tests, accuracy and
// stability reports. Pure functions of positions; no solver state.
#pragma once

#include "core/scene.hpp"
#include "core/topology.hpp"

#include <vector>

namespace drape {

using Positions = std::vector<glm::dvec3>;

glm::dvec3 centroid(const Positions& x);
double minY(const Positions& x);
double maxY(const Positions& x);
double maxDeviation(const Positions& a, const Positions& b);  // max |a_i - b_i|, m
double rmsDeviation(const Positions& a, const Positions& b);  // sqrt(mean |a_i - b_i|^2), m
double clothSize(const ClothSpec& cloth);                     // diagonal of the cloth, m
// Largest |x_b - x_a| / rest - 1 over the enabled spring types (0.1 means 10% stretched).
double maxStrain(const Topology& topo, const ClothSpec& cloth, const Positions& x);
// sum m |v/dt|^2 / 2 with v the per-substep displacement.
double kineticEnergy(const Positions& displacement, double mass, double dt);
// Signed distance of the closest point to each collider (negative: inside): spheres, then planes, then
// meshes (core/mesh_distance.hpp: from the obstacle's field where it holds exact values).
std::vector<double> colliderDistances(const Scene& scene, const Positions& x);
bool allFinite(const Positions& x);

}  // namespace drape
