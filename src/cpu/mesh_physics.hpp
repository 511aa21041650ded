// Collision with a mesh obstacle's signed distance field (core/mesh_obstacle.hpp): a pure function, as
// those of physics.hpp, implemented under the same name and with the same float operations in the same
// order in glsl/sim/mesh_collide.glsl. Keep the two side by side when changing either.
#pragma once

#include "core/mesh_obstacle.hpp"
#include "cpu/physics.hpp"

namespace drape::physics {

// A point closer to the surface than kMeshSurfaceOffset (or inside) goes to that distance along the field's
// gradient, with the sphere's friction response. The field is trilinear between its samples; its gradient
// is the trilinear function's own, so target and direction come from the same eight samples. The samples
// are signed distances throughout the lattice, so a point inside is pushed out however deep it is, through
// the nearest surface; outside the lattice (kFieldPadCells beyond the mesh's bounding box) nothing happens.
template <class T>
DRAPE_PHYSICS_INLINE bool collideField(vec3<T> x, vec3<T> v, const DistanceField& field, T friction, vec3<T>& c) {
  const vec3<T> g = (x - vec3<T>(field.origin)) * T(1.0 / field.cell);
  // Written so that NaN fails too: converting it to int would be undefined.
  if (!(g.x >= T(0) && g.y >= T(0) && g.z >= T(0) && g.x < T(field.dims.x - 1) && g.y < T(field.dims.y - 1) &&
        g.z < T(field.dims.z - 1)))
    return false;
  const vec3<T> f = glm::floor(g);
  const glm::ivec3 i(f);
  const vec3<T> t = g - f;
  auto s = [&](int dx, int dy, int dz) { return T(field.samples[field.index(i.x + dx, i.y + dy, i.z + dz)]); };
  const T s000 = s(0, 0, 0), s100 = s(1, 0, 0), s010 = s(0, 1, 0), s110 = s(1, 1, 0);
  const T s001 = s(0, 0, 1), s101 = s(1, 0, 1), s011 = s(0, 1, 1), s111 = s(1, 1, 1);
  const T x00 = glm::mix(s000, s100, t.x), x10 = glm::mix(s010, s110, t.x);
  const T x01 = glm::mix(s001, s101, t.x), x11 = glm::mix(s011, s111, t.x);
  const T d = glm::mix(glm::mix(x00, x10, t.y), glm::mix(x01, x11, t.y), t.z);
  const T offset = T(kMeshSurfaceOffset);
  if (d >= offset) return false;
  const vec3<T> grad(glm::mix(glm::mix(s100 - s000, s110 - s010, t.y), glm::mix(s101 - s001, s111 - s011, t.y), t.z),
                     glm::mix(glm::mix(s010 - s000, s110 - s100, t.x), glm::mix(s011 - s001, s111 - s101, t.x), t.z),
                     glm::mix(glm::mix(s001 - s000, s101 - s100, t.x), glm::mix(s011 - s010, s111 - s110, t.x), t.y));
  const T len = glm::length(grad);
  if (len <= T(0)) return false;
  c = frictionCorrection((offset - d) * (grad / len), v, friction);
  return true;
}

}  // namespace drape::physics
