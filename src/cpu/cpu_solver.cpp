#include "cpu/cpu_solver.hpp"
#include "cpu/cpu_solver_sweep.hpp"
#include "cpu/mesh_physics.hpp"
#include "cpu/parallel.hpp"

#include "core/derived.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <type_traits>

namespace drape {

namespace {

enum PassId {
  kForces,
  kIntegrate,
  kXpbd,
  kVbd,
  kSelfCollide,
  kCollide,
  kTether,
  kLimitStretch,
  kCollideFaces,
  kCollideLast,
  kPassCount
};
const char* const kPassNames[kPassCount] = {"forces",        "integrate",   "xpbd_solve",    "vbd_solve",
                                            "self_collide",  "collide",     kTetherPassName, "limit_stretch",
                                            "collide_faces", "collide_last"};

}  // namespace

template <class T>
CpuSolver<T>::CpuSolver(Scene scene, CpuSolverOptions options)
    : scene_(std::move(scene)), topo_(buildTopology(scene_.cloth)), form_(options.form) {
  threads_ = options.threads > 0 ? options.threads : std::max(omp_get_num_procs(), 1);
  pair_margin_ = options.pair_margin;
  adaptive_skin_ = options.adaptive_skin;
  pass_timing_ = options.pass_timing;
  record_waits_ = options.record_waits;
  rest_.reserve(topo_.springs.size());
  shortest_spring_ = std::numeric_limits<double>::infinity();
  for (const Spring& s : topo_.springs) {
    rest_.push_back(T(s.rest));
    if (s.type == SpringType::Structural) shortest_spring_ = std::min(shortest_spring_, s.rest);
  }
  // Also per adjacency entry: the gathers read it beside the entry, not through the spring index.
  rest_adjacent_.reserve(topo_.adjacency.size());
  for (const Neighbor& nb : topo_.adjacency)
    rest_adjacent_.push_back(T(nb.rest));
  colouring_ = colourSprings(topo_);
  if (options.skip_held_pairs) {
    pairs_.setRest(std::vector<vec3>(topo_.initial_positions.begin(), topo_.initial_positions.end()));
    if (topo_.W > 0 && options.pair_stencil) pairs_.setGrid(topo_.W, topo_.H);
    pairs_.setStencilSquares(options.stencil_squares);
  }
  buildFaceContacts();
  const std::size_t n = std::size_t(topo_.pointCount());
  team_ =
      threads_ > 1 && (long long)n >= std::min(options.team_min_points, options.team_trial_min_points) ? threads_ : 1;
  if (team_ > 1 && (long long)n < options.team_min_points)
    trial_.emplace(machineRoom(team_), missedProcessorTime(team_));
  if constexpr (std::is_same_v<T, float>)
    if (options.grid_path) {
      kernels_ = &drape::gridKernels(options.grid_isa);
      pairs_.setKernels(kernels_);
      if (topo_.W > 0) grid_.emplace(topo_, rest_, options.grid_isa);
    }
  f_.resize(n);
  correction_.resize(n);
  if (options.keep_self_corrections) self_correction_.assign(n, vec3(0));
  resetTimings();
  refreshDerived();
  reset();
}

template <class T>
std::string CpuSolver<T>::name() const {
  std::string base = sizeof(T) == sizeof(double) ? "cpu64" : "cpu";
  return form_ == VerletForm::Displacement ? base : base + "-xprev";
}

template <class T>
void CpuSolver<T>::refreshDerived() {
  const ClothSpec& c = scene_.cloth;
  if constexpr (std::is_same_v<T, float>) {
    quick_health_ = quickHealth(topo_, c);
    if (grid_) grid_->setHealthLimits(topo_, c);
  }
  const std::size_t n = std::size_t(topo_.pointCount());
  mass_.resize(n);
  inv_mass_.resize(n);
  drag_area_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    mass_[i] = T(derived::pointMass(c, topo_, i));
    inv_mass_[i] = T(1) / mass_[i];
    drag_area_[i] = T(derived::dragArea(scene_.sim.wind.drag, c, topo_, i));
  }
  if constexpr (std::is_same_v<T, float>) {
    if (grid_) grid_->setMasses(mass_, inv_mass_);
    if (kernels_) {
      const float pin = std::bit_cast<float>(~std::uint32_t(0));
      inv_mass3_.resize(3 * n);
      pinned3_.resize(3 * n);
      pinned1_.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        pinned1_[i] = topo_.pinned[i] ? pin : 0.0f;
      for (std::size_t e = 0; e < 3 * n; ++e) {
        inv_mass3_[e] = inv_mass_[e / 3];
        pinned3_[e] = topo_.pinned[e / 3] ? pin : 0.0f;
      }
    }
  }
  // collide()'s objects for the vectorised spheres and planes (cpu/grid_kernels.hpp, CollideArgs), made here
  // because a team's threads all run collide()
  collide_objects_.clear();
  for (const SphereSpec& s : scene_.spheres)
    collide_objects_.insert(collide_objects_.end(), {float(s.origin.x), float(s.origin.y), float(s.origin.z),
                                                     float(s.radius), float(s.friction)});
  for (const PlaneSpec& p : scene_.planes)
    collide_objects_.insert(collide_objects_.end(),
                            {float(p.point.x), float(p.point.y), float(p.point.z), float(p.normal.x), float(p.normal.y),
                             float(p.normal.z), float(p.friction)});
  dt_ = T(scene_.sim.dt());
  keep_ = T(1.0 - c.damping / 100.0);
  // A disabled spring type exerts no force: stiffness 0 is never used, the gather skips the type.
  stiffness_.k[int(SpringType::Structural)] = T(c.ks);
  stiffness_.k[int(SpringType::Shearing)] = T(c.ks);
  stiffness_.k[int(SpringType::Bending)] = T(derived::bendingStiffness(c));
  for (int t = 0; t < kSpringTypeCount; ++t)
    alpha_tilde_.k[t] = T(derived::xpbdAlphaTilde(c, scene_.sim, SpringType(t)));
  if (scene_.sim.integrator == Integrator::Vbd && point_colouring_.start.empty()) {
    point_colouring_ = colourPoints(topo_);
    if (grid_) grid_->setVbdPoints(point_colouring_.points);
  }
  // Built the first time a scene or a live change asks for them: a Dijkstra search over the cloth.
  if (scene_.sim.tethers && tether_rest_.empty() && tethers_.slots == 0) {
    tethers_ = buildTethers(topo_);
    tether_rest_.assign(tethers_.rest.begin(), tethers_.rest.end());
  }
}

template <class T>
void CpuSolver<T>::setParams(const ClothSpec& cloth, const SimParams& sim) {
  applyLiveParams(scene_, cloth, sim);
  refreshDerived();
}

template <class T>
void CpuSolver<T>::reset() {
  positionsMoved();
  const std::size_t n = std::size_t(topo_.pointCount());
  x_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    x_[i] = vec3(topo_.initial_positions[i]);
  // At rest: zero displacement, or x_prev = x in the CS184 form.
  v_ = form_ == VerletForm::Displacement ? std::vector<vec3>(n, vec3(0)) : x_;
  substeps_ = 0;
  team_substeps_ = 0;
  team_seconds_ = 0;
  waits_.clear();
  pair_terms_ = 0;
  pairs_.invalidate();
  wide_skin_ = true;
  skin_switches_ = 0;
  list_built_at_ = last_list_life_ = -1;
  std::fill(self_correction_.begin(), self_correction_.end(), vec3(0));
  for (PairScratch& scratch : pair_scratch_)
    scratch.points = scratch.linked = 0;
}

template <class T>
bool CpuSolver<T>::needsPass(int pass) const {
  switch (pass) {
    case kXpbd:
      return scene_.sim.integrator == Integrator::Xpbd;
    case kVbd:
      return scene_.sim.integrator == Integrator::Vbd;
    case kSelfCollide:
      return scene_.sim.self_collision;
    case kCollide:
      return !scene_.spheres.empty() || !scene_.planes.empty() || !scene_.meshes.empty();
    case kTether:
      return scene_.sim.tethers && tethers_.slots > 0;
    case kLimitStretch:
      return scene_.sim.stretch_passes > 0;
    case kCollideFaces:
      return !face_contacts_.empty();
    case kCollideLast:
      // Only where a pass moved the points after the collisions.
      return needsPass(kCollide) && (needsPass(kTether) || needsPass(kLimitStretch) || needsPass(kCollideFaces));
    default:
      return true;
  }
}

template <class T>
std::vector<std::string> CpuSolver<T>::passes() const {
  std::vector<std::string> out;
  for (int p = 0; p < kPassCount; ++p)
    if (needsPass(p)) out.push_back(kPassNames[p]);
  return out;
}

template <class T>
template <class F>
void CpuSolver<T>::timed(int pass, F&& f) {
  if (!pass_timing_) {
    f();
    if (teamThread() == 0) ++timings_[pass].calls;
    return;
  }
  auto start = std::chrono::steady_clock::now();
  f();  // in a team, every pass ends with a barrier: thread 0's clock covers the slowest thread
  if (teamThread() != 0) return;
  timings_[pass].ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++timings_[pass].calls;
}

// One OpenMP region for a run of substeps on a team (runTeamSubsteps): every thread runs every pass, each loop split
// between them and closed by a barrier (cpu/parallel.hpp), so the passes cost a barrier each rather than a
// fork and a join per loop. A mid-sized cloth's trial times each substep to decide the next one's way.
template <class T>
void CpuSolver<T>::step() {
  if (team_ > 1 && (!trial_ || trial_->useTeam())) {
    runTeamSubsteps(1);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  beginSubstep(true);
  runPasses();
  endSubstep(false, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (failure_) std::rethrow_exception(failure_);
}

// A frame's substeps, those the team runs in a row in one region: opening and closing it cost 1.3 us a substep, and
// its start found the other thread a little behind, which the first barrier then waited for (a forced team of two
// on CS184's files, 270 frames: 0.96-0.99 of the time in one region a frame).
template <class T>
void CpuSolver<T>::stepFrame() {
  for (int left = scene_.sim.steps_per_frame; left > 0;)
    if (team_ > 1 && (!trial_ || trial_->useTeam())) {
      left -= runTeamSubsteps(left);
    } else {
      step();
      --left;
    }
  endFrame();
}

// Up to `most` substeps on the team in one region, while the trial keeps the team; returns how many ran. Between two
// substeps, after every thread's passes, the first thread ends one and begins the next (the team's state, the
// trial's clock) while the others wait: two barriers, where a region of its own was a close and an open.
template <class T>
int CpuSolver<T>::runTeamSubsteps(int most) {
  using Clock = std::chrono::steady_clock;
  // The team's first substep moves its threads to processors of their own (spreadTeam): not before, as a
  // thread left idle in between sleeps, and waking its processor again costs as much as the move.
  if (!team_spread_) {
    spreadTeam(team_);
    team_spread_ = true;
  }
  int ran = 0;
  bool more = true;
  const auto region = Clock::now();
  auto start = region;
  beginSubstep(true);
  runOnTeam(team_, team_barrier_, record_waits_ ? &waits_ : nullptr, [&] {
    const bool first = teamThread() == 0;
    for (;;) {
      runPasses();
      teamBarrier();  // the last pass ends without one, and the substep's time is every thread's
      if (first) {
        more = endSubstep(true, std::chrono::duration<double>(Clock::now() - start).count()) && ++ran < most &&
               (!trial_ || trial_->useTeam());
        start = Clock::now();
        more = more && beginSubstep(false);
      }
      teamBarrier();
      if (!more) break;
    }
  });
  // The region's whole time, the first thread's work between two substeps included: every wait of the team lies
  // within it, even where that thread lost its processor in between (the substeps' own times leave that out)
  team_seconds_ += std::chrono::duration<double>(Clock::now() - region).count();
  if (failure_) std::rethrow_exception(failure_);
  return ran;
}

// Returns false, the substep not begun, where it would copy the arrays back (syncPositions) and may not: in a team
// the copy splits the rows between the threads, so a substep that needs it (wind's forces read x_ and v_) begins
// outside the team's region.
template <class T>
bool CpuSolver<T>::beginSubstep(bool may_copy) {
  failure_ = nullptr;
  in_passes_ = true;
  grid_integrate_ = gridIntegrates();
  if (grid_integrate_ && forcesReadArrays()) return true;
  if (positions_behind_ && !may_copy) return false;
  syncPositions();
  return true;
}

// The substep just run, `seconds` long, on the team or not: false where a pass failed (failure_), which does not
// count it.
template <class T>
bool CpuSolver<T>::endSubstep(bool team, double seconds) {
  in_passes_ = false;
  positions_behind_ = grid_integrate_;  // its stretch limit left them in the arrays
  grid_integrate_ = false;
  soa_positions_ = !failure_ && loadedAfterPasses() ? substeps_ + 1 : -1;
  // A substep that rebuilt the self-collision lists did a job of its own: the trial leaves it out of its means
  if (trial_) trial_->record(seconds, list_built_at_ != substeps_);
  if (failure_) return false;
  ++substeps_;
  team_substeps_ += team;
  return true;
}

template <class T>
void CpuSolver<T>::pointShare(int t, int team, long long& lo, long long& hi) const {
  if (grid_) {
    const long long rows = topo_.H, w = topo_.W;
    lo = evenShare(rows, t, team) * w;
    hi = evenShare(rows, t + 1, team) * w;
    return;
  }
  const auto n = (long long)x_.size();
  lo = evenShare(n, t, team);
  hi = evenShare(n, t + 1, team);
}

// Whether the last collisions run on the grid path's padded arrays, between the stretch limit's sweeps and its
// copy back (spheres and planes only, in displacement form): the grid's lanes need no gather, and the arrays then
// hold the positions the next substep's forces read.
template <class T>
bool CpuSolver<T>::collideLastOnGrid() const {
  return std::is_same_v<T, float> && grid_ && kernels_ && form_ == VerletForm::Displacement && scene_.meshes.empty() &&
         scene_.sim.stretch_scheme == StretchScheme::GaussSeidel && needsPass(kLimitStretch) &&
         needsPass(kCollideLast) && !needsPass(kCollideFaces);
}

// Whether the grid stretch limit's copy back (after the last collisions, where they run on the grid) is the last
// pass of a substep to move the points, leaving the padded arrays equal to x_ for the next substep's grid forces.
template <class T>
bool CpuSolver<T>::loadedAfterPasses() const {
  return std::is_same_v<T, float> && grid_ && scene_.sim.stretch_scheme == StretchScheme::GaussSeidel &&
         needsPass(kLimitStretch) && !needsPass(kCollideFaces) && (!needsPass(kCollideLast) || collideLastOnGrid());
}

// Whether this substep's integrate runs on the padded arrays (grid_integrate_): they hold x_ and v_ at its start,
// and between it and the grid stretch limit only self-collision (displace) and the spheres' and planes' collisions
// move the points, both of which can move them in the arrays. At 256 x 256 the copies in of the positions for
// self-collision and of the positions and displacements for the limit were 8.5% of a one-thread run, their points no
// longer in the core's cache.
template <class T>
bool CpuSolver<T>::gridIntegrates() const {
  return in_passes_ && soa_positions_ == substeps_ && keepsPointsInArrays();
}

template <class T>
bool CpuSolver<T>::keepsPointsInArrays() const {
  return std::is_same_v<T, float> && grid_ && kernels_ && form_ == VerletForm::Displacement &&
         scene_.sim.stretch_scheme == StretchScheme::GaussSeidel && needsPass(kLimitStretch) && !needsPass(kXpbd) &&
         !needsPass(kVbd) && scene_.meshes.empty() && !needsPass(kTether);
}

// Where self-collision follows integrate on the grid path and its check is split between the threads, no thread reads
// another's rows before the check's serial step ends with a barrier: each boxes the displacements of its own rows
// first (selfCollide), and the serial step reads no position. A barrier after integrate then only waited for the
// stores of the rows just integrated (selfCollision on a forced team: each thread 1.5-1.8k cycles a substep in it).
template <class T>
bool CpuSolver<T>::selfCollisionSparesBarrier() const {
  return needsPass(kSelfCollide) && pairs_.splitCheck();
}

template <class T>
std::vector<typename CpuSolver<T>::vec3>* CpuSolver<T>::integratedPositionsOut() {
  return needsPass(kSelfCollide) ? &x_ : nullptr;
}

// Whether the forces read the positions from the padded arrays (GridPath::forces), not from x_.
template <class T>
bool CpuSolver<T>::forcesReadArrays() const {
  return std::is_same_v<T, float> && grid_ && !isImplicit(scene_.sim.integrator) && !scene_.sim.wind.enabled;
}

// Whether the pass after collide is the grid stretch limit, which starts by copying its own rows in (copyIn).
template <class T>
bool CpuSolver<T>::stretchNextOnOwnRows() const {
  return grid_ && scene_.sim.stretch_scheme == StretchScheme::GaussSeidel && !needsPass(kTether) &&
         needsPass(kLimitStretch);
}

// In a team a pass ends with a barrier, except where the next pass reads only the points its own thread wrote
// in it (the same rows or points, pointShare): integrate after the grid forces (accumulateForces), the grid
// stretch limit's copy in after collide, collide_last after the stretch limit's copy back (on the grid, where it
// runs on the padded arrays, after the sweeps' last barrier, and copies its rows back), and the last pass, which
// the region's end waits for.
template <class T>
void CpuSolver<T>::runPasses() {
  timed(kForces, [&] { accumulateForces(); });
  timed(kIntegrate, [&] { integrate(); });
  if (needsPass(kXpbd)) timed(kXpbd, [&] { solveXpbd(); });
  if (needsPass(kVbd)) timed(kVbd, [&] { solveVbd(); });
  if (needsPass(kSelfCollide)) timed(kSelfCollide, [&] { selfCollide(); });
  if (needsPass(kCollide)) timed(kCollide, [&] { collide(!stretchNextOnOwnRows()); });
  if (needsPass(kTether)) timed(kTether, [&] { tether(); });
  if (needsPass(kLimitStretch)) timed(kLimitStretch, [&] { limitStretch(!needsPass(kCollideFaces)); });
  if (needsPass(kCollideFaces)) timed(kCollideFaces, [&] { collideFaces(); });
  if (needsPass(kCollideLast)) timed(kCollideLast, [&] { collideLast(); });
}

// Coordinate by coordinate, so that the compiler adds whole vectors; every point gets its correction, a zero
// one too (x + 0 turns a -0 into +0, as it always did).
template <class T>
void CpuSolver<T>::addCorrections(long long lo, long long hi) {
  T* x = &x_.data()->x;
  const T* c = &correction_.data()->x;
  for (long long k = 3 * lo; k < 3 * hi; ++k)
    x[k] += c[k];
  // x_prev stays where it was: in displacement form that is v += c.
  if (form_ == VerletForm::Displacement) {
    T* v = &v_.data()->x;
    for (long long k = 3 * lo; k < 3 * hi; ++k)
      v[k] += c[k];
  }
}

// In a team each thread adds its own points (pointShare), so that no cache line of x_ moves between cores here.
template <class T>
void CpuSolver<T>::applyCorrections() {
  const long long n = (long long)x_.size();
  if (inTeam()) {
    forPoints([&](long long lo, long long hi) { addCorrections(lo, hi); });
    return;
  }
  constexpr long long kBlock = 1024;
  parallelFor(0, (n + kBlock - 1) / kBlock, threads_,
              [&](long long b) { addCorrections(b * kBlock, std::min(n, (b + 1) * kBlock)); });
}

template <class T>
std::vector<PassTiming> CpuSolver<T>::timings() const {
  std::vector<PassTiming> out;
  for (int p = 0; p < kPassCount; ++p)
    if (needsPass(p)) out.push_back(timings_[p]);
  return out;
}

template <class T>
void CpuSolver<T>::resetTimings() {
  timings_.clear();
  for (const char* name : kPassNames)
    timings_.push_back({name, 0.0, 0});
}

template class CpuSolver<float>;
template class CpuSolver<double>;

}  // namespace drape
