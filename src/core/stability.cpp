#include "core/stability.hpp"

#include "core/cloth_mesh.hpp"
#include "core/derived.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace drape {

namespace {

// How many of the two neighbours at grid offset +-d point x has along an axis of n points.
int neighboursAt(int x, int n, int d) {
  return (x - d >= 0 ? 1 : 0) + (x + d <= n - 1 ? 1 : 0);
}

// core has no fmt dependency; these messages only format doubles.
template <class... Args>
std::string format(const char* pattern, Args... args) {
  char buf[256];
  std::snprintf(buf, sizeof buf, pattern, args...);
  return buf;
}

}  // namespace

double maxStiffnessSum(const ClothSpec& cloth) {
  const int W = cloth.num_width_points, H = cloth.num_height_points;
  const double k_straight = cloth.enable_structural ? cloth.ks : 0.0;
  const double k_diagonal = cloth.enable_shearing ? cloth.ks : 0.0;
  const double k_bending = cloth.enable_bending ? derived::bendingStiffness(cloth) : 0.0;
  // A point's springs depend only on its distance to the nearest edge along each axis, and every
  // distance beyond 2 looks like 2, so x, y in 0..2 cover every kind of point (small grids have fewer).
  double best = 0.0;
  for (int x = 0; x <= std::min(W - 1, 2); ++x)
    for (int y = 0; y <= std::min(H - 1, 2); ++y) {
      const int sx = neighboursAt(x, W, 1), sy = neighboursAt(y, H, 1);
      const double sum =
          k_straight * (sx + sy) + k_diagonal * sx * sy + k_bending * (neighboursAt(x, W, 2) + neighboursAt(y, H, 2));
      best = std::max(best, sum);
    }
  return best;
}

// k_sum / m at the point where it is largest (1/s^2). A mesh's points differ in both, so every point counts.
double maxStiffnessOverMass(const ClothSpec& cloth) {
  if (cloth.isGrid()) {
    const double k = maxStiffnessSum(cloth), m = derived::pointMass(cloth);
    if (k <= 0.0) return 0.0;
    return m <= 0.0 ? INFINITY : k / m;
  }
  const ClothMesh& mesh = *cloth.mesh;
  std::vector<double> k(mesh.positions.size(), 0.0);
  for (const MeshSpring& s : mesh.springs)
    if (cloth.springEnabled(s.type)) {
      k[s.a] += derived::springStiffness(cloth, s.type);
      k[s.b] += derived::springStiffness(cloth, s.type);
    }
  double worst = 0.0;
  for (std::size_t i = 0; i < k.size(); ++i)
    if (k[i] > 0.0) worst = std::max(worst, k[i] / (cloth.density * mesh.area[i]));
  return worst;
}

double stabilityNumber(const Scene& scene) {
  const double km = maxStiffnessOverMass(scene.cloth);
  if (km <= 0.0) return 0.0;
  return scene.sim.dt() * std::sqrt(km);
}

double stabilityLimit(double damping_percent) {
  const double keep = std::clamp(1.0 - damping_percent / 100.0, 0.0, 1.0);
  return std::sqrt(1.0 + keep);
}

StabilityCheck checkStability(const Scene& scene) {
  StabilityCheck c;
  c.number = stabilityNumber(scene);
  c.limit = stabilityLimit(scene.cloth.damping);
  if (isImplicit(scene.sim.integrator)) {
    // The bound is Verlet's: XPBD and VBD solve the springs implicitly, a step bounded at any dt.
    c.ok = true;
    c.message = format("%s: no explicit-integration bound (Verlet's dt*sqrt(k/m) would be %.3g, limit %.3g)",
                       integratorName(scene.sim.integrator), c.number, c.limit);
    return c;
  }
  c.ok = c.number < c.limit;
  if (c.ok) {
    c.message = format("explicit-integration bound: dt*sqrt(k/m) = %.3g < %.3g (%d substeps per frame)", c.number,
                       c.limit, scene.sim.steps_per_frame);
    return c;
  }
  const int need = c.steps_needed = autoSubsteps(scene);
  c.message = format("explicit-integration bound crossed: dt*sqrt(k/m) = %.3g >= %.3g with %d substeps per frame",
                     c.number, c.limit, scene.sim.steps_per_frame);
  c.message += need > 0 ? "; " + std::to_string(need) + " substeps per frame stay inside it (--auto-substeps)"
                        : "; no substep count up to " + std::to_string(kMaxAutoSubsteps) + " does";
  return c;
}

int autoSubsteps(const Scene& scene, int max_steps) {
  const double km = maxStiffnessOverMass(scene.cloth);
  if (km <= 0.0) return 1;
  if (!std::isfinite(km) || !(scene.sim.frames_per_sec > 0.0)) return 0;
  // More substeps lower the number and (with the damping rescaled) raise the limit, so "inside" is
  // monotonic in the count: bisect between a count that is outside (or 0) and one that is inside.
  auto inside = [&](int steps) {
    const Scene s = withSubsteps(scene, steps);
    return stabilityNumber(s) < stabilityLimit(s.cloth.damping);
  };
  if (inside(1)) return 1;
  // Undamped limit sqrt(2) >= any limit >= 1, so the count for limit 1 is always inside.
  const double enough = std::ceil(std::sqrt(km) / scene.sim.frames_per_sec) + 1.0;
  int lo = 1, hi = int(std::min(enough, double(max_steps)));
  if (!inside(hi)) return 0;
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    (inside(mid) ? hi : lo) = mid;
  }
  return hi;
}

Scene withStableSubsteps(const Scene& scene, int max_steps) {
  const int need = autoSubsteps(scene, max_steps);
  return need > scene.sim.steps_per_frame ? withSubsteps(scene, need) : scene;
}

Scene withSubsteps(const Scene& scene, int steps_per_frame) {
  Scene out = scene;
  out.sim.steps_per_frame = steps_per_frame;
  const double ratio = double(scene.sim.steps_per_frame) / steps_per_frame;
  const auto rescale = [ratio](double loss) { return 1.0 - std::pow(1.0 - loss, ratio); };
  out.cloth.damping = 100.0 * rescale(scene.cloth.damping / 100.0);
  for (SphereSpec& s : out.spheres)
    s.friction = rescale(s.friction);
  for (PlaneSpec& p : out.planes)
    p.friction = rescale(p.friction);
  for (MeshSpec& m : out.meshes)
    m.friction = rescale(m.friction);
  return out;
}

std::string detectBlowUp(const Topology& topo, const ClothSpec& cloth, const Positions& start, const Positions& x,
                         const BlowUpCriteria& criteria) {
  const double reach = criteria.max_travel * clothSize(cloth);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const glm::dvec3 p = x[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return "non-finite position at point " + std::to_string(i);
    if (i < start.size() && glm::distance(p, start[i]) > reach)
      return format("point %zu is %.3g m from its start (more than %.3g cloth sizes)", i, glm::distance(p, start[i]),
                    criteria.max_travel);
  }
  const double strain = maxStrain(topo, cloth, x);
  if (!(strain <= criteria.max_strain))
    return format("a spring is stretched to %.3g times its rest length (limit %.3g)", 1.0 + strain,
                  1.0 + criteria.max_strain);
  return {};
}

}  // namespace drape
