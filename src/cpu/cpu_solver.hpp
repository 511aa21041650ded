// CPU reference solver: the passes of docs/design.md section 2, in that order, with the same Jacobi semantics
// as the GPU, templated on float (to compare with the GPU) and double (the accuracy reference).
#pragma once

#include "core/colouring.hpp"
#include "core/derived.hpp"
#include "core/health.hpp"
#include "core/mesh_features.hpp"
#include "core/solver.hpp"
#include "core/tethers.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/grid_path.hpp"
#include "cpu/parallel.hpp"
#include "cpu/physics.hpp"
#include "cpu/team_trial.hpp"
#include "cpu/wait_log.hpp"

#include <chrono>
#include <exception>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace drape {

// A barrier costs well under a microsecond when both threads have a core and up to a time slice when other
// load on the machine has descheduled one (docs/results/cpu_speed.md). From kTeamMinPoints a substep's loops
// are long enough to pay for that under load too (the size from which loops forked a team of their own,
// kParallelItems), and the cloth always gets a team. From kTeamTrialMinPoints up to there, whether a team
// pays depends on the machine's load (on this 2-core machine a team ran a 50x50 substep 1.3x faster when it
// was quiet, 12x slower when it was busy): the solver times both ways as it runs (cpu/team_trial.hpp).
inline constexpr long long kTeamMinPoints = 32768;
inline constexpr long long kTeamTrialMinPoints = 1024;

// How Verlet keeps the previous position: the displacement v = x - x_prev (default, precise) or
// x_prev itself (CS184's form, kept to measure the round-off it costs).
enum class VerletForm { Displacement, PreviousPosition };

struct CpuSolverOptions {
  VerletForm form = VerletForm::Displacement;
  int threads = 0;  // OpenMP threads for the per-point loops; 0 = every core. Any count gives the same bytes.
  // list skin / min(2*thickness, 4/3 of the shortest structural spring at rest) (derived::pairSkin); 0 rebuilds
  // the list every substep
  double pair_margin = kDefaultPairMargin;
  // The skin follows the cloth: pair_margin while its lists wear out, 2/3 of it once a list has lasted
  // kSettledSubsteps (a still cloth gains nothing from the wide skin's ring on the stencil), back when a narrow
  // list lasts under kBusySubsteps. The same bytes either way; false keeps pair_margin.
  bool adaptive_skin = true;
  // Self-collision skips the pairs closer than 2*thickness at rest (physics::heldAtRest); false collides them
  // too, as CS184 does, to measure what skipping changes.
  bool skip_held_pairs = true;
  // With skip_held_pairs on a grid cloth: the pairs at the grid offsets just beyond the contact distance at rest
  // are tested by offset every substep instead of listed (CollisionPairs::setGrid); false lists them, to
  // compare. The same bytes either way.
  bool pair_stencil = true;
  // With the stencil on a float grid: between the lists' builds, the stencil's pairs that the build's distances and
  // the check's boxes of the displacements show out of range are not tested (CollisionPairs::stencilTiles); false
  // tests every one, to compare. The same bytes either way.
  bool stencil_squares = true;
  // Float grid cloths: forces and the Gauss-Seidel stretch limit by the SIMD grid kernels (cpu/grid_path.hpp),
  // the same bytes as the general gathers; false runs the general path (the tests compare the two).
  bool grid_path = true;
  GridIsa grid_isa = GridIsa::Auto;  // the grid kernels' instruction set; Auto: the widest the CPU has
  // The fewest points for which step() always runs its passes on a team of `threads` (one OpenMP region a
  // substep, a barrier between passes). Tests set 0 to run a small cloth on a team. Measured:
  // docs/results/cpu_speed.md.
  long long team_min_points = kTeamMinPoints;
  // From this many points up to team_min_points, each substep runs on the team or on one thread, whichever
  // the solver measured faster (TeamTrial); below, one thread.
  long long team_trial_min_points = kTeamTrialMinPoints;
  // Keep what each selfCollide added to each point (selfCorrections), for the tests that look at it: a write a
  // moved point and its clearing at the next pass, which nothing else reads (pinned2 at 256^2 on one thread: 0.99
  // of the run's time without them).
  bool keep_self_corrections = false;
  // The wall clock around each pass, for timings() (bench, the viewer); false only counts the passes, as
  // `drape simulate` runs them: two clock reads a pass on every thread of a team.
  bool pass_timing = true;
  // Time each wait of a team's threads for each other (barriers, neighbours' progress) into waits(), by the line
  // that waits: two clock reads a wait, off unless asked (`drape simulate --waits`).
  bool record_waits = false;
};

template <class T>
class CpuSolver final : public Solver {
 public:
  using vec3 = glm::vec<3, T>;

  explicit CpuSolver(Scene scene, CpuSolverOptions options = {});
  CpuSolver(Scene scene, VerletForm form) : CpuSolver(std::move(scene), CpuSolverOptions{.form = form}) {}

  std::string name() const override;
  const Scene& scene() const override { return scene_; }
  const Topology& topology() const override { return topo_; }

  // step() is this list of passes; each is public so tests can run and compare them one by one.
  void step() override;
  void stepFrame() override;  // a run of substeps on the team in one region (runTeamSubsteps)
  void accumulateForces();    // gravity + springs + wind -> forces_ (XPBD: gravity + wind, springs are constraints)
  void integrate();           // Verlet, pinned points stay (XPBD: the prediction x* = x + keep v + a dt^2)
  void solveXpbd();           // XPBD: sim.iterations Gauss-Seidel sweeps of the springs as distance constraints
  void solveVbd();            // VBD: sim.iterations Gauss-Seidel sweeps of per-point Newton steps, colour by colour
  void selfCollide();         // candidate lists, Jacobi, averaged, / steps_per_frame
  void collide(bool wait = true);       // each sphere, then each plane, then each mesh's field; wait: see runPasses
  void tether();                        // long-range attachments to the pins (core/tethers.hpp), when the scene asks
  void limitStretch(bool wait = true);  // Provot, sim.stretch_passes passes (Gauss-Seidel over colours, or Jacobi)
  void collideFaces();  // the cloth's edges and triangles off the meshes' sharp edges and corners, Jacobi
  // collide() again, last: whatever moved the points after the collisions, none ends inside a collider.

  void reset() override;
  void setParams(const ClothSpec& cloth, const SimParams& sim) override;
  std::vector<glm::dvec3> readPositions() override;
  Health health() override;
  std::vector<glm::dvec3> readDisplacements() override;
  long long substeps() const override { return substeps_; }
  std::vector<std::string> passes() const override;
  std::vector<PassTiming> timings() const override;
  void resetTimings() override;

  // Direct state access for tests and tools.
  const std::vector<vec3>& positions() const {
    syncPositions();
    return x_;
  }
  const std::vector<vec3>& displacements() const {
    syncPositions();
    return v_;
  }
  const std::vector<vec3>& forces() const { return f_; }
  void setState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v);
  T mass() const { return mass_.front(); }  // point 0's (every grid point has the same)
  const std::vector<T>& masses() const { return mass_; }
  int threads() const override { return threads_; }
  const CollisionPairs<T>& collisionPairs() const { return pairs_; }
  const Tethers& tethers() const { return tethers_; }
  const PointColouring& pointColouring() const { return point_colouring_; }
  const FaceAdjacency& faceAdjacency() const { return faces_; }
  // The grid kernels' instruction set ("sse2", "avx2", "avx512"), or "" where the general path runs.
  std::string gridKernels() const { return grid_ ? grid_->kernels().name : ""; }
  int teamThreads() const { return team_; }                  // threads step() runs its passes on when on a team
  long long teamSubsteps() const { return team_substeps_; }  // substeps run on the team since reset()
  double teamSeconds() const { return team_seconds_; }       // the wall-clock time of the team regions that ran them
  const WaitLog* waits() const { return record_waits_ ? &waits_ : nullptr; }  // since reset(); null unless recorded
  const TeamTrial* teamTrial() const { return trial_ ? &*trial_ : nullptr; }  // where a trial decides
  long long pairTerms() const { return pair_terms_; }  // self-collision: pairs in range summed, both ends
  // Self-collision's shares of the points in a team (thread t: [bounds[t], bounds[t + 1])), to sum their terms
  // and to find their pairs, moved towards equal times after each substep; fixPairShares sets them and keeps them
  // (a test's uneven split; finding as summing where `find` is empty).
  const std::vector<long long>& pairShares() const { return pair_bounds_; }
  const std::vector<long long>& findShares() const { return find_bounds_; }
  void fixPairShares(std::vector<long long> sums, std::vector<long long> find = {});
  // The grid path's rows of the stretch limit's colours per thread of a team (GridPath::colourRows; empty without
  // a grid path or a team), and a test's fixed split of them.
  std::vector<long long> colourRows() const { return grid_ ? grid_->colourRows() : std::vector<long long>{}; }
  void fixColourRows(std::vector<long long> rows) {
    if (grid_) grid_->fixColourRows(std::move(rows));
  }
  // Whether the substeps keep the points in the grid path's padded arrays from one to the next (gridIntegrates),
  // integrate then running in the forces' sweep (GridPath::forcesAndIntegrate): what the scene and options say; a
  // substep after a state set or a reset copies them in first.
  bool keepsPointsInArrays() const;
  // The last substep left the points in the grid path's padded arrays, to be copied back when read (syncPositions)
  bool positionsInArrays() const { return positions_behind_; }
  bool wideSkin() const { return wide_skin_; }  // the lists' skin now: pair_margin (else 2/3 of it)
  int skinSwitches() const { return skin_switches_; }
  // What the last selfCollide added to each point (0 where it added nothing): its bits, which a position rounds
  // away. Kept only with CpuSolverOptions::keep_self_corrections (else empty).
  const std::vector<vec3>& selfCorrections() const { return self_correction_; }

 private:
  struct Stiffness {
    T k[kSpringTypeCount];
  };
  void refreshDerived();
  // x_i += c; in displacement form v_i += c too, so that x_prev stays where it was (a constraint moves the point,
  // not its past). Between a grid integrate and the stretch limit, which copies the arrays back, in the padded
  // arrays alone.
  void displace(std::size_t i, vec3 c) {
    if constexpr (std::is_same_v<T, float>)
      if (grid_integrate_) {
        grid_->displace(i, c);
        return;
      }
    x_[i] += c;
    if (form_ == VerletForm::Displacement) v_[i] += c;
  }
  void applyCorrections();                          // x += c, and v += c so that x_prev stays put
  void addCorrections(long long lo, long long hi);  // applyCorrections on points [lo, hi)
  void limitStretchColoured(bool wait);
  void limitStretchJacobi();
  void buildFaceContacts();  // the meshes' features, their grids and the cloth's face adjacency
  // One Gauss-Seidel sweep over the enabled springs, colour after colour, each colour one parallel loop:
  // f(k, s, spring) with k the spring's slot in the colouring and s its index.
  template <class F>
  void sweepColours(F&& f);
  vec3 pointNormal(int i) const;
  void collidePoint(std::size_t i);  // collide()'s work on one point
  CollideArgs collideArgs();         // float: collide()'s spheres and planes for the kernels
  bool collideLastOnGrid() const;
  void collideLast();
  // Points [lo, hi) of thread t of a team of `team`: on a grid cloth whole rows, those GridPath's passes give it;
  // elsewhere teamShare's. Every point pass of a substep splits by it (forPoints), so a pass that reads only the
  // points its own thread wrote in the pass before needs no barrier between them (runPasses).
  void pointShare(int t, int team, long long& lo, long long& hi) const;
  bool stretchNextOnOwnRows() const;
  // body(lo, hi) on this thread's points in a team (pointShare), then a barrier unless !wait; outside a team, all
  // of them at once.
  template <class F>
  void forPoints(F&& body, bool wait = true);
  // point(p) for every point: in a team by forPoints, outside one by parallelFor (which forks for long loops).
  template <class F>
  void forEachPoint(F&& point, bool wait = true);
  // selfCollide()'s sum, a pair at a time (cpu_solver_self_collision.cpp)
  struct PairScratch;
  // far: the list's far entries too (CollisionPairs::farNeeded)
  void findPairHits(long long lo, long long hi, bool stencil, T thickness, T inv_range, bool far, PairScratch& mine);
  long long sumPairTerms(int thread, T steps, PairScratch& mine);
  void clearSelfCorrections(PairScratch& scratch);  // self_correction_ back to 0 at the points it moved
  bool needsPass(int pass) const;
  template <class F>
  void timed(int pass, F&& f);
  void runPasses();
  bool gridForces() const;

  Scene scene_;
  Topology topo_;
  VerletForm form_;
  int threads_ = 1;
  int team_ = 1;                            // threads a team has (team_min_points, team_trial_min_points)
  bool team_spread_ = false;                // spreadTeam done (the team's first substep)
  TeamBarrier team_barrier_;                // the team's barrier (cpu/parallel.hpp): not OpenMP's
  std::optional<TeamTrial> trial_;          // mid-sized cloths: whether this substep runs on the team
  std::optional<GridPath> grid_;            // float grid cloths, unless the options turn it off (copyable)
  const GridKernels* kernels_ = nullptr;    // float: the SIMD integrate (any cloth)
  std::vector<float> inv_mass3_, pinned3_;  // float: per coordinate, its point's 1/m and pin mask
  std::vector<float> pinned1_;              // float: per point, its pin mask
  std::exception_ptr failure_;              // thrown inside step()'s team, rethrown once it is over
  double pair_margin_ = kDefaultPairMargin;
  // The adaptive skin (CpuSolverOptions::adaptive_skin): the substep the lists were last built at, how many
  // substeps the list before them lasted (-1: unknown)
  static constexpr long long kSettledSubsteps = 256, kBusySubsteps = 32;
  bool adaptive_skin_ = true, wide_skin_ = true;
  bool pass_timing_ = true;
  int skin_switches_ = 0;
  long long list_built_at_ = -1, last_list_life_ = -1;
  double shortest_spring_ = 0;  // m, the shortest structural spring's rest length
  std::vector<vec3> x_, v_, f_;
  std::vector<vec3> correction_;  // the Jacobi stretch limit's and collideFaces': every point's, then added
  // selfCollide's: nonzero only at the points its last pass moved (each scratch's `touched`), zeroed there before
  // the next pass writes its own
  std::vector<vec3> self_correction_;
  std::vector<T> rest_;           // per spring, in T
  std::vector<T> rest_adjacent_;  // per adjacency entry, in T
  CollisionPairs<T> pairs_;
  // Per point: its stencil partners in range this substep (stencilMask), where no grid path finds the stencil's pairs
  std::vector<StencilMask> near_;
  // selfCollide(): a term point i gets from its pair with j, as found by another thread than the one that sums i's
  // terms (routed to it), and as the summing thread links it to i's other terms.
  struct FoundTerm {
    std::uint32_t i, j;
    int order;  // cellOrder(cell of i, cell of j)
    vec3 c;
  };
  struct PairTerm {
    std::uint64_t key;  // its place in the point's sum: termKey(cell order, partner)
    std::int32_t next;  // the point's next term in the same scratch, or -1
    vec3 c;
  };
  static std::uint64_t termKey(int order, std::uint32_t j) { return std::uint64_t(std::uint32_t(order)) << 32 | j; }
  struct alignas(64) PairScratch {            // one per thread of the team, on cache lines of their own
    std::vector<std::vector<FoundTerm>> to;   // per thread of the team: the terms found here for its points,
    std::vector<std::size_t> sent;            // this substep's the first sent[t] of to[t] (only grown)
    std::vector<PairTermOut> hits;            // the pairs in range with their terms (GridKernels::pairTerms)
    std::vector<std::uint32_t> lower, upper;  // the stencil's pairs in range, for pairTerms
    std::size_t stencil_pairs = 0;            // how many (GridPath::stencilPairs)
    std::vector<PairTerm> terms;              // the first `linked`, linked by point from first_term_ (linkTerm)
    std::vector<std::uint32_t> touched;       // the first `points` are the points with terms, which the sums moved
    std::size_t points = 0, linked = 0;
    std::vector<std::int32_t> chain;
    std::exception_ptr failure;
    long long summed = 0;  // terms summed this substep
  };
  std::vector<PairScratch> pair_scratch_;  // only grown: a team's, kept while the trial runs a probe on one thread
  int pair_team_ = 1;                      // how many of them this substep's threads use
  std::span<PairScratch> teamScratch() { return {pair_scratch_.data(), std::size_t(pair_team_)}; }
  // In a team, thread t sums the terms of points [pair_bounds_[t], pair_bounds_[t + 1]) and finds the pairs whose
  // lower ends are in [find_bounds_[t], find_bounds_[t + 1]) (on a grid path, whole rows of it), or in a substep
  // that built the lists in [built_find_bounds_[t], ...) (on a grid path, whole rows of the stencil's squares: that
  // substep records them, testing every offset of every point, so its work lies elsewhere): even shares at first,
  // then each moved towards equal times (balancePairShares). Finding and summing are apart, a barrier between, and
  // where a cloth folds onto itself one end of its pairs finds them all.
  std::vector<long long> pair_bounds_, find_bounds_, built_find_bounds_;
  bool pair_shares_fixed_ = false;  // fixPairShares
  // Per thread of the team: this substep's seconds for its sums (pair_) and for its stencil and search (find_),
  // and its seconds a point of each share smoothed over substeps (balanceShares; -1: none yet)
  std::vector<double> pair_seconds_, pair_per_point_, find_seconds_, find_per_point_, built_find_per_point_;
  int pairOwner(std::uint32_t j) const {
    int t = 0;
    while ((long long)j >= pair_bounds_[std::size_t(t) + 1])
      ++t;
    return t;
  }
  void balancePairShares(bool built);
  std::vector<std::int32_t> first_term_;  // per point: its first term in its thread's scratch, or -1
  // Point i's term from j onto the front of i's in `to` (sized for it); a point's first term lists it in touched.
  void linkTerm(PairScratch& to, std::uint32_t i, std::uint32_t j, int order, vec3 c) {
    std::int32_t& first = first_term_[i];
    to.touched[to.points] = i;
    to.points += first < 0;
    to.terms[to.linked] = {termKey(order, j), first, c};
    first = std::int32_t(to.linked++);
  }
  void unlinkTerms(PairScratch& scratch) {  // first_term_ back to -1 at its points, as a failed substep leaves it
    for (const std::uint32_t i : std::span(scratch.touched.data(), scratch.points))
      first_term_[i] = -1;
  }
  SpringColouring colouring_;
  Tethers tethers_;  // empty until the scene asks for tethers
  std::vector<T> tether_rest_;
  std::vector<T> mass_, inv_mass_, drag_area_;  // per point (derived::pointMass, dragArea)
  T dt_ = 0, keep_ = 1;
  Stiffness stiffness_{};
  Stiffness alpha_tilde_{};             // XPBD: compliance / dt^2 per spring type
  std::vector<float> collide_objects_;  // collide()'s CollideArgs: the spheres, then the planes
  std::vector<T> lambda_;               // XPBD: per coloured spring, the multiplier summed over this substep's sweeps
  PointColouring point_colouring_;      // VBD: built the first time the scene asks for VBD
  std::vector<vec3> inertia_target_;    // VBD with iterations > 1: the prediction y, kept by the first sweep
  // Per mesh obstacle, for collideFaces: its sharp features in T and the grid they are looked up by.
  struct FeatureEdgeT {
    vec3 a, b, n1, n2;
    vec3 mid;  // (a + b) / 2 and |b - a| / 2: a sphere around it, to pass over the far ones quickly
    T half;
  };
  struct FeatureCornerT {
    vec3 p, normal;
  };
  struct FaceContacts {
    std::vector<FeatureEdgeT> edges;
    std::vector<FeatureCornerT> corners;
    FeatureGrid grid;
    T thickness = 0;
  };
  std::vector<FaceContacts> face_contacts_;  // one per mesh, in scene order; empty if no mesh has features
  FaceAdjacency faces_;
  long long substeps_ = 0;
  long long team_substeps_ = 0;
  double team_seconds_ = 0;
  bool record_waits_ = false;
  WaitLog waits_;
  long long pair_terms_ = 0;
  std::vector<PassTiming> timings_;
  QuickHealth quick_health_;  // float: health()'s quick look (refreshDerived)
  // The grid path's padded arrays hold x_ as it is at the start of substep soa_positions_ (-1: not known), so
  // that the forces need not copy the positions in: after a substep whose last pass to move the points was the
  // grid stretch limit's copy back (loadedAfterPasses). Only endSubstep sets it, on one thread; every other way
  // the points move (a pass run on its own, setState, reset) clears it (positionsMoved).
  long long soa_positions_ = -1;
  bool in_passes_ = false;  // a substep is running its passes, which keep soa_positions_ themselves
  // This substep runs integrate on the padded arrays (they hold x_ and v_ at its start) and every pass after it
  // moves the points there (self-collision, the spheres' and planes' collisions, the stretch limit), so that none
  // copies them in (gridIntegrates). Set by beginSubstep, on one thread.
  bool grid_integrate_ = false;
  bool gridIntegrates() const;
  int runTeamSubsteps(int most);
  bool beginSubstep(bool may_copy);            // a substep's state before its passes, by one thread
  bool endSubstep(bool team, double seconds);  // and after them
  // Where integrate on the arrays also writes its positions: x_ where self-collision reads them there (its search and
  // builds), else nowhere. x_ and v_ are then behind the arrays (positions_behind_) until syncPositions: no pass of
  // the substep reads them, and writing every point's twice was a third of integrate's stores.
  std::vector<vec3>* integratedPositionsOut();
  bool selfCollisionSparesBarrier() const;  // integrate on the grid path ends without a barrier
  bool forcesReadArrays() const;
  void positionsMoved() {
    if (in_passes_) return;
    syncPositions();  // a pass run on its own reads x_ and v_
    soa_positions_ = -1;
  }
  // A substep that integrates on the padded arrays ends with the points there, not in x_ and v_: the next one reads
  // them there (at 256 x 256 the copy back was 5% of a one-thread run). Anything else that reads x_ or v_ copies
  // them back first (syncPositions): the accessors, the passes run on their own, a substep that does not.
  mutable bool positions_behind_ = false;
  void syncPositions() const;
  bool loadedAfterPasses() const;
};

extern template class CpuSolver<float>;
extern template class CpuSolver<double>;

}  // namespace drape
