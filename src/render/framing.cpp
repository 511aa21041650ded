#include "render/framing.hpp"

#include "core/mesh_obstacle.hpp"
#include "core/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace drape {

namespace {

// The indices of the points on the upper convex hull of (u[i], v[i]): the chain every other point lies on or
// below. Andrew's monotone chain.
std::vector<std::size_t> upperHull(const std::vector<float>& u, const std::vector<float>& v) {
  std::vector<std::size_t> order(u.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return u[a] != u[b] ? u[a] < u[b] : v[a] < v[b]; });
  std::vector<std::size_t> hull;
  for (std::size_t p : order) {
    while (hull.size() >= 2) {
      const std::size_t o = hull[hull.size() - 2], b = hull.back();
      // p on or above the line from o through b: b is not on the upper hull.
      if ((u[b] - u[o]) * (v[p] - v[o]) - (v[b] - v[o]) * (u[p] - u[o]) < 0.0f) break;
      hull.pop_back();
    }
    hull.push_back(p);
  }
  return hull;
}

// Keeps the points that can decide the default view's framing. Camera::frame fits the largest of
// z ± x / t_x, z ± y / t_y and z over the points (x, y, z in the default view's axes) for whatever t the
// aspect ratio gives: linear functions, so each is largest at a vertex of the upper hull of the points in
// the (x, z) plane or in the (y, z) plane.
void keepOutline(std::vector<glm::vec3>& points) {
  if (points.size() < 4) return;
  const ViewAxes axes = Camera::defaultAxes();
  std::vector<float> x(points.size()), y(points.size()), z(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    x[i] = glm::dot(points[i], axes.right);
    y[i] = glm::dot(points[i], axes.up);
    z[i] = glm::dot(points[i], axes.back);
  }
  std::vector<std::size_t> keep = upperHull(x, z);
  const std::vector<std::size_t> vertical = upperHull(y, z);
  keep.insert(keep.end(), vertical.begin(), vertical.end());
  std::sort(keep.begin(), keep.end());
  keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  std::vector<glm::vec3> kept;
  kept.reserve(keep.size());
  for (std::size_t i : keep)
    kept.push_back(points[i]);
  points = std::move(kept);
}

// Appends `more` to `points`, keeping the outline of the whole once it grows: the union's outline is the
// outline of the parts' outlines.
void addOutline(std::vector<glm::vec3>& points, std::vector<glm::vec3> more) {
  keepOutline(more);
  points.insert(points.end(), more.begin(), more.end());
  if (points.size() > 4096) keepOutline(points);
}

Bounds emptyBounds() {
  return {glm::vec3(1e30f), glm::vec3(-1e30f)};
}

}  // namespace

SceneExtent::SceneExtent(const Scene& scene, const Topology& topology) : cloth_bounds_(emptyBounds()) {
  if (!scene.planes.empty()) {
    scene_ground_ = true;
    up_ = glm::normalize(glm::vec3(scene.planes.front().normal));
    ground_point_ = glm::vec3(scene.planes.front().point);
  } else {
    const glm::vec3 g = glm::vec3(scene.sim.gravity);
    up_ = glm::length(g) > 0.0f ? -glm::normalize(g) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  for (const SphereSpec& s : scene.spheres)
    colliders_.spheres.push_back(glm::vec4(glm::vec3(s.origin), float(s.radius)));
  for (const MeshSpec& m : scene.meshes)
    for (const glm::dvec3& x : m.mesh->positions)
      colliders_.points.push_back(glm::vec3(x));
  addCloth(topology.initial_positions);
}

void SceneExtent::addCloth(const std::vector<glm::dvec3>& x) {
  std::vector<glm::vec3> points, shadow;
  points.reserve(x.size());
  shadow.reserve(x.size());
  for (const glm::dvec3& p : x) {
    const glm::vec3 q(p);
    points.push_back(q);
    shadow.push_back(q - glm::dot(q, up_) * up_);
    cloth_bounds_.include(q);
  }
  addOutline(cloth_, std::move(points));
  addOutline(shadow_, std::move(shadow));
  ++cloth_frames_;
}

Bounds SceneExtent::colliderBounds() const {
  Bounds b = emptyBounds();
  for (const glm::vec3& p : colliders_.points)
    b.include(p);
  for (const glm::vec4& s : colliders_.spheres) {
    b.include(glm::vec3(s) - s.w);
    b.include(glm::vec3(s) + s.w);
  }
  return b;
}

Bounds SceneExtent::casterBounds() const {
  Bounds b = colliderBounds();
  b.include(cloth_bounds_.min);
  b.include(cloth_bounds_.max);
  return b;
}

Ground SceneExtent::ground() const {
  if (scene_ground_) return {ground_point_, up_, true};
  // A little below the lowest point the cloth reached and the lowest collider, so that nothing touches it.
  const Bounds b = casterBounds();
  float lowest = 1e30f;
  for (int corner = 0; corner < 8; ++corner)
    lowest = std::min(lowest, glm::dot(glm::vec3(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                                                 corner & 4 ? b.max.z : b.min.z),
                                       up_));
  const float gap = std::max(0.03f * b.radius(), 1e-3f);
  return {(lowest - gap) * up_, up_, false};
}

FramingSubject SceneExtent::subject() const {
  FramingSubject s = colliders_;
  s.points.insert(s.points.end(), cloth_.begin(), cloth_.end());
  const Ground g = ground();
  const glm::vec3 offset = glm::dot(g.point, g.normal) * g.normal;
  for (const glm::vec3& p : shadow_)
    s.points.push_back(p + offset);
  return s;
}

int lookAheadFrames(const Scene& scene) {
  return std::max(1, int(std::ceil(2.0 * scene.sim.frames_per_sec - 1e-9)));
}

int lookAhead(SceneExtent& extent, Solver& solver, int frames,
              const std::function<void(int frame, const std::vector<glm::dvec3>& x)>& each) {
  if (each) each(0, solver.readPositions());
  int stepped = 0;
  while (stepped < frames) {
    solver.stepFrame();
    // The explicit read-back of the look-ahead, once a frame: it runs before the first image, not during the run.
    const std::vector<glm::dvec3> x = solver.readPositions();
    if (!allFinite(x) || !solver.health().ok()) break;
    ++stepped;
    extent.addCloth(x);
    if (each) each(stepped, x);
  }
  solver.reset();
  return stepped;
}

}  // namespace drape
