// The explicit-integration bound of a scene, the substep count that keeps inside it, and the blow-up
// test every long run applies. Pure functions of the scene and of positions; no solver state.
//
// The bound. Linearise the spring forces about any state: the stiffness matrix K is assembled from one
// 3x3 block per spring, k (u u^T) + k (1 - rest/len) (I - u u^T) with u the spring's unit vector; for
// len >= rest/2 its spectral norm is at most k. Block Gershgorin (Feingold & Varga 1962) on the free
// points then gives lambda_max(K) <= max_i (||K_ii|| + sum_j ||K_ij||) <= 2 k_sum, where k_sum is the
// largest per-vertex sum of enabled spring stiffnesses. Damped Verlet on x'' = -omega^2 x,
// x' = x + keep (x - x_prev) - (omega dt)^2 x, has the characteristic polynomial
// z^2 - (1 + keep - (omega dt)^2) z + keep; by the Jury criterion both roots lie in the unit circle iff
// (omega dt)^2 < 2 (1 + keep): omega dt < 2 undamped, but only sqrt(2) at 100 % damping (damping
// shrinks the stable range: with keep = 0 the step is gradient descent). With omega_max^2 = lambda_max/m
// it suffices that
//     dt sqrt(2 k_sum / m) < sqrt(2 (1 + keep)),  i.e.  dt sqrt(k_sum / m) < sqrt(1 + keep).
// Pins remove rows (eigenvalues interlace). The bound is sufficient, not necessary: for a full grid
// lambda_max is about 8 ks at rest (8.3 ks stretched by 10%) against 2 k_sum = 17.6 ks, so undamped the
// true limit of the number is near 2.1 (2.06) and the guard asks for up to 1.5x more substeps than
// strictly needed. It does not cover springs compressed
// below half their rest length (their transverse stiffness exceeds k: a buckling start), nor the
// position corrections (collisions, stretch limit, self-collision), which are projections, not forces.
#pragma once

#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"

#include <string>

namespace drape {

// The guard's limit on dt sqrt(k_sum / m) without damping (see above): sqrt(2).
inline constexpr double kStabilityLimit = 1.4142135623730951;
// The limit for a damping percentage: sqrt(1 + keep), keep = 1 - damping/100; from sqrt(2) to 1.
double stabilityLimit(double damping_percent);
// autoSubsteps never asks for more than this (a scene needing more is reported, not run for hours):
// the most a scene file may ask for.
inline constexpr int kMaxAutoSubsteps = kMaxStepsPerFrame;

struct StabilityCheck {
  double number = 0.0;             // dt sqrt(k_sum / m)
  double limit = kStabilityLimit;  // stable when number < limit (stabilityLimit of the scene's damping)
  bool ok = true;
  int steps_needed = 0;  // when !ok: autoSubsteps of the scene (0: no count up to kMaxAutoSubsteps)
  std::string message;   // one line; says what to do when !ok
};

// Largest sum over one point of the stiffness of its enabled springs, N/m (bending counts 0.2 ks),
// from the grid size alone (an interior point has 4 structural, 4 shearing and 4 bending springs; on
// small grids no point has them all). Pins are ignored, which can only overestimate.
double maxStiffnessSum(const ClothSpec& cloth);
// The largest k_sum / m over the cloth's points (a mesh's vary), 1/s^2.
double maxStiffnessOverMass(const ClothSpec& cloth);
double stabilityNumber(const Scene& scene);
StabilityCheck checkStability(const Scene& scene);
// Smallest steps_per_frame (>= 1) at which withSubsteps(scene, steps) is inside the bound; 0 if more than
// max_steps would be needed (or the point mass is zero).
int autoSubsteps(const Scene& scene, int max_steps = kMaxAutoSubsteps);

// The scene at another substep count with the same physics. Damping is a fraction of the displacement
// lost per substep (CS184), so the same number at s substeps instead of S is a different material (at
// 16x the substeps it loses 16x as much per second); this keeps the loss per simulated second:
// 1 - d_s = (1 - d)^(S/s). Collision friction is the same kind of per-substep factor (a point in
// contact keeps (1 - f) of its displacement each substep) and is rescaled the same way.
Scene withSubsteps(const Scene& scene, int steps_per_frame);
// The scene at autoSubsteps' count where that is more than it has (withSubsteps); as it is where it is inside
// the bound already, or where no count up to max_steps would do (checkStability then still says so).
Scene withStableSubsteps(const Scene& scene, int max_steps = kMaxAutoSubsteps);

// What counts as a blow-up in the measurement commands: a non-finite coordinate, a spring longer than
// (1 + max_strain) times its rest length, or a point farther than max_travel cloth sizes from where it
// started.
struct BlowUpCriteria {
  double max_strain = 10.0;
  double max_travel = 100.0;  // cloth sizes (diagonals)
};

// Empty while the state is sane, else one line saying what broke (and at which point).
std::string detectBlowUp(const Topology& topo, const ClothSpec& cloth, const Positions& start, const Positions& x,
                         const BlowUpCriteria& criteria = {});

}  // namespace drape
