#include "cpu/cpu_solver.hpp"
#include "cpu/mesh_physics.hpp"
#include "cpu/parallel.hpp"

#include "core/derived.hpp"

#include <omp.h>

#include <algorithm>
#include <limits>

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
  if (options.skip_held_pairs)
    pairs_.setRest(std::vector<vec3>(topo_.initial_positions.begin(), topo_.initial_positions.end()));
  buildFaceContacts();
  const std::size_t n = std::size_t(topo_.pointCount());
  f_.resize(n);
  correction_.resize(n);
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
  const std::size_t n = std::size_t(topo_.pointCount());
  mass_.resize(n);
  inv_mass_.resize(n);
  drag_area_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    mass_[i] = T(derived::pointMass(c, topo_, i));
    inv_mass_[i] = T(1) / mass_[i];
    drag_area_[i] = T(derived::dragArea(scene_.sim.wind.drag, c, topo_, i));
  }
  dt_ = T(scene_.sim.dt());
  keep_ = T(1.0 - c.damping / 100.0);
  // A disabled spring type exerts no force: stiffness 0 is never used, the gather skips the type.
  stiffness_.k[int(SpringType::Structural)] = T(c.ks);
  stiffness_.k[int(SpringType::Shearing)] = T(c.ks);
  stiffness_.k[int(SpringType::Bending)] = T(derived::bendingStiffness(c));
  for (int t = 0; t < kSpringTypeCount; ++t)
    alpha_tilde_.k[t] = T(derived::xpbdAlphaTilde(c, scene_.sim, SpringType(t)));
  if (scene_.sim.integrator == Integrator::Vbd && point_colouring_.start.empty())
    point_colouring_ = colourPoints(topo_);
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
  const std::size_t n = std::size_t(topo_.pointCount());
  x_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    x_[i] = vec3(topo_.initial_positions[i]);
  // At rest: zero displacement, or x_prev = x in the CS184 form.
  v_ = form_ == VerletForm::Displacement ? std::vector<vec3>(n, vec3(0)) : x_;
  substeps_ = 0;
  pairs_.invalidate();
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
  auto start = std::chrono::steady_clock::now();
  f();
  timings_[pass].ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++timings_[pass].calls;
}

template <class T>
void CpuSolver<T>::step() {
  timed(kForces, [&] { accumulateForces(); });
  timed(kIntegrate, [&] { integrate(); });
  if (needsPass(kXpbd)) timed(kXpbd, [&] { solveXpbd(); });
  if (needsPass(kVbd)) timed(kVbd, [&] { solveVbd(); });
  if (needsPass(kSelfCollide)) timed(kSelfCollide, [&] { selfCollide(); });
  if (needsPass(kCollide)) timed(kCollide, [&] { collide(); });
  if (needsPass(kTether)) timed(kTether, [&] { tether(); });
  if (needsPass(kLimitStretch)) timed(kLimitStretch, [&] { limitStretch(); });
  if (needsPass(kCollideFaces)) timed(kCollideFaces, [&] { collideFaces(); });
  if (needsPass(kCollideLast)) timed(kCollideLast, [&] { collide(); });
  ++substeps_;
}

template <class T>
typename CpuSolver<T>::vec3 CpuSolver<T>::pointNormal(int i) const {
  const auto& s = topo_.normal_stencil[std::size_t(i)];
  return physics::gridNormal(x_[s[0]], x_[s[1]], x_[s[2]], x_[s[3]]);
}

template <class T>
void CpuSolver<T>::accumulateForces() {
  const ClothSpec& cloth = scene_.cloth;
  const WindSpec& wind = scene_.sim.wind;
  // XPBD and VBD predict with the external forces only: their springs act in solveXpbd or solveVbd.
  const bool springs = !isImplicit(scene_.sim.integrator);
  const bool enabled[kSpringTypeCount] = {springs && cloth.enable_structural, springs && cloth.enable_shearing,
                                          springs && cloth.enable_bending};
  const vec3 gravity = vec3(scene_.sim.gravity);
  const T time = T(double(substeps_) * scene_.sim.dt());
  // Per point, over its adjacency in a fixed order (the GPU's). Computing each spring once and gathering
  // it from both ends gives the same bytes (springForce(b, a) is exactly -springForce(a, b)) but measured
  // 1.5x slower here: the per-spring pass scatters its reads and writes, while this loop reads one
  // point's neighbourhood, which is mostly in cache.
  const long long n = (long long)x_.size();
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    vec3 f = gravity * mass_[i];
    for (std::uint32_t e = topo_.offsets[i]; e < topo_.offsets[i + 1]; ++e) {
      const Neighbor& nb = topo_.adjacency[e];
      const int type = int(nb.type);
      if (enabled[type]) f += physics::springForce(x_[i], x_[nb.other], rest_adjacent_[e], stiffness_.k[type]);
    }
    if (wind.enabled) {
      vec3 air = physics::windVelocity(x_[i], time, vec3(wind.velocity), T(wind.turbulence), T(wind.noise_scale),
                                       T(wind.noise_speed));
      vec3 disp = form_ == VerletForm::Displacement ? v_[i] : x_[i] - v_[i];
      f += physics::windForce(pointNormal(int(i)), disp / dt_, air, drag_area_[i]);
    }
    f_[i] = f;
  });
}

template <class T>
void CpuSolver<T>::integrate() {
  const T dt2 = dt_ * dt_;
  const long long n = (long long)x_.size();
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    if (topo_.pinned[i]) {
      if (form_ == VerletForm::Displacement)
        v_[i] = vec3(0);
      else
        v_[i] = x_[i];
      return;
    }
    if (form_ == VerletForm::Displacement) {
      v_[i] = physics::integrateVerlet(v_[i], f_[i] * inv_mass_[i], dt2, keep_);
      x_[i] += v_[i];
    } else {
      vec3 next = physics::integrateVerletPrevious(x_[i], v_[i], f_[i] * inv_mass_[i], dt2, keep_);
      v_[i] = x_[i];
      x_[i] = next;
    }
  });
}

// XPBD with Small Steps (Macklin et al. 2019): many substeps of few sweeps, each spring a distance
// constraint of compliance 1/k. Gauss-Seidel over the stretch limit's colouring rather than a Jacobi
// average: a colour's springs share no point, so each sees its neighbours' latest positions (Jacobi
// needs relaxation to converge and then damps), a colour is one parallel loop here and one dispatch on
// the GPU, and the result does not depend on the thread count. The multipliers start from 0 each
// substep (Small Steps); with one sweep the stored multiplier is never read, so it is not kept.
template <class T>
void CpuSolver<T>::solveXpbd() {
  const bool displacement = form_ == VerletForm::Displacement;
  const int iterations = scene_.sim.iterations;
  if (iterations > 1) lambda_.assign(colouring_.springs.size(), T(0));
  for (int sweep = 0; sweep < iterations; ++sweep)
    sweepColours([&](std::size_t k, std::uint32_t s, const Spring& sp) {
      const bool pinned_a = topo_.pinned[sp.a] != 0, pinned_b = topo_.pinned[sp.b] != 0;
      if (pinned_a && pinned_b) return;
      const T wa = pinned_a ? T(0) : inv_mass_[sp.a];
      const T wb = pinned_b ? T(0) : inv_mass_[sp.b];
      const T lambda = iterations > 1 ? lambda_[k] : T(0);
      vec3 p;
      const T dlambda = physics::xpbdDistanceCorrection(x_[sp.a], x_[sp.b], rest_[s], wa + wb,
                                                        alpha_tilde_.k[int(sp.type)], lambda, p);
      if (iterations > 1) lambda_[k] = lambda + dlambda;
      if (!pinned_a) {
        const vec3 ca = (-wa) * p;
        x_[sp.a] += ca;
        if (displacement) v_[sp.a] += ca;  // x_prev stays: v = x - x_prev is the constrained displacement
      }
      if (!pinned_b) {
        const vec3 cb = wb * p;
        x_[sp.b] += cb;
        if (displacement) v_[sp.b] += cb;
      }
    });
}

// Vertex Block Descent (Chen et al. 2024) on the springs: each sweep moves every free point, colour after
// colour, by a Newton step on its share of the implicit-Euler energy with its neighbours held
// (physics::vbdAddSpring, vbdStep). Points of a colour share no spring, so a colour is one parallel loop
// here and one dispatch on the GPU, and the result does not depend on the thread count. The sweeps start
// from the prediction y = x + keep v + a dt^2 (integrate): a point's own position changes only when its
// colour runs, so in the first sweep x = y and the inertia's gradient is exactly 0; later sweeps need y,
// which the first keeps. CS184's damping is in the prediction, as for XPBD.
template <class T>
void CpuSolver<T>::solveVbd() {
  const ClothSpec& cloth = scene_.cloth;
  const bool enabled[kSpringTypeCount] = {cloth.enable_structural, cloth.enable_shearing, cloth.enable_bending};
  const bool displacement = form_ == VerletForm::Displacement;
  const int iterations = scene_.sim.iterations;
  const T dt2 = dt_ * dt_;
  if (iterations > 1) inertia_target_.resize(x_.size());
  for (int sweep = 0; sweep < iterations; ++sweep)
    for (int colour = 0; colour < point_colouring_.colourCount(); ++colour) {
      const long long first = point_colouring_.start[std::size_t(colour)];
      const long long last = point_colouring_.start[std::size_t(colour) + 1];
      parallelFor(first, last, threads_, [&](long long k) {
        const std::size_t i = point_colouring_.points[std::size_t(k)];
        if (topo_.pinned[i]) return;
        const vec3 x = x_[i];
        const T inertia = T(1) / (inv_mass_[i] * dt2);  // m / dt^2, from the inverse mass the GPU holds
        vec3 f(0), h_off(0);
        vec3 h_diag(inertia);
        if (sweep > 0) f = (-inertia) * (x - inertia_target_[i]);
        for (std::uint32_t e = topo_.offsets[i]; e < topo_.offsets[i + 1]; ++e) {
          const Neighbor& nb = topo_.adjacency[e];
          const int type = int(nb.type);
          if (enabled[type])
            physics::vbdAddSpring(x, x_[nb.other], rest_adjacent_[e], stiffness_.k[type], f, h_diag, h_off);
        }
        if (sweep == 0 && iterations > 1) inertia_target_[i] = x;
        const vec3 dx = physics::vbdStep(f, h_diag, h_off);
        x_[i] = x + dx;
        if (displacement) v_[i] += dx;  // x_prev stays: v = x - x_prev is the solved displacement
      });
    }
}

template <class T>
template <class F>
void CpuSolver<T>::sweepColours(F&& f) {
  const ClothSpec& cloth = scene_.cloth;
  const bool enabled[kSpringTypeCount] = {cloth.enable_structural, cloth.enable_shearing, cloth.enable_bending};
  for (int colour = 0; colour < colouring_.colourCount(); ++colour) {
    const long long first = colouring_.start[std::size_t(colour)], last = colouring_.start[std::size_t(colour) + 1];
    parallelFor(first, last, threads_, [&](long long k) {
      const std::uint32_t s = colouring_.springs[std::size_t(k)];
      const Spring& sp = topo_.springs[s];
      if (enabled[int(sp.type)]) f(std::size_t(k), s, sp);
    });
  }
}

// Each free point, slot after slot, back within the stretch limit of its anchors. The anchors are pinned
// and never move here, so the points are independent and the loop is parallel.
template <class T>
void CpuSolver<T>::tether() {
  const bool displacement = form_ == VerletForm::Displacement;
  const std::size_t slots = std::size_t(tethers_.slots);
  const T limit = T(scene_.sim.stretch_limit);
  const long long n = (long long)x_.size();
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    if (topo_.pinned[i]) return;
    for (std::size_t s = 0; s < slots; ++s) {
      const std::uint32_t anchor = tethers_.anchor[i * slots + s];
      if (anchor == kNoAnchor) break;
      const vec3 c = physics::tetherCorrection(x_[i], x_[anchor], tether_rest_[i * slots + s], limit);
      x_[i] += c;
      if (displacement) v_[i] += c;  // x_prev stays: v = x - x_prev
    }
  });
}

template <class T>
void CpuSolver<T>::applyCorrections() {
  const long long n = (long long)x_.size();
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    x_[i] += correction_[i];
    // x_prev stays where it was: in displacement form that is v += c.
    if (form_ == VerletForm::Displacement) v_[i] += correction_[i];
  });
}

template <class T>
void CpuSolver<T>::selfCollide() {
  const T thickness = T(scene_.cloth.thickness);
  const T range = T(2) * thickness;
  // The skin is a share of the contact distance, or of the spacing where the cloth is finer than that: a
  // skin as thick as the contact distance holds a ring of points that never touch (97 a point at 256^2
  // with CS184's thickness, 19.5 with the spacing's). The lists' bytes do not depend on it.
  pairs_.configure(range, T(pair_margin_) * std::min(range, T(shortest_spring_)));
  pairs_.update(x_, threads_);
  // The cells of a grid of cell size `range` fix the order of each point's sum (see forEachOrderedPair).
  const T inv_range = T(1) / range;
  const long long n = (long long)x_.size();
  const T steps = T(scene_.sim.steps_per_frame);
  // Jacobi: every correction is computed from the positions before the pass, so the result does not
  // depend on the order points are visited (nor, on the GPU, on thread order).
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    vec3 sum(0);
    int count = 0;
    if (!topo_.pinned[i]) {
      forEachOrderedPair(pairs_, i, x_, thickness, inv_range, [&](vec3 c) {
        sum += c;
        ++count;
      });
    }
    correction_[i] = count > 0 ? sum / (T(count) * steps) : vec3(0);
  });
  applyCorrections();
}

template <class T>
void CpuSolver<T>::collide() {
  const long long n = (long long)x_.size();
  parallelFor(0, n, threads_, [&](long long k) {
    const std::size_t i = std::size_t(k);
    if (topo_.pinned[i]) return;
    vec3 x = x_[i];
    vec3 v = form_ == VerletForm::Displacement ? v_[i] : x_[i] - v_[i];
    vec3 c;
    // Objects in turn, each seeing the result of the previous one (CS184 order: spheres, then planes).
    for (const SphereSpec& s : scene_.spheres)
      if (physics::collideSphere(x, v, vec3(s.origin), T(s.radius), T(s.friction), c)) {
        x += c;
        v += c;
      }
    for (const PlaneSpec& p : scene_.planes)
      if (physics::collidePlane(x, v, vec3(p.point), vec3(p.normal), T(p.friction), c)) {
        x += c;
        v += c;
      }
    for (const MeshSpec& m : scene_.meshes)
      if (physics::collideField(x, v, m.mesh->field, physics::meshOffset(T(meshThickness(scene_.cloth, m))),
                                T(m.friction), c)) {
        x += c;
        v += c;
      }
    x_[i] = x;
    if (form_ == VerletForm::Displacement) v_[i] = v;
  });
}

template <class T>
void CpuSolver<T>::limitStretch() {
  if (scene_.sim.stretch_scheme == StretchScheme::GaussSeidel)
    limitStretchColoured();
  else
    limitStretchJacobi();
}

// Provot (1995) as CS184 applies it, one spring after another, each moving its ends at once, but in
// colour order: the springs of a colour share no point, so they run in parallel and the result does not
// depend on the thread count. Holds the limit as tightly as CS184's sequential pass (the averaged
// Jacobi pass lets pinned2 reach 17% strain where this holds about 12.5%).
template <class T>
void CpuSolver<T>::limitStretchColoured() {
  const T limit = T(scene_.sim.stretch_limit);
  const bool displacement = form_ == VerletForm::Displacement;
  for (int pass = 0; pass < scene_.sim.stretch_passes; ++pass)
    sweepColours([&](std::size_t, std::uint32_t s, const Spring& sp) {
      const bool pinned_a = topo_.pinned[sp.a] != 0, pinned_b = topo_.pinned[sp.b] != 0;
      const T share_a = physics::stretchShare<T>(pinned_a, pinned_b);
      const T share_b = physics::stretchShare<T>(pinned_b, pinned_a);
      const vec3 ca = physics::stretchCorrection(x_[sp.a], x_[sp.b], rest_[s], limit, share_a);
      const vec3 cb =
          share_a == share_b ? -ca : physics::stretchCorrection(x_[sp.b], x_[sp.a], rest_[s], limit, share_b);
      if (!pinned_a) {
        x_[sp.a] += ca;
        if (displacement) v_[sp.a] += ca;  // x_prev stays where it was
      }
      if (!pinned_b) {
        x_[sp.b] += cb;
        if (displacement) v_[sp.b] += cb;
      }
    });
}

template <class T>
void CpuSolver<T>::limitStretchJacobi() {
  const ClothSpec& cloth = scene_.cloth;
  const bool enabled[kSpringTypeCount] = {cloth.enable_structural, cloth.enable_shearing, cloth.enable_bending};
  const T limit = T(scene_.sim.stretch_limit);
  const long long n = (long long)x_.size();
  for (int pass = 0; pass < scene_.sim.stretch_passes; ++pass) {
    // Provot (1995) per spring, gathered per vertex (Jacobi) so the GPU can do the same with no atomics.
    parallelFor(0, n, threads_, [&](long long p) {
      const std::size_t i = std::size_t(p);
      vec3 sum(0);
      int violated = 0;
      if (!topo_.pinned[i]) {
        for (std::uint32_t e = topo_.offsets[i]; e < topo_.offsets[i + 1]; ++e) {
          const Neighbor& nb = topo_.adjacency[e];
          if (!enabled[int(nb.type)]) continue;
          const T share = physics::stretchShare<T>(false, topo_.pinned[nb.other] != 0);
          const vec3 c = physics::stretchCorrection(x_[i], x_[nb.other], rest_adjacent_[e], limit, share);
          if (c != vec3(0)) {
            sum += c;
            ++violated;
          }
        }
      }
      // Averaged, not summed: the springs of a hanging point mostly pull the same way, and their summed
      // Jacobi corrections overshoot and diverge (measured: strain 9.6 -> 1e52 over 64 passes).
      correction_[i] = violated > 0 ? sum / T(violated) : vec3(0);
    });
    applyCorrections();
  }
}

template <class T>
void CpuSolver<T>::setState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v) {
  pairs_.invalidate();
  for (std::size_t i = 0; i < x_.size(); ++i) {
    x_[i] = vec3(x[i]);
    v_[i] = form_ == VerletForm::Displacement ? vec3(v[i]) : vec3(x[i] - v[i]);
  }
}

template <class T>
std::vector<glm::dvec3> CpuSolver<T>::readPositions() {
  return std::vector<glm::dvec3>(x_.begin(), x_.end());
}

template <class T>
std::vector<glm::dvec3> CpuSolver<T>::readDisplacements() {
  std::vector<glm::dvec3> out(x_.size());
  for (std::size_t i = 0; i < x_.size(); ++i)
    out[i] = form_ == VerletForm::Displacement ? glm::dvec3(v_[i]) : glm::dvec3(x_[i]) - glm::dvec3(v_[i]);
  return out;
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
