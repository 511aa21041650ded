// Collision with a mesh obstacle: its signed distance field (core/mesh_obstacle.hpp) for the cloth's points,
// and its sharp edges and corners (core/mesh_features.hpp) for the cloth's edges and triangles. Pure
// functions, as those of physics.hpp; collideField has its GLSL twin in glsl/sim/phases/mesh_collide.glsl, the
// same float operations in the same order; edgeContact and cornerContact are written for one (their data
// and order: docs/contact.md). Keep each pair side by side when changing either.
#pragma once

#include "core/mesh_obstacle.hpp"
#include "cpu/physics.hpp"

namespace drape::physics {

// A point closer to the surface than `offset` (the obstacle's collision thickness, at least
// kMeshSurfaceOffset: meshOffset) or inside goes to that distance along the field's gradient, with the sphere's
// friction response. The field is trilinear between its samples; its gradient is the trilinear function's own, so
// target and direction come from the same eight samples. The samples are signed distances throughout the lattice, so a
// point inside is pushed out however deep it is, through the nearest surface; outside the lattice (kFieldPadCells
// beyond the mesh's bounding box) nothing happens.
template <class T>
DRAPE_PHYSICS_INLINE bool collideField(vec3<T> x, vec3<T> v, const DistanceField& field, T offset, T friction,
                                       vec3<T>& c) {
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
  if (d >= offset) return false;
  const vec3<T> grad(glm::mix(glm::mix(s100 - s000, s110 - s010, t.y), glm::mix(s101 - s001, s111 - s011, t.y), t.z),
                     glm::mix(glm::mix(s010 - s000, s110 - s100, t.x), glm::mix(s011 - s001, s111 - s101, t.x), t.z),
                     glm::mix(glm::mix(s001 - s000, s101 - s100, t.x), glm::mix(s011 - s010, s111 - s110, t.x), t.y));
  const T len = glm::length(grad);
  if (len <= T(0)) return false;
  c = frictionCorrection((offset - d) * (grad / len), v, friction);
  return true;
}

// How far a cloth point is kept outside the field's zero level: the obstacle's collision thickness, and never
// less than kMeshSurfaceOffset, which covers how far the trilinear surface cuts a convex edge.
template <class T>
DRAPE_PHYSICS_INLINE T meshOffset(T thickness) {
  return std::max(thickness, T(kMeshSurfaceOffset));
}

// Whether two balls (centre, radius) are more than `thickness` apart, with a tenth to spare: such a cloth edge
// or triangle cannot touch such a feature, and edgeContact or cornerContact would say no for sure. Only a
// shortcut past them, taken alike by both solvers.
template <class T>
DRAPE_PHYSICS_INLINE bool farApart(vec3<T> a, T ra, vec3<T> b, T rb, T thickness) {
  const vec3<T> d = a - b;
  const T reach = T(1.1) * (ra + rb + thickness);
  return glm::dot(d, d) > reach * reach;
}

// A cloth edge p-q against a sharp convex obstacle edge a-b, whose faces have the outward unit normals n1, n2
// (core/mesh_features.hpp). Where the two segments come closest at points inside both, c = p + s (q - p) and
// e = a + t (b - a), and c is less than `thickness` outside both of the edge's faces, the cloth edge must
// pass the obstacle edge on its outer side by `thickness`: c moves along the segments' common normal m
// (cross(q - p, b - a), turned to the outer side, n1 + n2) by thickness - sep, sep = (c - e).m, its height
// above the edge. A cloth edge crossing deeper under the edge than half its own length is not this edge's
// (a thin part's far side). Returns whether it touches, s, and c's move; the caller shares the move between
// p and q (edgeShare). Segments closest at an end are a point's or a corner's contact, not this one's.
// (Closest points of two segments: Ericson, Real-Time Collision Detection, 5.1.9.)
template <class T>
DRAPE_PHYSICS_INLINE bool edgeContact(vec3<T> p, vec3<T> q, vec3<T> a, vec3<T> b, vec3<T> n1, vec3<T> n2, T thickness,
                                      T& s, vec3<T>& move) {
  const vec3<T> d1 = q - p, d2 = b - a, r = p - a;
  const T aa = glm::dot(d1, d1), bb = glm::dot(d1, d2), ee = glm::dot(d2, d2);
  const T cc = glm::dot(d1, r), ff = glm::dot(d2, r);
  const vec3<T> normal = glm::cross(d1, d2);
  const T normal2 = glm::dot(normal, normal);
  // Nearly parallel (the sine of their angle below 1e-3): no single crossing to push apart.
  if (!(normal2 > T(1e-6) * aa * ee)) return false;
  const T denom = aa * ee - bb * bb;
  s = (bb * ff - cc * ee) / denom;
  const T t = (aa * ff - bb * cc) / denom;
  if (!(s > T(0) && s < T(1) && t > T(0) && t < T(1))) return false;
  const vec3<T> gap = (p + s * d1) - (a + t * d2);
  if (std::max(glm::dot(gap, n1), glm::dot(gap, n2)) >= thickness) return false;  // clear of the edge's faces
  vec3<T> m = normal / std::sqrt(normal2);
  const vec3<T> out = n1 + n2;
  const T along = glm::dot(m, out);
  // m nearly across the edge's outer direction (the cloth edge in the plane of the edge and that direction):
  // which side is out is not clear, and the points' collisions decide.
  if (along * along < T(0.01) * glm::dot(out, out)) return false;
  if (along < T(0)) m = -m;
  const T sep = glm::dot(gap, m);
  if (sep >= thickness || sep < T(-0.5) * std::sqrt(aa)) return false;
  move = (thickness - sep) * m;
  return true;
}

// A cloth triangle p0 p1 p2 against a sharp convex obstacle corner v of outward unit normal nv: where v lies
// inside the triangle seen along the triangle's normal n (turned to nv's side), and the triangle's plane is
// less than `thickness` above v along n, the triangle moves along n until it is `thickness` above v.
// Returns whether it touches, the barycentric weights of the point of the triangle over v, and that point's
// move; the caller shares it between the corners (cornerShare). A plane more than half the triangle's
// longest side below v is not this corner's business.
template <class T>
DRAPE_PHYSICS_INLINE bool cornerContact(vec3<T> p0, vec3<T> p1, vec3<T> p2, vec3<T> v, vec3<T> nv, T thickness,
                                        vec3<T>& bary, vec3<T>& move) {
  const vec3<T> normal = glm::cross(p1 - p0, p2 - p0);
  const T normal2 = glm::dot(normal, normal);
  if (!(normal2 > T(0))) return false;
  vec3<T> n = normal / std::sqrt(normal2);
  const T along = glm::dot(n, nv);
  if (along * along < T(0.01)) return false;  // the triangle edge-on to the corner: no clear outer side
  if (along < T(0)) n = -n;
  const T sep = glm::dot(p0 - v, n);
  const T longest2 = std::max({glm::dot(p1 - p0, p1 - p0), glm::dot(p2 - p1, p2 - p1), glm::dot(p0 - p2, p0 - p2)});
  if (sep >= thickness || sep * sep * T(4) > longest2) return false;
  const vec3<T> at = v + sep * n;  // v seen in the triangle's plane
  const T b0 = glm::dot(glm::cross(p1 - at, p2 - at), normal) / normal2;
  const T b1 = glm::dot(glm::cross(p2 - at, p0 - at), normal) / normal2;
  const T b2 = T(1) - b0 - b1;
  if (!(b0 > T(0) && b1 > T(0) && b2 > T(0))) return false;
  bary = vec3<T>(b0, b1, b2);
  move = (thickness - sep) * n;
  return true;
}

// The share of a contact's move that one corner of the cloth edge or triangle takes so that the contact point,
// at weights w (1 - s, s or the barycentric ones), moves by exactly `move` when every corner takes its share:
// w_i / sum w_k^2 (Bridson, Fedkiw, Anderson 2002).
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> edgeShare(T s, bool second, vec3<T> move) {
  const T w = second ? s : T(1) - s;
  return (w / ((T(1) - s) * (T(1) - s) + s * s)) * move;
}

template <class T>
DRAPE_PHYSICS_INLINE vec3<T> cornerShare(vec3<T> bary, int corner, vec3<T> move) {
  return (bary[corner] / glm::dot(bary, bary)) * move;
}

}  // namespace drape::physics
