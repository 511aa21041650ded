// What the GPU solver uploads of a scene, worked out on the host (GL-free): the parameters every kernel reads,
// the per-point masses, the adjacency and the coloured springs of the enabled spring types, the tables of the
// tiled and one-dispatch stretch limits, and the tethers (the colliders: colliders.hpp). Every value is
// rounded with the CPU reference's operations, so both solvers start from the same floats.
#pragma once

#include "core/colouring.hpp"
#include "core/health.hpp"
#include "core/scene.hpp"
#include "core/tethers.hpp"
#include "core/topology.hpp"
#include "gpu/layout.hpp"
#include "gpu/scene_needs.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace drape::gpu {

// Each point's weight, inverse mass, wind drag and normal stencil (CpuSolver::refreshDerived's operations).
std::vector<PointMass> pointMasses(const Scene& scene, const Topology& topo);

struct ParamsInput {
  double pair_margin = 0;  // GpuSolverOptions::pair_margin
  HealthLimits health;
  std::uint32_t buckets = 0;  // the hash grid's, a power of two
  // m, the shortest structural spring at rest: the lists' skin is pair_margin times it where it is shorter than
  // the contact distance (CpuSolver::selfCollide), so that both solvers rebuild alike.
  double shortest_spring = std::numeric_limits<double>::infinity();
};
// The shortest structural spring's rest length (infinity without one).
double shortestStructural(const Topology& topo);
// The kernels' constants; on a grid (UNIFORM_MASS) the weight every point shares, which `masses` must agree on.
SimParams simParams(const Scene& scene, const std::vector<PointMass>& masses, const ParamsInput& in);

// The adjacency of the enabled spring types, in the CPU's order (ascending spring index): a disabled type costs
// no memory traffic, and the kernels need no per-entry test.
struct Adjacency {
  std::vector<std::uint32_t> offsets;  // point i's entries are neighbors[offsets[i] .. offsets[i + 1])
  std::vector<Neighbor> neighbors;
};
Adjacency adjacency(const Topology& topo, const SceneNeeds& needs);

// The Gauss-Seidel passes' springs: the enabled ones in colour order, and where each colour starts.
struct ColouredSprings {
  std::vector<ColouredSpring> springs;
  std::vector<std::uint32_t> start;  // colour c is springs[start[c] .. start[c + 1])
};
ColouredSprings colouredSprings(const Topology& topo, const SpringColouring& colouring, const SceneNeeds& needs);

// Per colour and point, the point's spring of that colour (at most one: springs of a colour share no point),
// colour-major: the Gauss-Seidel stretch seen from the points where the grid cannot give it.
std::vector<ColourPartner> colourPartners(const Topology& topo, const SpringColouring& colouring,
                                          const SceneNeeds& needs);

std::vector<Tether> tetherEntries(const Tethers& tethers);

// Whether some pair of the cloth's rest points may be closer than `range` (m): a little over it, so that every
// pair physics::heldAtRest holds in float is found (the kernels then apply the exact test). A sweep along x.
bool mayHoldPairs(const Topology& topo, double range);

// The rest positions as the kernels read them (kBindingRest): 3 floats a point.
std::vector<float> restPositions(const Topology& topo);

}  // namespace drape::gpu
