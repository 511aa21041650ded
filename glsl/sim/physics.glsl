// The physics of one spring, one collision, one stretch limit: the same pure functions, by the same
// names and with the same operations in the same order, as src/cpu/physics.hpp. Keep the two side
// by side when changing either. The model: docs/design.md.
//
// Every result is `precise`: without it the compiler may contract a*b + c into one fused multiply-add
// (rounded once, where the CPU rounds twice) or reassociate sums, and the GPU would drift from the CPU
// float reference by more than the ulps the consistency tests allow. dot3/length3/cross3/mix1 spell
// out glm's operation order instead of trusting the driver's built-ins to use the same one.
#pragma once

const float kSurfaceOffset = 1e-4;  // m, planes keep points this far on their side
const float kPlaneEpsilon = 1e-6;   // m, "on the plane" for x_prev

float dot3(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y + a.z * b.z;  // glm: (x + y) + z
  return r;
}

float length3(vec3 v) {
  precise float r = sqrt(dot3(v, v));
  return r;
}

vec3 cross3(vec3 a, vec3 b) {
  precise vec3 r = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
  return r;
}

float mix1(float a, float b, float t) {
  precise float r = a * (1.0 - t) + b * t;  // glm::mix, not a + t (b - a)
  return r;
}

// Hooke spring seen from a: k (|b - a| - rest) along the unit vector towards b.
vec3 springForce(vec3 a, vec3 b, float rest, float k) {
  precise vec3 d = b - a;
  precise float len = length3(d);
  if (len <= 0.0) return vec3(0.0);
  precise vec3 f = (k * (len - rest) / len) * d;
  return f;
}

// Verlet in displacement form (v = x - x_prev); returns v', the new position is x + v'.
vec3 integrateVerlet(vec3 v, vec3 accel, float dt2, float keep) {
  precise vec3 r = keep * v + accel * dt2;
  return r;
}

// Push xi away from xj by the overlap when closer than 2 * thickness (averaged by the caller).
vec3 selfCollisionCorrection(vec3 xi, vec3 xj, float thickness) {
  precise vec3 d = xi - xj;
  precise float dist2 = dot3(d, d);
  precise float range = 2.0 * thickness;
  if (dist2 >= range * range || dist2 <= 0.0) return vec3(0.0);
  precise float dist = sqrt(dist2);
  precise vec3 r = ((range - dist) / dist) * d;
  return r;
}

// x' = x_prev + (1-f)(target - x_prev) written as a correction added to both x and v.
vec3 frictionCorrection(vec3 target_minus_x, vec3 v, float friction) {
  precise vec3 r = (1.0 - friction) * target_minus_x - friction * v;
  return r;
}

bool collideSphere(vec3 x, vec3 v, vec3 center, float radius, float friction, out vec3 c) {
  c = vec3(0.0);
  precise vec3 d = x - center;
  precise float dist = length3(d);
  if (dist > radius) return false;
  precise vec3 dir = dist > 0.0 ? d / dist : vec3(0.0, 1.0, 0.0);
  precise vec3 r = frictionCorrection((radius - dist) * dir, v, friction);
  c = r;
  return true;
}

// Plane through p with unit normal n. x_prev within kPlaneEpsilon of the plane counts as on the
// normal's side (x_prev = x - v can land an ulp below a plane the point started on).
bool collidePlane(vec3 x, vec3 v, vec3 p, vec3 n, float friction, out vec3 c) {
  c = vec3(0.0);
  precise float dx = dot3(x - p, n);
  precise float vn = dot3(v, n);
  precise float dprev = dx - vn;
  bool prev_above = dprev >= -kPlaneEpsilon;
  bool crossed = prev_above ? dx <= 0.0 : dx >= 0.0;
  if (!crossed) return false;
  // x(s) = x_prev + s v meets the plane at 1 - s = dx / vn; moving along the plane: straight to it.
  // Clamped to s in [0, 1], as physics.hpp explains: x_prev in the band below the plane, moving up
  // slowly, would otherwise be thrown along v by |dx / vn|.
  precise vec3 target_minus_x = vn != 0.0 ? -clamp(dx / vn, 0.0, 1.0) * v : -dx * n;
  target_minus_x += ((prev_above ? 1.0 : -1.0) * kSurfaceOffset) * n;
  precise vec3 r = frictionCorrection(target_minus_x, v, friction);
  c = r;
  return true;
}

// Provot (1995) stretch limit for one spring seen from point i.
vec3 stretchCorrection(vec3 xi, vec3 xj, float rest, float limit, float share) {
  precise vec3 d = xj - xi;
  precise float len = length3(d);
  precise float max_len = limit * rest;
  if (len <= max_len) return vec3(0.0);
  precise vec3 r = (share * (len - max_len) / len) * d;
  return r;
}

float stretchShare(bool pinned_i, bool pinned_j) {
  return pinned_i ? 0.0 : pinned_j ? 1.0 : 0.5;
}

// limit_stretch_coloured.comp's move of a free end i of spring (a, b), a < b, seen from that end alone:
// exactly what the per-spring kernel gives it, so the kernels that work per point (phases/stretch_in_group.glsl:
// the one-dispatch and tiled paths) match it bit for bit. With equal shares end b takes -ca, which IEEE
// negation makes exact; `i_is_b` says which end i is.
vec3 stretchOneEnd(vec3 xi, vec3 xj, bool i_is_b, bool pinned_j, float rest, float limit) {
  float share_i = stretchShare(false, pinned_j);
  float share_j = stretchShare(pinned_j, false);
  if (i_is_b && share_i == share_j) {
    precise vec3 cj = stretchCorrection(xj, xi, rest, limit, share_j);
    return -cj;
  }
  precise vec3 ci = stretchCorrection(xi, xj, rest, limit, share_i);
  return ci;
}

// Long-range attachment of a free point to a pinned anchor (physics.hpp explains).
vec3 tetherCorrection(vec3 x, vec3 anchor, float rest, float limit) {
  precise vec3 d = anchor - x;
  precise float len = length3(d);
  precise float max_len = limit * rest;
  if (len <= max_len) return vec3(0.0);
  precise vec3 r = ((len - max_len) / len) * d;
  return r;
}

// XPBD distance constraint of one spring (physics.hpp explains): returns dlambda, and in p the step
// dlambda * unit(xb - xa); a moves by -w_a p, b by +w_b p.
float xpbdDistanceCorrection(vec3 xa, vec3 xb, float rest, float w_sum, float alpha_tilde, float lambda, out vec3 p) {
  p = vec3(0.0);
  precise vec3 d = xb - xa;
  precise float len = length3(d);
  if (len <= 0.0) return 0.0;
  precise float dlambda = (-(len - rest) - alpha_tilde * lambda) / (w_sum + alpha_tilde);
  precise vec3 r = (dlambda / len) * d;
  p = r;
  return dlambda;
}

// Vertex Block Descent: one spring's force and Hessian added to a point's block (physics.hpp explains).
void vbdAddSpring(vec3 x, vec3 xo, float rest, float k, inout vec3 f, inout vec3 h_diag, inout vec3 h_off) {
  precise vec3 d = xo - x;
  precise float len = length3(d);
  if (len <= 0.0) return;
  precise vec3 fs = (k * (len - rest) / len) * d;
  f = f + fs;
  precise float s = len > rest ? 1.0 - rest / len : 0.0;
  precise float a = k * (1.0 - s) / (len * len);
  precise float b = k * s;
  precise vec3 hd = vec3(a * d.x * d.x + b, a * d.y * d.y + b, a * d.z * d.z + b);
  precise vec3 ho = vec3(a * d.x * d.y, a * d.x * d.z, a * d.y * d.z);
  h_diag = h_diag + hd;
  h_off = h_off + ho;
}

// The Newton step H^-1 f of a point's block by LDL^T (physics.hpp explains).
vec3 vbdStep(vec3 f, vec3 h_diag, vec3 h_off) {
  precise float d0 = h_diag.x;
  if (!(d0 > 0.0)) return vec3(0.0);
  precise float l10 = h_off.x / d0;
  precise float l20 = h_off.y / d0;
  precise float d1 = h_diag.y - l10 * h_off.x;
  if (!(d1 > 0.0)) return vec3(0.0);
  precise float l21 = (h_off.z - l20 * h_off.x) / d1;
  precise float d2 = h_diag.z - l20 * h_off.y - l21 * l21 * d1;
  if (!(d2 > 0.0)) return vec3(0.0);
  precise float z0 = f.x;
  precise float z1 = f.y - l10 * z0;
  precise float z2 = f.z - l20 * z0 - l21 * z1;
  precise float x2 = z2 / d2;
  precise float x1 = z1 / d1 - l21 * x2;
  precise float x0 = z0 / d0 - l10 * x1 - l20 * x2;
  return vec3(x0, x1, x2);
}

vec3 windForce(vec3 normal, vec3 point_velocity, vec3 air_velocity, float drag_area) {
  precise float rel = dot3(air_velocity - point_velocity, normal);
  precise vec3 r = (drag_area * rel) * normal;
  return r;
}

uint hashU32(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

uint hashCell(ivec3 cell) {
  return hashU32(uint(cell.x) + hashU32(uint(cell.y) + hashU32(uint(cell.z))));
}

float quinticFade(float t) {
  precise float r = t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
  return r;
}

float noiseCorner(ivec3 cell) {
  precise float r = float(hashCell(cell) >> 8) * (1.0 / 8388608.0) - 1.0;
  return r;
}

// Value noise in [-1, 1]: lattice values from hashCell, quintic interpolation. 0 for non-finite points
// and beyond 2^30 wavelengths, where ivec3(floor(p)) is undefined (kNoiseLimit in physics.hpp).
float valueNoise(vec3 p) {
  const float kNoiseLimit = 1073741824.0;
  // isnan/isinf spelled out: a compiler may assume no NaN and turn !(a < b) into a >= b.
  if (any(isnan(p)) || any(isinf(p)) || any(greaterThanEqual(abs(p), vec3(kNoiseLimit)))) return 0.0;
  precise vec3 f = floor(p);
  ivec3 i = ivec3(f);
  precise vec3 t = p - f;
  precise vec3 u = vec3(quinticFade(t.x), quinticFade(t.y), quinticFade(t.z));
  precise float x00 = mix1(noiseCorner(i), noiseCorner(i + ivec3(1, 0, 0)), u.x);
  precise float x10 = mix1(noiseCorner(i + ivec3(0, 1, 0)), noiseCorner(i + ivec3(1, 1, 0)), u.x);
  precise float x01 = mix1(noiseCorner(i + ivec3(0, 0, 1)), noiseCorner(i + ivec3(1, 0, 1)), u.x);
  precise float x11 = mix1(noiseCorner(i + ivec3(0, 1, 1)), noiseCorner(i + ivec3(1, 1, 1)), u.x);
  precise float r = mix1(mix1(x00, x10, u.y), mix1(x01, x11, u.y), u.z);
  return r;
}

vec3 windVelocity(vec3 x, float t, vec3 velocity, float turbulence, float noise_scale, float noise_speed) {
  precise vec3 p = x / noise_scale + (t * noise_speed) * vec3(1.0, 0.37, 0.71);
  precise vec3 n = vec3(valueNoise(p), valueNoise(p + vec3(17.3, 5.1, 9.7)), valueNoise(p + vec3(3.7, 23.9, 13.1)));
  precise vec3 r = velocity + (length3(velocity) * turbulence) * n;
  return r;
}

// Normal of a grid point from its neighbours (clamped at the border), for wind.
vec3 gridNormal(vec3 left, vec3 right, vec3 down, vec3 up) {
  precise vec3 n = cross3(right - left, up - down);
  precise float len = length3(n);
  precise vec3 r = len > 0.0 ? n / len : vec3(0.0);
  return r;
}

// Self-collision skips a pair the springs hold: closer than the contact distance at rest.
bool heldAtRest(vec3 rest_i, vec3 rest_j, float range) {
  precise vec3 d = rest_i - rest_j;
  precise float d2 = dot3(d, d);
  precise float r2 = range * range;
  return d2 < r2;
}

// The face contacts with a mesh's sharp features (src/cpu/mesh_physics.hpp, which says what each does).
bool farApart(vec3 a, float ra, vec3 b, float rb, float thickness) {
  precise vec3 d = a - b;
  precise float reach = 1.1 * (ra + rb + thickness);
  precise float d2 = dot3(d, d);
  precise float reach2 = reach * reach;
  return d2 > reach2;
}

bool edgeContact(vec3 p, vec3 q, vec3 a, vec3 b, vec3 n1, vec3 n2, float thickness, out float s, out vec3 move) {
  s = 0.0;
  move = vec3(0.0);
  precise vec3 d1 = q - p, d2 = b - a, r = p - a;
  precise float aa = dot3(d1, d1), bb = dot3(d1, d2), ee = dot3(d2, d2);
  precise float cc = dot3(d1, r), ff = dot3(d2, r);
  precise vec3 normal = cross3(d1, d2);
  precise float normal2 = dot3(normal, normal);
  precise float parallel = 1e-6 * aa * ee;
  if (!(normal2 > parallel)) return false;
  precise float denom = aa * ee - bb * bb;
  precise float sc = (bb * ff - cc * ee) / denom;
  precise float t = (aa * ff - bb * cc) / denom;
  s = sc;
  if (!(sc > 0.0 && sc < 1.0 && t > 0.0 && t < 1.0)) return false;
  precise vec3 gap = (p + sc * d1) - (a + t * d2);
  if (max(dot3(gap, n1), dot3(gap, n2)) >= thickness) return false;
  precise vec3 m = normal / sqrt(normal2);
  precise vec3 out_dir = n1 + n2;
  precise float along = dot3(m, out_dir);
  precise float across = 0.01 * dot3(out_dir, out_dir);
  if (along * along < across) return false;
  if (along < 0.0) m = -m;
  precise float sep = dot3(gap, m);
  precise float deep = -0.5 * sqrt(aa);
  if (sep >= thickness || sep < deep) return false;
  precise vec3 r_move = (thickness - sep) * m;
  move = r_move;
  return true;
}

bool cornerContact(vec3 p0, vec3 p1, vec3 p2, vec3 v, vec3 nv, float thickness, out vec3 bary, out vec3 move) {
  bary = vec3(0.0);
  move = vec3(0.0);
  precise vec3 normal = cross3(p1 - p0, p2 - p0);
  precise float normal2 = dot3(normal, normal);
  if (!(normal2 > 0.0)) return false;
  precise vec3 n = normal / sqrt(normal2);
  precise float along = dot3(n, nv);
  if (along * along < 0.01) return false;
  if (along < 0.0) n = -n;
  precise float sep = dot3(p0 - v, n);
  precise float longest2 = max(max(dot3(p1 - p0, p1 - p0), dot3(p2 - p1, p2 - p1)), dot3(p0 - p2, p0 - p2));
  precise float sep4 = sep * sep * 4.0;
  if (sep >= thickness || sep4 > longest2) return false;
  precise vec3 at = v + sep * n;
  precise float b0 = dot3(cross3(p1 - at, p2 - at), normal) / normal2;
  precise float b1 = dot3(cross3(p2 - at, p0 - at), normal) / normal2;
  precise float b2 = 1.0 - b0 - b1;
  if (!(b0 > 0.0 && b1 > 0.0 && b2 > 0.0)) return false;
  bary = vec3(b0, b1, b2);
  precise vec3 r_move = (thickness - sep) * n;
  move = r_move;
  return true;
}

vec3 edgeShare(float s, bool second, vec3 move) {
  precise float w = second ? s : 1.0 - s;
  precise float sum2 = (1.0 - s) * (1.0 - s) + s * s;
  precise vec3 r = (w / sum2) * move;
  return r;
}

vec3 cornerShare(vec3 bary, int corner, vec3 move) {
  precise float b2 = dot3(bary, bary);
  precise vec3 r = (bary[corner] / b2) * move;
  return r;
}
