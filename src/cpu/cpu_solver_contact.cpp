// CpuSolver's contact with the obstacles: each point against the spheres, planes and meshes (collide), and the
// cloth's faces against the mesh obstacles' sharp features (collideFaces); kept apart from cpu_solver.cpp for
// its size. The data and the order of the work: docs/contact.md.
#include "cpu/cpu_solver.hpp"
#include "cpu/cpu_solver_sweep.hpp"
#include "cpu/mesh_physics.hpp"
#include "cpu/parallel.hpp"

#include <type_traits>

namespace drape {

template <class T>
void CpuSolver<T>::collidePoint(std::size_t i) {
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
}

template <class T>
void CpuSolver<T>::collide(bool wait) {
  positionsMoved();
  // Spheres and planes lane by lane, several points at once; meshes (the baked field) point by point. Where
  // integrate left the points in the grid path's arrays, there.
  if constexpr (std::is_same_v<T, float>)
    if (grid_integrate_) {
      grid_->collide(collideArgs());
      if (wait) teamBarrier();
      return;
    }
  if constexpr (std::is_same_v<T, float>)
    if (kernels_ && form_ == VerletForm::Displacement && scene_.meshes.empty()) {
      const CollideArgs args = collideArgs();
      forPoints(
          [&](long long lo, long long hi) {
            for (long long k = kernels_->collideObjects(args, lo, hi); k < hi; ++k)
              collidePoint(std::size_t(k));
          },
          wait);
      return;
    }
  forEachPoint([&](long long k) { collidePoint(std::size_t(k)); }, wait);
}

template <class T>
CollideArgs CpuSolver<T>::collideArgs() {
  const std::size_t planes = 5 * scene_.spheres.size();  // refreshDerived lays them out
  return CollideArgs{&x_.data()->x,
                     &v_.data()->x,
                     pinned1_.data(),
                     collide_objects_.data(),
                     int(scene_.spheres.size()),
                     collide_objects_.data() + planes,
                     int(scene_.planes.size()),
                     float(physics::kPlaneEpsilon),
                     float(physics::kSurfaceOffset)};
}

// collide() once more, after the passes that moved the points since: on the padded arrays where they still hold
// them (collideLastOnGrid; the stretch limit left them there), then copied back.
template <class T>
void CpuSolver<T>::collideLast() {
  if constexpr (std::is_same_v<T, float>)
    if (grid_integrate_) {  // and left there for the next substep (positions_behind_)
      grid_->collide(collideArgs());
      return;
    }
  if constexpr (std::is_same_v<T, float>)
    if (collideLastOnGrid()) {
      grid_->collideAndCopyOut(x_, v_, collideArgs(), false);
      return;
    }
  collide(false);
}

template <class T>
void CpuSolver<T>::buildFaceContacts() {
  face_contacts_.clear();
  if (scene_.meshes.empty() || topo_.triangles.empty()) return;
  faces_ = buildFaceAdjacency(topo_);
  bool any = false;
  std::vector<FaceContacts> contacts;
  for (const MeshSpec& m : scene_.meshes) {
    const MeshFeatures kept = contactFeatures(scene_, m);
    FaceContacts fc;
    const double thickness = meshThickness(scene_.cloth, m);
    fc.thickness = T(thickness);
    fc.grid = buildFeatureGrid(kept, featureReach(thickness, faces_));
    for (const FeatureEdge& e : kept.edges)
      fc.edges.push_back({vec3(e.a), vec3(e.b), vec3(e.normal_a), vec3(e.normal_b), vec3(0.5 * (e.a + e.b)),
                          T(0.5 * glm::distance(e.a, e.b))});
    for (const FeatureCorner& c : kept.corners)
      fc.corners.push_back({vec3(c.p), vec3(c.normal)});
    any = any || !fc.edges.empty() || !fc.corners.empty();
    contacts.push_back(std::move(fc));
  }
  if (any) face_contacts_ = std::move(contacts);
}

// Jacobi, as self-collision: every point gathers the contacts of its edges (those with a pinned point skipped)
// (ascending edge index) and then of its triangles (ascending triangle index), mesh after mesh, each against the
// features its grid cell lists (ascending), all from the positions before the pass; it takes the mean of its shares. A
// contact's two or three points compute it alike, so they agree on it without writing to one another.
template <class T>
void CpuSolver<T>::collideFaces() {
  positionsMoved();
  const long long n = (long long)x_.size();
  const T third = T(1.0 / 3.0);
  parallelFor(0, n, threads_, [&](long long pi) {
    const auto i = std::uint32_t(pi);
    vec3 sum(0);
    int count = 0;
    if (!topo_.pinned[i]) {
      for (const FaceContacts& mesh : face_contacts_) {
        const FeatureGrid& g = mesh.grid;
        if (g.edge_start.empty()) continue;
        auto cellOf = [&](vec3 at, glm::ivec3& cell) {
          const vec3 c = glm::floor((at - vec3(g.origin_f)) * T(g.inv_cell_f));
          if (!(c.x >= T(0) && c.y >= T(0) && c.z >= T(0) && c.x < T(g.dims.x) && c.y < T(g.dims.y) &&
                c.z < T(g.dims.z)))
            return false;
          cell = glm::ivec3(c);
          return true;
        };
        for (std::uint32_t k = faces_.edge_start[i]; k < faces_.edge_start[i + 1]; ++k) {
          const std::uint32_t e = faces_.point_edges[k];
          const std::uint32_t a = faces_.edges[2 * e], b = faces_.edges[2 * e + 1];
          if (topo_.pinned[a] || topo_.pinned[b]) continue;  // see below
          const vec3 mid = (x_[a] + x_[b]) * T(0.5);
          glm::ivec3 cell;
          if (!cellOf(mid, cell)) continue;
          const std::size_t c = g.index(cell);
          const T half = T(0.5) * glm::distance(x_[a], x_[b]);
          for (std::uint32_t f = g.edge_start[c]; f < g.edge_start[c + 1]; ++f) {
            const FeatureEdgeT& fe = mesh.edges[g.edges[f]];
            if (physics::farApart(mid, half, fe.mid, fe.half, mesh.thickness)) continue;
            T s;
            vec3 move;
            if (physics::edgeContact(x_[a], x_[b], fe.a, fe.b, fe.n1, fe.n2, mesh.thickness, s, move)) {
              sum += physics::edgeShare(s, i == b, move);
              ++count;
            }
          }
        }
        for (std::uint32_t k = faces_.triangle_start[i]; k < faces_.triangle_start[i + 1]; ++k) {
          const std::uint32_t t = faces_.point_triangles[k];
          const std::uint32_t p0 = topo_.triangles[3 * t], p1 = topo_.triangles[3 * t + 1],
                              p2 = topo_.triangles[3 * t + 2];
          // A pin cannot take its share, so a contact at a pin never resolves and pushes the free points
          // again every substep, into their velocity: the flag, pinned a thickness from its pole, wrapped
          // itself around the pole. Where the scene pins the cloth, the pin has the last word.
          if (topo_.pinned[p0] || topo_.pinned[p1] || topo_.pinned[p2]) continue;
          const vec3 centre = (x_[p0] + x_[p1] + x_[p2]) * third;
          glm::ivec3 cell;
          if (!cellOf(centre, cell)) continue;
          const std::size_t c = g.index(cell);
          const int corner = i == p0 ? 0 : i == p1 ? 1 : 2;
          const T radius = std::sqrt(
              std::max({glm::dot(x_[p0] - centre, x_[p0] - centre), glm::dot(x_[p1] - centre, x_[p1] - centre),
                        glm::dot(x_[p2] - centre, x_[p2] - centre)}));
          for (std::uint32_t f = g.corner_start[c]; f < g.corner_start[c + 1]; ++f) {
            const FeatureCornerT& fc = mesh.corners[g.corners[f]];
            if (physics::farApart(centre, radius, fc.p, T(0), mesh.thickness)) continue;
            vec3 bary, move;
            if (physics::cornerContact(x_[p0], x_[p1], x_[p2], fc.p, fc.normal, mesh.thickness, bary, move)) {
              sum += physics::cornerShare(bary, corner, move);
              ++count;
            }
          }
        }
      }
    }
    correction_[i] = count > 0 ? sum / T(count) : vec3(0);
  });
  applyCorrections();
}

// The members defined here; cpu_solver.cpp instantiates the rest of the class.
template void CpuSolver<float>::buildFaceContacts();
template void CpuSolver<float>::collideFaces();
template void CpuSolver<float>::collide(bool);
template CollideArgs CpuSolver<float>::collideArgs();
template void CpuSolver<float>::collideLast();
template void CpuSolver<double>::collideLast();
template void CpuSolver<double>::collide(bool);
template void CpuSolver<float>::collidePoint(std::size_t);
template void CpuSolver<double>::collidePoint(std::size_t);
template void CpuSolver<double>::buildFaceContacts();
template void CpuSolver<double>::collideFaces();

}  // namespace drape
