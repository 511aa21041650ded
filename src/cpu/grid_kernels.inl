// The grid kernels, written once over a vector type V (cpu/simd.hpp) and included by one translation unit
// per instruction set. Each lane follows the scalar code of cpu/physics.hpp operation for operation: the
// comments name the function whose arithmetic a block repeats. Nothing here may be a non-inline symbol
// shared with other units (see simd.hpp), so everything but the table at the end is in an unnamed namespace.
#include "cpu/grid_kernels.hpp"
#include "cpu/simd.hpp"

#include <cstring>

namespace drape {
namespace {

// GridShape::at, kept here: the kernels' translation units share no inline function with the rest.
std::ptrdiff_t at(const GridShape& g, int x, int y) {
  return std::ptrdiff_t(y + GridShape::kTop) * g.stride + GridShape::kLeft + x;
}

constexpr int kDx[6] = {1, 0, 1, -1, 2, 0}, kDy[6] = {0, 1, 1, 1, 0, 2};  // core/colouring.hpp, kGridDirections

template <class V>
struct Kernels {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;

  static void toSoa(const GridShape& g, const float* aos, float* x, float* y, float* z, int y0, int y1) {
    for (int row = y0; row < y1; ++row) {
      const float* src = aos + 3 * std::ptrdiff_t(row) * g.W;
      const std::ptrdiff_t q = at(g, 0, row);
      int i = 0;
      for (; i + kW <= g.W; i += kW) {
        F X, Y, Z;
        V::loadVec3(src + 3 * i, X, Y, Z);
        V::store(x + q + i, X);
        V::store(y + q + i, Y);
        V::store(z + q + i, Z);
      }
      for (; i < g.W; ++i) {
        x[q + i] = src[3 * i];
        y[q + i] = src[3 * i + 1];
        z[q + i] = src[3 * i + 2];
      }
    }
  }

  static void fromSoa(const GridShape& g, const float* x, const float* y, const float* z, float* aos, int y0, int y1) {
    for (int row = y0; row < y1; ++row) {
      float* dst = aos + 3 * std::ptrdiff_t(row) * g.W;
      const std::ptrdiff_t q = at(g, 0, row);
      int i = 0;
      for (; i + kW <= g.W; i += kW)
        V::storeVec3(dst + 3 * i, V::load(x + q + i), V::load(y + q + i), V::load(z + q + i));
      for (; i < g.W; ++i) {
        dst[3 * i] = x[q + i];
        dst[3 * i + 1] = y[q + i];
        dst[3 * i + 2] = z[q + i];
      }
    }
  }

  // Lanes whose point x + offset lies on the grid (lane x coordinates in xs, exact small integers).
  static F onGrid(F xs, int offset, int w) {
    return V::bitAnd(V::le(V::set1(float(-offset)), xs), V::lt(xs, V::set1(float(w - offset))));
  }

  // f += springForce(x_i, x_other, rest, k) (cpu/physics.hpp) in the lanes of `exists`; the others keep f.
  static void addSpring(const GridForceArgs& a, std::ptrdiff_t rest_at, std::ptrdiff_t other, const float* rest, F k,
                        F exists, F X, F Y, F Z, F& fx, F& fy, F& fz) {
    const F dx = V::sub(V::load(a.x + other), X);
    const F dy = V::sub(V::load(a.y + other), Y);
    const F dz = V::sub(V::load(a.z + other), Z);
    const F len = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
    const F s = V::div(V::mul(k, V::sub(len, V::load(rest + rest_at))), len);
    const F zero = V::set1(0.0f), none = V::le(len, zero);  // springForce returns vec3(0) there, and f adds it
    fx = V::select(exists, V::add(fx, V::select(none, zero, V::mul(s, dx))), fx);
    fy = V::select(exists, V::add(fy, V::select(none, zero, V::mul(s, dy))), fy);
    fz = V::select(exists, V::add(fz, V::select(none, zero, V::mul(s, dz))), fz);
  }

  static void forces(const GridForceArgs& a, int y0, int y1) {
    const GridShape& g = a.shape;
    const F gx = V::set1(a.gravity[0]), gy = V::set1(a.gravity[1]), gz = V::set1(a.gravity[2]);
    for (int row = y0; row < y1; ++row)
      for (int x0 = 0; x0 < g.W; x0 += kW) {
        const std::ptrdiff_t q = at(g, x0, row);
        const F X = V::load(a.x + q), Y = V::load(a.y + q), Z = V::load(a.z + q);
        const F m = V::load(a.mass + q);
        F fx = V::mul(gx, m), fy = V::mul(gy, m), fz = V::mul(gz, m);  // gravity * mass
        const F xs = V::add(V::set1(float(x0)), V::iota());
        // Per direction, in the adjacency's order: the spring that ends at the point, then the one that
        // starts there (both ascending spring index, core/topology.cpp).
        for (int d = 0; d < 6; ++d) {
          if (!a.springs.enabled[d]) continue;
          const F k = V::set1(a.springs.k[d]);
          const std::ptrdiff_t offset = kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
          if (row - kDy[d] >= 0)
            addSpring(a, q - offset, q - offset, a.springs.rest[d], k, onGrid(xs, -kDx[d], g.W), X, Y, Z, fx, fy, fz);
          if (row + kDy[d] < g.H)
            addSpring(a, q, q + offset, a.springs.rest[d], k, onGrid(xs, kDx[d], g.W), X, Y, Z, fx, fy, fz);
        }
        float* out = a.forces + 3 * (std::ptrdiff_t(row) * g.W + x0);
        if (x0 + kW <= g.W) {
          V::storeVec3(out, fx, fy, fz);
        } else {
          float tmp[3 * kW];
          V::storeVec3(tmp, fx, fy, fz);
          std::memcpy(out, tmp, sizeof(float) * 3 * std::size_t(g.W - x0));
        }
      }
  }

  struct End {
    F x, y, z, vx, vy, vz, pinned;
  };

  // One lane per spring a-b of the colour (valid lanes only): Provot's correction as limitStretchColoured
  // computes it, both ends moved at once. stretchShare, stretchCorrection (cpu/physics.hpp) lane by lane:
  // ca = (share_a (len - max) / len) d with d = x_b - x_a; cb = -ca where the shares are equal, else the
  // same expression seen from b, whose d is exactly -d. A spring within the limit gives +0 (and -ca = -0),
  // which is still added, as the scalar code adds it.
  static void limitSprings(End& a, End& b, F rest, F limit, F valid, bool displacements) {
    const F dx = V::sub(b.x, a.x), dy = V::sub(b.y, a.y), dz = V::sub(b.z, a.z);
    const F len = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
    const F max_len = V::mul(limit, rest);
    const F within = V::le(len, max_len);
    const F excess = V::sub(len, max_len);
    const F zero = V::set1(0.0f), one = V::set1(1.0f), half = V::set1(0.5f);
    const F share_a = V::select(a.pinned, zero, V::select(b.pinned, one, half));
    const F share_b = V::select(b.pinned, zero, V::select(a.pinned, one, half));
    const F qa = V::div(V::mul(share_a, excess), len);
    const F qb = V::div(V::mul(share_b, excess), len);
    const F same = V::eq(share_a, share_b);
    const F cax = V::select(within, zero, V::mul(qa, dx));
    const F cay = V::select(within, zero, V::mul(qa, dy));
    const F caz = V::select(within, zero, V::mul(qa, dz));
    const F cbx = V::select(same, V::neg(cax), V::select(within, zero, V::mul(qb, V::neg(dx))));
    const F cby = V::select(same, V::neg(cay), V::select(within, zero, V::mul(qb, V::neg(dy))));
    const F cbz = V::select(same, V::neg(caz), V::select(within, zero, V::mul(qb, V::neg(dz))));
    const F move_a = V::andNot(a.pinned, valid), move_b = V::andNot(b.pinned, valid);
    a.x = V::select(move_a, V::add(a.x, cax), a.x);
    a.y = V::select(move_a, V::add(a.y, cay), a.y);
    a.z = V::select(move_a, V::add(a.z, caz), a.z);
    b.x = V::select(move_b, V::add(b.x, cbx), b.x);
    b.y = V::select(move_b, V::add(b.y, cby), b.y);
    b.z = V::select(move_b, V::add(b.z, cbz), b.z);
    if (!displacements) return;  // x_prev stays where it was: v takes the same corrections
    a.vx = V::select(move_a, V::add(a.vx, cax), a.vx);
    a.vy = V::select(move_a, V::add(a.vy, cay), a.vy);
    a.vz = V::select(move_a, V::add(a.vz, caz), a.vz);
    b.vx = V::select(move_b, V::add(b.vx, cbx), b.vx);
    b.vy = V::select(move_b, V::add(b.vy, cby), b.vy);
    b.vz = V::select(move_b, V::add(b.vz, cbz), b.vz);
  }

  static End loadEnd(const GridStretchArgs& a, std::ptrdiff_t q, bool displacements) {
    End e{V::load(a.x + q), V::load(a.y + q), V::load(a.z + q), {}, {}, {}, V::load(a.pinned + q)};
    if (displacements) {
      e.vx = V::load(a.vx + q);
      e.vy = V::load(a.vy + q);
      e.vz = V::load(a.vz + q);
    }
    return e;
  }
  static void storeEnd(const GridStretchArgs& a, std::ptrdiff_t q, const End& e, bool displacements) {
    V::store(a.x + q, e.x);
    V::store(a.y + q, e.y);
    V::store(a.z + q, e.z);
    if (!displacements) return;
    V::store(a.vx + q, e.vx);
    V::store(a.vy + q, e.vy);
    V::store(a.vz + q, e.vz);
  }

  // A colour of a vertical or diagonal direction: the springs from row y to row y + dy, one per point of a
  // run of row y, so the a ends are consecutive and so are the b ends.
  static void rowColour(const GridStretchArgs& a, int d, int row, bool displacements) {
    const GridShape& g = a.shape;
    const int x_first = kDx[d] < 0 ? -kDx[d] : 0, x_end = kDx[d] > 0 ? g.W - kDx[d] : g.W;
    const std::ptrdiff_t offset = kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
    const F limit = V::set1(a.limit);
    for (int x0 = x_first; x0 < x_end; x0 += kW) {
      const std::ptrdiff_t q = at(g, x0, row);
      const F valid = V::lt(V::add(V::set1(float(x0)), V::iota()), V::set1(float(x_end)));
      End ea = loadEnd(a, q, displacements), eb = loadEnd(a, q + offset, displacements);
      limitSprings(ea, eb, V::load(a.springs.rest[d] + q), limit, valid, displacements);
      storeEnd(a, q, ea, displacements);
      storeEnd(a, q + offset, eb, displacements);
    }
  }

  // A colour of a horizontal direction: along a row the a and b ends alternate, one by one (structural,
  // dx = 1) or two by two (bending, dx = 2). 2 kW consecutive points are loaded and split into a vector of
  // a ends and one of b ends, then put back.
  template <bool kPairs>
  static void split(F lo, F hi, F& ea, F& eb) {
    ea = kPairs ? V::pairsA(lo, hi) : V::evens(lo, hi);
    eb = kPairs ? V::pairsB(lo, hi) : V::odds(lo, hi);
  }
  template <bool kPairs>
  static void join(F ea, F eb, float* p) {
    F lo, hi;
    if (kPairs)
      V::interleavePairs(ea, eb, lo, hi);
    else
      V::interleave(ea, eb, lo, hi);
    V::store(p, lo);
    V::store(p + kW, hi);
  }
  template <bool kPairs>
  static void splitArray(const float* p, F& ea, F& eb) {
    split<kPairs>(V::load(p), V::load(p + kW), ea, eb);
  }

  template <bool kPairs>
  static void alternatingColour(const GridStretchArgs& a, int d, int parity, int row, bool displacements) {
    const GridShape& g = a.shape;
    const int dx = kDx[d];
    const F limit = V::set1(a.limit);
    F lane_lo = V::iota(), lane_hi = V::add(V::iota(), V::set1(float(kW))), lane_a, lane_b;
    split<kPairs>(lane_lo, lane_hi, lane_a, lane_b);
    for (int x0 = dx * parity; x0 + dx < g.W; x0 += 2 * kW) {
      const std::ptrdiff_t q = at(g, x0, row);
      const F valid = V::lt(V::add(V::set1(float(x0)), lane_a), V::set1(float(g.W - dx)));
      End ea, eb;
      F rest, unused;
      splitArray<kPairs>(a.x + q, ea.x, eb.x);
      splitArray<kPairs>(a.y + q, ea.y, eb.y);
      splitArray<kPairs>(a.z + q, ea.z, eb.z);
      splitArray<kPairs>(a.pinned + q, ea.pinned, eb.pinned);
      splitArray<kPairs>(a.springs.rest[d] + q, rest, unused);
      if (displacements) {
        splitArray<kPairs>(a.vx + q, ea.vx, eb.vx);
        splitArray<kPairs>(a.vy + q, ea.vy, eb.vy);
        splitArray<kPairs>(a.vz + q, ea.vz, eb.vz);
      }
      limitSprings(ea, eb, rest, limit, valid, displacements);
      join<kPairs>(ea.x, eb.x, a.x + q);
      join<kPairs>(ea.y, eb.y, a.y + q);
      join<kPairs>(ea.z, eb.z, a.z + q);
      if (displacements) {
        join<kPairs>(ea.vx, eb.vx, a.vx + q);
        join<kPairs>(ea.vy, eb.vy, a.vy + q);
        join<kPairs>(ea.vz, eb.vz, a.vz + q);
      }
    }
  }

  // Colour 2 d + parity (core/colouring.hpp, colourGridSprings): the springs of direction d whose start's
  // coordinate along it (x for horizontal directions, else y; halved for bending) has that parity.
  static void stretchColour(const GridStretchArgs& a, int d, int parity, int y0, int y1) {
    const bool displacements = a.vx != nullptr;
    for (int row = y0; row < y1; ++row) {
      if (kDy[d] == 0) {
        if (d == 0)
          alternatingColour<false>(a, d, parity, row, displacements);
        else
          alternatingColour<true>(a, d, parity, row, displacements);
        continue;
      }
      const int along = kDy[d] == 2 ? row / 2 : row;
      if (along % 2 == parity && row + kDy[d] < a.shape.H) rowColour(a, d, row, displacements);
    }
  }

  static void integrate(float* x, float* v, const float* f, const float* inv_mass3, const float* pinned3, float dt2,
                        float keep, long long first, long long last) {
    const F dt2v = V::set1(dt2), keepv = V::set1(keep), zero = V::set1(0.0f);
    long long e = first;
    for (; e + kW <= last; e += kW) {
      const F pinned = V::load(pinned3 + e), xe = V::load(x + e);
      // keep * v + (f * (1/m)) * dt^2, as integrateVerlet computes each coordinate
      const F ve = V::add(V::mul(keepv, V::load(v + e)), V::mul(V::mul(V::load(f + e), V::load(inv_mass3 + e)), dt2v));
      V::store(v + e, V::select(pinned, zero, ve));
      V::store(x + e, V::select(pinned, xe, V::add(xe, ve)));
    }
    for (; e < last; ++e) {
      if (pinned3[e] != pinned3[e]) {  // all bits set is a NaN
        v[e] = 0.0f;
        continue;
      }
      v[e] = keep * v[e] + f[e] * inv_mass3[e] * dt2;
      x[e] += v[e];
    }
  }

  static bool anyInRange(const float* x, const std::uint32_t* begin, const std::uint32_t* end, std::size_t i,
                         float thickness) {
    const float range = 2.0f * thickness;  // selfCollisionCorrection's range * range, in its order
    if (end - begin < 4) {                 // a gather costs more than a few scalar tests
      const float r2 = range * range, px = x[3 * i], py = x[3 * i + 1], pz = x[3 * i + 2];
      for (const std::uint32_t* p = begin; p < end; ++p) {
        const float dx = px - x[3 * std::size_t(*p)], dy = py - x[3 * std::size_t(*p) + 1],
                    dz = pz - x[3 * std::size_t(*p) + 2];
        const float d2 = dx * dx + dy * dy + dz * dz;
        if (!(d2 >= r2 || d2 <= 0.0f)) return true;
      }
      return false;
    }
    const F range2 = V::set1(range * range), zero = V::set1(0.0f);
    const F xi = V::set1(x[3 * i]), yi = V::set1(x[3 * i + 1]), zi = V::set1(x[3 * i + 2]);
    for (const std::uint32_t* p = begin; p < end; p += kW) {
      F gx, gy, gz, live;
      V::gatherVec3(x, p, int(end - p < kW ? end - p : kW), gx, gy, gz, live);
      const F dx = V::sub(xi, gx), dy = V::sub(yi, gy), dz = V::sub(zi, gz);
      const F dist2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
      // Not (dist2 >= range^2 or dist2 <= 0): a NaN distance is a term there too.
      if (V::any(V::andNot(V::bitOr(V::ge(dist2, range2), V::le(dist2, zero)), live))) return true;
    }
    return false;
  }

  static void stencilFlags(const GridStencilArgs& a, int y0, int y1) {
    const GridShape& g = a.shape;
    const F r2 = V::set1(a.range2);
    for (int v = y0; v < y1; ++v)
      for (int u0 = 0; u0 < g.W; u0 += kW) {
        const std::ptrdiff_t q = at(g, u0, v);
        const F X = V::load(a.x + q), Y = V::load(a.y + q), Z = V::load(a.z + q);
        const F us = V::add(V::set1(float(u0)), V::iota());
        const F own = V::lt(us, V::set1(float(g.W)));
        std::uint8_t* mine = a.flags + std::ptrdiff_t(v) * g.W + u0;
        F hit = V::set1(0.0f);
        for (int k = 0; k < a.count; ++k) {
          if (v + a.dv[k] < 0 || v + a.dv[k] >= g.H) continue;
          // The padding keeps every partner load inside the arrays (|du| <= kMaxStencilBox < 2 rows)
          const std::ptrdiff_t p = q + std::ptrdiff_t(a.dv[k]) * g.stride + a.du[k];
          const F dx = V::sub(X, V::load(a.x + p)), dy = V::sub(Y, V::load(a.y + p)), dz = V::sub(Z, V::load(a.z + p));
          const F d2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
          F pair = V::bitAnd(onGrid(us, a.du[k], g.W), V::andNot(V::ge(d2, r2), own));
          if (a.mixed[k] && V::any(pair)) {  // heldAtRest(rest_i, rest_j, range): d . d < range^2
            const F ex = V::sub(V::load(a.rx + q), V::load(a.rx + p)),
                    ey = V::sub(V::load(a.ry + q), V::load(a.ry + p)),
                    ez = V::sub(V::load(a.rz + q), V::load(a.rz + p));
            const F e2 = V::add(V::add(V::mul(ex, ex), V::mul(ey, ey)), V::mul(ez, ez));
            pair = V::andNot(V::lt(e2, r2), pair);
          }
          if (int bits = V::bits(pair); bits != 0) {
            std::uint8_t* theirs = mine + std::ptrdiff_t(a.dv[k]) * g.W + a.du[k];
            for (; bits != 0; bits &= bits - 1)
              __atomic_fetch_or(theirs + __builtin_ctz(unsigned(bits)), std::uint8_t(1), __ATOMIC_RELAXED);
          }
          hit = V::bitOr(hit, pair);
        }
        for (int bits = V::bits(hit); bits != 0; bits &= bits - 1)
          __atomic_fetch_or(mine + __builtin_ctz(unsigned(bits)), std::uint8_t(1), __ATOMIC_RELAXED);
      }
  }

  static long long collideObjects(const CollideArgs& a, long long first, long long last) {
    const F zero = V::set1(0.0f), one = V::set1(1.0f), all = V::eq(zero, zero);
    long long i = first;
    for (; i + kW <= last; i += kW) {
      F X, Y, Z, VX, VY, VZ;
      V::loadVec3(a.x + 3 * i, X, Y, Z);
      V::loadVec3(a.v + 3 * i, VX, VY, VZ);
      const F free = V::andNot(V::load(a.pinned + i), all);
      F moved = zero;
      // c is added to x and to v where `hit` (collidePoint: x += c, v += c)
      const auto apply = [&](F hit, F cx, F cy, F cz) {
        X = V::select(hit, V::add(X, cx), X);
        Y = V::select(hit, V::add(Y, cy), Y);
        Z = V::select(hit, V::add(Z, cz), Z);
        VX = V::select(hit, V::add(VX, cx), VX);
        VY = V::select(hit, V::add(VY, cy), VY);
        VZ = V::select(hit, V::add(VZ, cz), VZ);
        moved = V::bitOr(moved, hit);
      };
      // frictionCorrection(t, v, f) = (1 - f) t - f v
      const auto friction = [&](F f, F tx, F ty, F tz, F& cx, F& cy, F& cz) {
        const F keep = V::sub(one, f);
        cx = V::sub(V::mul(keep, tx), V::mul(f, VX));
        cy = V::sub(V::mul(keep, ty), V::mul(f, VY));
        cz = V::sub(V::mul(keep, tz), V::mul(f, VZ));
      };
      for (int s = 0; s < a.sphere_count; ++s) {  // collideSphere
        const float* o = a.spheres + 5 * s;
        const F r = V::set1(o[3]);
        const F dx = V::sub(X, V::set1(o[0])), dy = V::sub(Y, V::set1(o[1])), dz = V::sub(Z, V::set1(o[2]));
        const F dist = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
        const F hit = V::andNot(V::lt(r, dist), free);  // not (dist > radius)
        if (!V::any(hit)) continue;
        const F up = V::lt(zero, dist);  // dist > 0: d / dist, else (0, 1, 0)
        const F ux = V::select(up, V::div(dx, dist), zero), uy = V::select(up, V::div(dy, dist), one),
                uz = V::select(up, V::div(dz, dist), zero);
        const F depth = V::sub(r, dist);
        F cx, cy, cz;
        friction(V::set1(o[4]), V::mul(depth, ux), V::mul(depth, uy), V::mul(depth, uz), cx, cy, cz);
        apply(hit, cx, cy, cz);
      }
      for (int p = 0; p < a.plane_count; ++p) {  // collidePlane
        const float* o = a.planes + 7 * p;
        const F nx = V::set1(o[3]), ny = V::set1(o[4]), nz = V::set1(o[5]);
        const F dx = V::add(V::add(V::mul(V::sub(X, V::set1(o[0])), nx), V::mul(V::sub(Y, V::set1(o[1])), ny)),
                            V::mul(V::sub(Z, V::set1(o[2])), nz));
        const F vn = V::add(V::add(V::mul(VX, nx), V::mul(VY, ny)), V::mul(VZ, nz));
        const F above = V::ge(V::sub(dx, vn), V::neg(V::set1(a.plane_epsilon)));
        const F crossed = V::bitOr(V::bitAnd(above, V::le(dx, zero)), V::andNot(above, V::ge(dx, zero)));
        const F hit = V::bitAnd(crossed, free);
        if (!V::any(hit)) continue;
        // vn != 0: -clamp(dx / vn, 0, 1) v; else -dx n
        F t = V::div(dx, vn);
        t = V::select(V::lt(t, zero), zero, t);
        t = V::neg(V::select(V::lt(one, t), one, t));
        const F along = V::eq(vn, zero), ndx = V::neg(dx);
        F tx = V::select(along, V::mul(ndx, nx), V::mul(t, VX));
        F ty = V::select(along, V::mul(ndx, ny), V::mul(t, VY));
        F tz = V::select(along, V::mul(ndx, nz), V::mul(t, VZ));
        const F offset = V::select(above, V::set1(a.surface_offset), V::neg(V::set1(a.surface_offset)));
        tx = V::add(tx, V::mul(offset, nx));
        ty = V::add(ty, V::mul(offset, ny));
        tz = V::add(tz, V::mul(offset, nz));
        F cx, cy, cz;
        friction(V::set1(o[6]), tx, ty, tz, cx, cy, cz);
        apply(hit, cx, cy, cz);
      }
      if (V::any(moved)) {
        V::storeVec3(a.x + 3 * i, X, Y, Z);
        V::storeVec3(a.v + 3 * i, VX, VY, VZ);
      }
    }
    return i;
  }

  static bool tileBoxes(const TileBoxArgs& a) {
    const std::ptrdiff_t n = std::ptrdiff_t(a.w) * a.h;
    const float inf = __builtin_inff();
    const F big = V::set1(inf), small = V::set1(-inf);
    F finite = V::eq(big, big);
    bool finite_tail = true;
    for (int tv = a.tv0; tv < a.tv1 && tv * a.edge < a.h; ++tv)
      for (int tu = 0; tu * a.edge < a.w; ++tu) {
        const int u0 = tu * a.edge, u1 = u0 + a.edge < a.w ? u0 + a.edge : a.w;
        const int v0 = tv * a.edge, v1 = v0 + a.edge < a.h ? v0 + a.edge : a.h;
        F box[12] = {big, big, big, small, small, small, big, big, big, small, small, small};
        float tail[12] = {inf, inf, inf, -inf, -inf, -inf, inf, inf, inf, -inf, -inf, -inf};
        for (int v = v0; v < v1; ++v)
          for (int u = u0; u < u1; u += kW) {
            const std::ptrdiff_t i = std::ptrdiff_t(v) * a.w + u;
            const int lanes = u1 - u < kW ? u1 - u : kW;
            if (i + kW > n) {  // the loads would leave the arrays
              for (int l = 0; l < lanes; ++l)
                for (int c = 0; c < 3; ++c) {
                  const float p = a.x[3 * (i + l) + c], d = p - a.anchor[3 * (i + l) + c];
                  finite_tail = finite_tail && d - d == 0.0f;
                  tail[c] = d < tail[c] ? d : tail[c];
                  tail[3 + c] = d > tail[3 + c] ? d : tail[3 + c];
                  tail[6 + c] = p < tail[6 + c] ? p : tail[6 + c];
                  tail[9 + c] = p > tail[9 + c] ? p : tail[9 + c];
                }
              continue;
            }
            F P[3], A[3];
            V::loadVec3(a.x + 3 * i, P[0], P[1], P[2]);
            V::loadVec3(a.anchor + 3 * i, A[0], A[1], A[2]);
            const F live = V::lt(V::iota(), V::set1(float(lanes)));
            for (int c = 0; c < 3; ++c) {
              const F d = V::sub(P[c], A[c]);
              finite =
                  V::bitAnd(finite, V::bitOr(V::eq(V::sub(d, d), V::set1(0.0f)), V::andNot(live, V::eq(big, big))));
              box[c] = V::select(live, V::min(box[c], d), box[c]);
              box[3 + c] = V::select(live, V::max(box[3 + c], d), box[3 + c]);
              box[6 + c] = V::select(live, V::min(box[6 + c], P[c]), box[6 + c]);
              box[9 + c] = V::select(live, V::max(box[9 + c], P[c]), box[9 + c]);
            }
          }
        float* out = a.out + 12 * (std::ptrdiff_t(tv) * a.across + tu);
        for (int k = 0; k < 12; ++k) {
          float lanes[kW];
          V::store(lanes, box[k]);
          float r = tail[k];
          for (float l : lanes)
            r = (k / 3) % 2 == 0 ? (l < r ? l : r) : (l > r ? l : r);
          out[k] = r;
        }
      }
    return finite_tail && V::bits(finite) == (1 << kW) - 1;
  }

  static bool scanOne(const PairScanArgs& a, std::uint32_t s) {
    const float dx = a.px - a.x[s], dy = a.py - a.y[s], dz = a.pz - a.z[s];
    if (!(dx * dx + dy * dy + dz * dz < a.reach2)) return false;
    const float du = a.u[s] - a.pu, dv = a.v[s] - a.pv;
    const float nominal = du * du * a.a2 + dv * dv * a.b2;
    return !(nominal < a.near_below);
  }

  static int scanPairs(const PairScanArgs& a, std::uint32_t first, std::uint32_t last, std::uint32_t* out) {
    int count = 0;
    std::uint32_t s = first;
    const F px = V::set1(a.px), py = V::set1(a.py), pz = V::set1(a.pz), pu = V::set1(a.pu), pv = V::set1(a.pv);
    const F reach2 = V::set1(a.reach2), a2 = V::set1(a.a2), b2 = V::set1(a.b2);
    const F near_below = V::set1(a.near_below);
    for (; s + kW <= last; s += kW) {
      const F dx = V::sub(px, V::load(a.x + s)), dy = V::sub(py, V::load(a.y + s)), dz = V::sub(pz, V::load(a.z + s));
      const F d2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
      const F du = V::sub(V::load(a.u + s), pu), dv = V::sub(V::load(a.v + s), pv);
      const F nominal = V::add(V::mul(V::mul(du, du), a2), V::mul(V::mul(dv, dv), b2));
      int bits = V::bits(V::andNot(V::lt(nominal, near_below), V::lt(d2, reach2)));
      while (bits != 0) {
        const int l = __builtin_ctz(unsigned(bits));
        bits &= bits - 1;
        out[count++] = s + std::uint32_t(l);
      }
    }
    for (; s < last; ++s)
      if (scanOne(a, s)) out[count++] = s;
    return count;
  }

  static float sum(F v) {
    float lanes[kW];
    V::store(lanes, v);
    float s = 0;
    for (float l : lanes)
      s += l;
    return s;
  }

  static float probeAddMul(long long reps) {
    const F m = V::set1(0.9999999f), c = V::set1(1e-7f);
    F p0 = V::set1(1.0f), p1 = V::set1(1.1f), p2 = V::set1(1.2f), p3 = V::set1(1.3f), p4 = V::set1(1.4f),
      p5 = V::set1(1.5f);
    F s0 = V::set1(0.0f), s1 = s0, s2 = s0, s3 = s0, s4 = s0, s5 = s0;
    for (long long r = 0; r < reps; ++r) {
      p0 = V::mul(p0, m);
      s0 = V::add(s0, c);
      p1 = V::mul(p1, m);
      s1 = V::add(s1, c);
      p2 = V::mul(p2, m);
      s2 = V::add(s2, c);
      p3 = V::mul(p3, m);
      s3 = V::add(s3, c);
      p4 = V::mul(p4, m);
      s4 = V::add(s4, c);
      p5 = V::mul(p5, m);
      s5 = V::add(s5, c);
    }
    return sum(V::add(V::add(V::add(p0, p1), V::add(p2, p3)), V::add(V::add(p4, p5), V::add(s0, s5)))) +
           sum(V::add(V::add(s1, s2), V::add(s3, s4)));
  }

  static float probeDivSqrt(long long reps) {
    const F c = V::set1(1.5f);
    F r0 = V::set1(2.0f), r1 = V::set1(3.0f), r2 = V::set1(4.0f), r3 = V::set1(5.0f);
    F q0 = V::set1(1.1f), q1 = V::set1(1.2f), q2 = V::set1(1.3f), q3 = V::set1(1.4f);
    for (long long r = 0; r < reps; ++r) {
      r0 = V::sqrt(r0);
      q0 = V::div(c, q0);
      r1 = V::sqrt(r1);
      q1 = V::div(c, q1);
      r2 = V::sqrt(r2);
      q2 = V::div(c, q2);
      r3 = V::sqrt(r3);
      q3 = V::div(c, q3);
    }
    return sum(V::add(V::add(V::add(r0, r1), V::add(r2, r3)), V::add(V::add(q0, q1), V::add(q2, q3))));
  }

  static void probeTriad(float* a, const float* b, const float* c, long long n, float s) {
    const F sv = V::set1(s);
    for (long long i = 0; i < n; i += kW)
      V::store(a + i, V::add(V::load(b + i), V::mul(sv, V::load(c + i))));
  }

  static constexpr GridKernels table(const char* name) {
    return {
        name,          kW,         &toSoa,          &fromSoa,   &forces,      &stretchColour, &integrate, &anyInRange,
        &stencilFlags, &scanPairs, &collideObjects, &tileBoxes, &probeAddMul, &probeDivSqrt,  &probeTriad};
  }
};

}  // namespace
}  // namespace drape
