// The physics of one spring, one collision, one stretch limit: pure functions of values that return
// forces or position corrections. glsl/sim/physics.glsl implements the same functions under the same
// names; keep the two side by side when changing either. The model: docs/design.md.
#pragma once

#include "core/hash.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace drape::physics {

// The per-point loops call these thousands of times a substep; inside the solver's loop lambdas GCC's
// inliner gave up on some (stretchCorrection stayed a call, measured 1.5x slower), so force it.
#define DRAPE_PHYSICS_INLINE [[gnu::always_inline]] inline

template <class T>
using vec3 = glm::vec<3, T>;

inline constexpr double kSurfaceOffset = 1e-4;  // m, planes keep points this far on their side
inline constexpr double kPlaneEpsilon = 1e-6;   // m, "on the plane" for x_prev (16 float ulps at 1 m)

// Hooke spring seen from a: k (|b - a| - rest) along the unit vector towards b.
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> springForce(vec3<T> a, vec3<T> b, T rest, T k) {
  vec3<T> d = b - a;
  T len = glm::length(d);
  if (len <= T(0)) return vec3<T>(0);
  return (k * (len - rest) / len) * d;
}

// Verlet in displacement form: v = x - x_prev is stored instead of x_prev, because at dt = 1/2700 the
// difference of two positions near 1 m keeps only a few float digits (g dt^2 is ~11 ulps of 1.0).
// Returns the new displacement; the new position is x + v'.
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> integrateVerlet(vec3<T> v, vec3<T> accel, T dt2, T keep) {
  return keep * v + accel * dt2;  // keep = 1 - damping/100
}

// The same step in the classic CS184 form, kept for the accuracy comparison: returns x'.
template <class T>
vec3<T> integrateVerletPrevious(vec3<T> x, vec3<T> x_prev, vec3<T> accel, T dt2, T keep) {
  return x + keep * (x - x_prev) + accel * dt2;
}

// Self-collision between two points closer than 2*thickness: push xi away from xj by the overlap.
// The caller averages these over all such j and divides by steps_per_frame (CS184).
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> selfCollisionCorrection(vec3<T> xi, vec3<T> xj, T thickness) {
  vec3<T> d = xi - xj;
  T dist2 = glm::dot(d, d);
  T range = T(2) * thickness;
  if (dist2 >= range * range || dist2 <= T(0)) return vec3<T>(0);
  T dist = std::sqrt(dist2);
  return ((range - dist) / dist) * d;
}

// selfCollisionCorrection from both ends of a pair at once, bit for bit the two calls: xj - xi is exactly
// -(xi - xj) (rounding is symmetric), so both ends have the same dist2 and one square root serves. A NaN
// distance (whose payload need not be symmetric) takes the two calls. Returns whether the pair is in range.
template <class T>
DRAPE_PHYSICS_INLINE bool selfCollisionCorrections(vec3<T> xi, vec3<T> xj, T thickness, vec3<T>& ci, vec3<T>& cj) {
  vec3<T> d = xi - xj;
  T dist2 = glm::dot(d, d);
  T range = T(2) * thickness;
  if (dist2 >= range * range || dist2 <= T(0)) return false;
  if (!(dist2 == dist2)) {
    ci = selfCollisionCorrection(xi, xj, thickness);
    cj = selfCollisionCorrection(xj, xi, thickness);
    return true;
  }
  T dist = std::sqrt(dist2);
  T f = (range - dist) / dist;
  ci = f * d;
  cj = f * (xj - xi);
  return true;
}

// Whether the springs already hold the pair {i, j}: its distance in the rest shape is below the contact
// distance 2*thickness, so it would start "in contact" and self-collision would fight the springs (a cloth
// refined below 2*thickness between points). Such pairs are not self-collision candidates.
template <class T>
DRAPE_PHYSICS_INLINE bool heldAtRest(vec3<T> rest_i, vec3<T> rest_j, T range) {
  vec3<T> d = rest_i - rest_j;
  return glm::dot(d, d) < range * range;
}

// Position-based collision response with friction f, written as a correction c added to both x and
// v (so x_prev = x - v stays put): x' = x_prev + (1-f)(target - x_prev)  <=>  c = (1-f)(target-x) - f v.
// Working with the small differences target - x and v keeps float precision.
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> frictionCorrection(vec3<T> target_minus_x, vec3<T> v, T friction) {
  return (T(1) - friction) * target_minus_x - friction * v;
}

// Sphere: a point inside (|x - c| <= r, inclusive) goes to the nearest surface point. Returns whether
// it collided and the correction in `c`.
template <class T>
DRAPE_PHYSICS_INLINE bool collideSphere(vec3<T> x, vec3<T> v, vec3<T> center, T radius, T friction, vec3<T>& c) {
  vec3<T> d = x - center;
  T dist = glm::length(d);
  if (dist > radius) return false;
  vec3<T> dir = dist > T(0) ? d / dist : vec3<T>(0, 1, 0);  // the exact centre has no direction: go up
  c = frictionCorrection((radius - dist) * dir, v, friction);
  return true;
}

// Plane through p with unit normal n. Collides when x_prev = x - v and x are on different sides or x
// lies on the plane (inclusive, so points starting on it do not fall through). x_prev within
// kPlaneEpsilon of the plane counts as on the normal's side: x_prev is rebuilt as x - v, which can
// land an ulp or two below a plane that the point started exactly on. The target is where
// x_prev -> x meets the plane, moved kSurfaceOffset towards x_prev's side.
template <class T>
DRAPE_PHYSICS_INLINE bool collidePlane(vec3<T> x, vec3<T> v, vec3<T> p, vec3<T> n, T friction, vec3<T>& c) {
  T dx = glm::dot(x - p, n);
  T vn = glm::dot(v, n);
  bool prev_above = dx - vn >= -T(kPlaneEpsilon);
  bool crossed = prev_above ? dx <= T(0) : dx >= T(0);
  if (!crossed) return false;
  // x(s) = x_prev + s v meets the plane at 1 - s = dx / vn, so target - x = -(dx / vn) v; a point
  // moving along the plane (vn = 0) is on it and goes straight to the offset. The band lets the
  // line meet the plane outside the step (x_prev up to kPlaneEpsilon below it, moving up too slowly
  // to reach it, or down): there |dx / vn| would throw the point far along v. Clamped to the step's
  // segment, s in [0, 1], it goes to x or back to x_prev, then gets the offset.
  vec3<T> target_minus_x = vn != T(0) ? -std::clamp(dx / vn, T(0), T(1)) * v : -dx * n;
  target_minus_x += ((prev_above ? T(1) : T(-1)) * T(kSurfaceOffset)) * n;
  c = frictionCorrection(target_minus_x, v, friction);
  return true;
}

// Provot (1995) stretch limit for one spring seen from point i: if |xj - xi| > limit*rest, move xi
// towards xj by its share of the excess (1/2, all of it if j is pinned, none if i is pinned).
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> stretchCorrection(vec3<T> xi, vec3<T> xj, T rest, T limit, T share) {
  vec3<T> d = xj - xi;
  T len = glm::length(d);
  T max_len = limit * rest;
  if (len <= max_len) return vec3<T>(0);
  return (share * (len - max_len) / len) * d;
}

template <class T>
DRAPE_PHYSICS_INLINE T stretchShare(bool pinned_i, bool pinned_j) {
  return pinned_i ? T(0) : pinned_j ? T(1) : T(0.5);
}

// Long-range attachment (core/tethers.hpp) of a free point x to a pinned anchor: if x is further than
// limit*rest from it, x moves straight back to that distance. One-sided: a tether never pushes.
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> tetherCorrection(vec3<T> x, vec3<T> anchor, T rest, T limit) {
  vec3<T> d = anchor - x;
  T len = glm::length(d);
  T max_len = limit * rest;
  if (len <= max_len) return vec3<T>(0);
  return ((len - max_len) / len) * d;
}

// XPBD (Macklin, Mueller, Chentanez 2016) for one spring as a distance constraint C = |xb - xa| - rest of
// compliance 1/k, alpha_tilde = 1/(k dt^2) from the host. Returns the change of the spring's multiplier,
// dlambda = (-C - alpha_tilde lambda) / (w_sum + alpha_tilde), where w_sum = w_a + w_b (inverse masses,
// 0 for a pinned end), and in `p` the step dlambda * unit(xb - xa): a moves by -w_a p and b by +w_b p.
// alpha_tilde in the denominator is what makes the step bounded for any k and dt: k -> infinity is a
// hard constraint, not an explosion. A spring of zero length has no direction and takes no step.
template <class T>
DRAPE_PHYSICS_INLINE T xpbdDistanceCorrection(vec3<T> xa, vec3<T> xb, T rest, T w_sum, T alpha_tilde, T lambda,
                                              vec3<T>& p) {
  vec3<T> d = xb - xa;
  T len = glm::length(d);
  if (len <= T(0)) {
    p = vec3<T>(0);
    return T(0);
  }
  T dlambda = (-(len - rest) - alpha_tilde * lambda) / (w_sum + alpha_tilde);
  p = (dlambda / len) * d;
  return dlambda;
}

// Vertex Block Descent (Chen, Macklin, Mueller et al. 2024): one point's Newton step on its share of the
// implicit-Euler energy, the neighbours held, G(x) = m/(2 dt^2) |x - y|^2 + sum over its springs of
// k/2 (|xo - x| - rest)^2, y the prediction. The caller sums each spring's force and 3x3 Hessian into the
// point's block (f, the Hessian's diagonal and its xy, xz, yz entries), adds the inertia, and solves.
//
// One spring's share: springForce, and the Hessian k [u u^T + s (I - u u^T)] with u the unit direction
// and s = 1 - rest/|d| the transverse stiffness of a stretched spring. A compressed spring's s is negative
// and would make the block indefinite (a Newton step uphill): it is clamped to 0, the usual projection,
// which keeps the block at least m/dt^2 I, so the step is defined for any k and dt.
template <class T>
DRAPE_PHYSICS_INLINE void vbdAddSpring(vec3<T> x, vec3<T> xo, T rest, T k, vec3<T>& f, vec3<T>& h_diag,
                                       vec3<T>& h_off) {
  vec3<T> d = xo - x;
  T len = glm::length(d);
  if (len <= T(0)) return;
  f += (k * (len - rest) / len) * d;  // springForce(x, xo, rest, k), its operations in its order
  T s = len > rest ? T(1) - rest / len : T(0);
  T a = k * (T(1) - s) / (len * len);  // along u: k, written over d to need no normalised u
  T b = k * s;
  h_diag += vec3<T>(a * d.x * d.x + b, a * d.y * d.y + b, a * d.z * d.z + b);
  h_off += vec3<T>(a * d.x * d.y, a * d.x * d.z, a * d.y * d.z);
}

// The Newton step dx = H^-1 f of a point's block, by an LDL^T factorisation of the symmetric 3x3 H
// (no determinant, whose k^3 would overflow float at k = 1e13). H is at least m/dt^2 I, so every pivot is
// positive; one that is not (a NaN, an overflow) gives no step rather than a wild one.
template <class T>
DRAPE_PHYSICS_INLINE vec3<T> vbdStep(vec3<T> f, vec3<T> h_diag, vec3<T> h_off) {
  T d0 = h_diag.x;
  if (!(d0 > T(0))) return vec3<T>(0);
  T l10 = h_off.x / d0;
  T l20 = h_off.y / d0;
  T d1 = h_diag.y - l10 * h_off.x;
  if (!(d1 > T(0))) return vec3<T>(0);
  T l21 = (h_off.z - l20 * h_off.x) / d1;
  T d2 = h_diag.z - l20 * h_off.y - l21 * l21 * d1;
  if (!(d2 > T(0))) return vec3<T>(0);
  T z0 = f.x;
  T z1 = f.y - l10 * z0;
  T z2 = f.z - l20 * z0 - l21 * z1;
  T x2 = z2 / d2;
  T x1 = z1 / d1 - l21 * x2;
  T x0 = z0 / d0 - l10 * x1 - l20 * x2;
  return vec3<T>(x0, x1, x2);
}

// Wind: drag along the point's normal, proportional to the normal component of the air velocity
// relative to the point (sign of n does not matter).
template <class T>
vec3<T> windForce(vec3<T> normal, vec3<T> point_velocity, vec3<T> air_velocity, T drag_area) {
  T rel = glm::dot(air_velocity - point_velocity, normal);
  return (drag_area * rel) * normal;
}

using drape::hashCell;
using drape::hashU32;

template <class T>
T quinticFade(T t) {
  return t * t * t * (t * (t * T(6) - T(15)) + T(10));
}

// Beyond this many wavelengths from the origin valueNoise is 0: its lattice cell would not fit an int
// (converting it is undefined behaviour), and float has no fraction left there anyway (2^30 has ulp 128).
inline constexpr double kNoiseLimit = 1073741824.0;  // 2^30

// Value noise in [-1, 1]: lattice values from hashCell, quintic interpolation (C2 smooth). 0 for
// non-finite points (a cloth blowing up) and for points beyond kNoiseLimit.
template <class T>
T valueNoise(vec3<T> p) {
  // Written so that NaN fails the test too.
  if (!(std::fabs(p.x) < T(kNoiseLimit) && std::fabs(p.y) < T(kNoiseLimit) && std::fabs(p.z) < T(kNoiseLimit)))
    return T(0);
  vec3<T> f = glm::floor(p);
  glm::ivec3 i(f);
  vec3<T> t = p - f;
  vec3<T> u(quinticFade(t.x), quinticFade(t.y), quinticFade(t.z));
  auto corner = [&](int dx, int dy, int dz) {
    return T(hashCell(i + glm::ivec3(dx, dy, dz)) >> 8) * T(1.0 / 8388608.0) - T(1);
  };
  T x00 = glm::mix(corner(0, 0, 0), corner(1, 0, 0), u.x);
  T x10 = glm::mix(corner(0, 1, 0), corner(1, 1, 0), u.x);
  T x01 = glm::mix(corner(0, 0, 1), corner(1, 0, 1), u.x);
  T x11 = glm::mix(corner(0, 1, 1), corner(1, 1, 1), u.x);
  return glm::mix(glm::mix(x00, x10, u.y), glm::mix(x01, x11, u.y), u.z);
}

// Air velocity at x and time t: steady velocity plus noise of relative amplitude `turbulence`, its
// pattern drifting through space at noise_speed (in wavelengths per second).
template <class T>
vec3<T> windVelocity(vec3<T> x, T t, vec3<T> velocity, T turbulence, T noise_scale, T noise_speed) {
  vec3<T> p = x / noise_scale + (t * noise_speed) * vec3<T>(1.0, 0.37, 0.71);
  vec3<T> n(valueNoise(p), valueNoise(p + vec3<T>(17.3, 5.1, 9.7)), valueNoise(p + vec3<T>(3.7, 23.9, 13.1)));
  return velocity + (glm::length(velocity) * turbulence) * n;
}

// Normal of a grid point from its neighbours (clamped at the border): central differences along the
// grid's two directions. Used by wind, which only needs the direction up to sign.
template <class T>
vec3<T> gridNormal(vec3<T> left, vec3<T> right, vec3<T> down, vec3<T> up) {
  vec3<T> n = glm::cross(right - left, up - down);
  T len = glm::length(n);
  return len > T(0) ? n / len : vec3<T>(0);
}

}  // namespace drape::physics
