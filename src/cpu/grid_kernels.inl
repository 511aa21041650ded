// The grid kernels, written once over a vector type V (cpu/simd.hpp) and included by one translation unit
// per instruction set. Each lane follows the scalar code of cpu/physics.hpp operation for operation: the
// comments name the function whose arithmetic a block repeats. Nothing here may be a non-inline symbol
// shared with other units (see simd.hpp), so everything but the table at the end is in an unnamed namespace.
// The forces and integration are here; the stretch limit's and XPBD's colours in cpu/grid_kernels_colours.inl,
// self-collision's and the collisions' kernels in cpu/grid_kernels_contact.inl, VBD's in cpu/grid_kernels_vbd.inl,
// the machine probes in cpu/grid_kernels_probes.inl, which this file includes.
#include "cpu/grid_kernels.hpp"
#include "cpu/simd.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace drape {
namespace {

// GridShape::at, kept here: the kernels' translation units share no inline function with the rest.
std::ptrdiff_t at(const GridShape& g, int x, int y) {
  return std::ptrdiff_t(y + GridShape::kTop) * g.stride + GridShape::kLeft + x;
}

constexpr int kDx[6] = {1, 0, 1, -1, 2, 0}, kDy[6] = {0, 1, 1, 1, 0, 2};  // core/topology.hpp, kGridDirections

// What every kernel's lanes share: the vector type, its width and two helpers.
template <class V>
struct Lanes {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;

  // Lanes whose point x + offset lies on the grid (lane x coordinates in xs, exact small integers).
  static F onGrid(F xs, int offset, int w) {
    return V::bitAnd(V::le(V::set1(float(-offset)), xs), V::lt(xs, V::set1(float(w - offset))));
  }

  static float sum(F v) {
    float lanes[kW];
    V::store(lanes, v);
    float s = 0;
    for (float l : lanes)
      s += l;
    return s;
  }
};

}  // namespace
}  // namespace drape

#include "cpu/grid_kernels_colours.inl"
#include "cpu/grid_kernels_contact.inl"
#include "cpu/grid_kernels_probes.inl"
#include "cpu/grid_kernels_stencil.inl"
#include "cpu/grid_kernels_vbd.inl"

namespace drape {
namespace {

template <class V>
struct Kernels : Lanes<V> {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;
  using Lanes<V>::onGrid;
  using Lanes<V>::sum;
  using Contact = ContactKernels<V>;
  using Vbd = VbdKernels<V>;
  using Probes = ProbeKernels<V>;
  using Colours = ColourKernels<V>;

  static void toSoa(const GridShape& g, const float* aos, float* x, float* y, float* z, int y0, int y1,
                    std::uint8_t* signed_rows) {
    for (int row = y0; row < y1; ++row) {
      const float* src = aos + 3 * std::ptrdiff_t(row) * g.W;
      const std::ptrdiff_t q = at(g, 0, row);
      F negative_zero = V::set1(0.0f);
      int i = 0;
      for (; i + kW <= g.W; i += kW) {
        F X, Y, Z;
        V::loadVec3(src + 3 * i, X, Y, Z);
        V::store(x + q + i, X);
        V::store(y + q + i, Y);
        V::store(z + q + i, Z);
        if (signed_rows)
          negative_zero = V::bitOr(negative_zero, V::bitOr(V::negZero(X), V::bitOr(V::negZero(Y), V::negZero(Z))));
      }
      bool tail_zero = false;
      for (; i < g.W; ++i) {
        x[q + i] = src[3 * i];
        y[q + i] = src[3 * i + 1];
        z[q + i] = src[3 * i + 2];
        for (int c = 0; c < 3; ++c)
          tail_zero = tail_zero || (src[3 * i + c] == 0.0f && std::signbit(src[3 * i + c]));
      }
      if (signed_rows && (tail_zero || V::any(negative_zero))) signed_rows[row] = 1;
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

  // A spring's factor s = k (len - rest) / len and its length (springForce, cpu/physics.hpp), computed once
  // from its start a and used by both ends: each end's d is the other end less itself (at b exactly -d of a,
  // or +0 for +0), so len, s and the term s d are bit for bit what springForce gives from that end.
  // Per thread, three rows of them (a spring ends at most two rows below its start), each row of each
  // direction kPad floats ahead of x = 0 (a spring may start two columns to the left of its end).
  static constexpr int kPad = 8;
  struct SpringRows {
    std::vector<float> data;
    int row_floats = 0;
    bool degenerate[3] = {};  // per row (of the three): some spring there has len <= 0, whose term is vec3(0)
    float* s(int row, int d) {
      return data.data() + std::size_t((row % 3) * 12 + 2 * d) * std::size_t(row_floats) + kPad;
    }
    float* len(int row, int d) { return s(row, d) + row_floats; }
  };

  static void springRow(const GridForceArgs& a, int row, SpringRows& rows) {
    const GridShape& g = a.shape;
    const F zero = V::set1(0.0f);
    F degenerate = zero;
    for (int d = 0; d < 6; ++d) {
      if (!a.springs.enabled[d] || row + kDy[d] >= g.H) continue;
      const F k = V::set1(a.springs.k[d]);
      const std::ptrdiff_t offset = kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
      float *s_out = rows.s(row, d), *len_out = rows.len(row, d);
      for (int x0 = 0; x0 < g.W; x0 += kW) {
        const std::ptrdiff_t q = at(g, x0, row);
        const F dx = V::sub(V::load(a.x + q + offset), V::load(a.x + q));
        const F dy = V::sub(V::load(a.y + q + offset), V::load(a.y + q));
        const F dz = V::sub(V::load(a.z + q + offset), V::load(a.z + q));
        // The row's last vector: the divider only for the lanes on the grid (the padding holds anything)
        const int lanes = std::min(kW, g.W - x0);
        const F len = V::sqrtFirst(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)), lanes);
        V::store(s_out + x0, V::divFirst(V::mul(k, V::sub(len, V::load(a.springs.rest[d] + q))), len, lanes));
        V::store(len_out + x0, len);
        F none = V::le(len, zero);
        if (x0 < 2 || x0 + kW + 2 > g.W)  // only the lanes of springs on the grid: the padding holds anything
          none = V::bitAnd(none, V::bitAnd(onGrid(V::add(V::set1(float(x0)), V::iota()), kDx[d], g.W),
                                           V::lt(V::add(V::set1(float(x0)), V::iota()), V::set1(float(g.W)))));
        degenerate = V::bitOr(degenerate, none);
      }
    }
    rows.degenerate[row % 3] = V::any(degenerate);
  }

  // f += springForce(x_i, x_other, rest, k) in the lanes of `exists` (the others keep f), from the spring's
  // s and len. kEvery: every lane's spring exists (a vector away from the grid's sides), so no mask.
  // kDegenerate: a spring of these rows may have len <= 0 (springRow knows), where springForce returns
  // vec3(0); the rest need not read len.
  template <bool kEvery, bool kDegenerate>
  static void addSpring(const GridForceArgs& a, std::ptrdiff_t other, const float* s_at, const float* len_at, F exists,
                        F X, F Y, F Z, F& fx, F& fy, F& fz) {
    const F dx = V::sub(V::load(a.x + other), X);
    const F dy = V::sub(V::load(a.y + other), Y);
    const F dz = V::sub(V::load(a.z + other), Z);
    const F s = V::load(s_at);
    F tx, ty, tz;
    if constexpr (kDegenerate) {
      const F none = V::le(V::load(len_at), V::set1(0.0f));  // +0 there: the bits of 0.0f
      tx = V::add(fx, V::andNot(none, V::mul(s, dx)));
      ty = V::add(fy, V::andNot(none, V::mul(s, dy)));
      tz = V::add(fz, V::andNot(none, V::mul(s, dz)));
    } else {
      tx = V::add(fx, V::mul(s, dx));
      ty = V::add(fy, V::mul(s, dy));
      tz = V::add(fz, V::mul(s, dz));
    }
    fx = kEvery ? tx : V::select(exists, tx, fx);
    fy = kEvery ? ty : V::select(exists, ty, fy);
    fz = kEvery ? tz : V::select(exists, tz, fz);
  }

  // A row's springs in the order a point adds them: per direction, in the adjacency's order, the spring that
  // ends at the point and then the one that starts there (both ascending spring index, core/topology.cpp).
  // Each as where its partner is and where its s and len are at x = 0 of the row, worked out once a row: a
  // vector at a time they were a third of the kernel's instructions (a modulo and products a spring, reloaded
  // after each store, which may alias anything).
  struct Term {
    std::ptrdiff_t other;  // the partner's padded index less the point's
    const float *s, *len;  // add x0
    int du;                // the partner's column less the point's
  };
  struct RowTerms {
    Term term[12];
    int count = 0;
  };

  static void rowTerms(const GridForceArgs& a, SpringRows& rows, int row, RowTerms& out) {
    const GridShape& g = a.shape;
    out.count = 0;
    for (int d = 0; d < 6; ++d) {
      if (!a.springs.enabled[d]) continue;
      const std::ptrdiff_t offset = kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
      if (row - kDy[d] >= 0)
        out.term[out.count++] = {-offset, rows.s(row - kDy[d], d) - kDx[d], rows.len(row - kDy[d], d) - kDx[d],
                                 -kDx[d]};
      if (row + kDy[d] < g.H) out.term[out.count++] = {offset, rows.s(row, d), rows.len(row, d), kDx[d]};
    }
  }

  // One vector of points' force sums: gravity, then the row's springs in order.
  template <bool kInterior, bool kDegenerate>
  static void forceVector(const GridForceArgs& a, const RowTerms& terms, int row, int x0, F gx, F gy, F gz) {
    const GridShape& g = a.shape;
    const std::ptrdiff_t q = at(g, x0, row);
    const F X = V::load(a.x + q), Y = V::load(a.y + q), Z = V::load(a.z + q);
    const F m = V::load(a.mass + q);
    F fx = V::mul(gx, m), fy = V::mul(gy, m), fz = V::mul(gz, m);  // gravity * mass
    // Off the interior, which lanes' partners are on the grid, per column offset (-2 to 2), once a vector: five masks
    // of two compares each, where each of the twelve terms made its own (pinned2 0.98 of the time)
    F on[5];
    if constexpr (!kInterior) {
      const F xs = V::add(V::set1(float(x0)), V::iota());
      for (int du = -2; du <= 2; ++du)
        on[du + 2] = onGrid(xs, du, g.W);
    }
    for (int k = 0; k < terms.count; ++k) {
      const Term& t = terms.term[k];
      addSpring<kInterior, kDegenerate>(a, q + t.other, t.s + x0, t.len + x0, kInterior ? F{} : on[t.du + 2], X, Y, Z,
                                        fx, fy, fz);
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

  template <bool kDegenerate>
  static void rowForces(const GridForceArgs& a, const RowTerms& terms, int row, F gx, F gy, F gz) {
    const GridShape& g = a.shape;
    // A spring reaches at most 2 columns to either side (kDx): vectors from x0 = 2 up to W - 2 - kW have
    // every lane's neighbours on the grid.
    for (int x0 = 0; x0 < g.W; x0 += kW) {
      if (x0 >= 2 && x0 + kW + 2 <= g.W)
        forceVector<true, kDegenerate>(a, terms, row, x0, gx, gy, gz);
      else
        forceVector<false, kDegenerate>(a, terms, row, x0, gx, gy, gz);
    }
  }

  static void forces(const GridForceArgs& a, int y0, int y1) {
    const GridShape& g = a.shape;
    static thread_local SpringRows rows;
    rows.row_floats = kPad + (g.W + kW - 1) / kW * kW + kW;
    rows.data.resize(std::size_t(36) * std::size_t(rows.row_floats));
    for (int row = std::max(y0 - 2, 0); row < y0; ++row)  // springs that end in the first rows
      springRow(a, row, rows);
    const F gx = V::set1(a.gravity[0]), gy = V::set1(a.gravity[1]), gz = V::set1(a.gravity[2]);
    RowTerms terms;
    const auto integrates = [&](int row) { return a.integrate && row >= a.integrate_from && row < a.integrate_to; };
    for (int row = y0; row < y1; ++row) {
      springRow(a, row, rows);
      rowTerms(a, rows, row, terms);
      // A row's points end springs of that row and the two above
      if (rows.degenerate[row % 3] || (row >= 1 && rows.degenerate[(row - 1) % 3]) ||
          (row >= 2 && rows.degenerate[(row - 2) % 3]))
        rowForces<true>(a, terms, row, gx, gy, gz);
      else
        rowForces<false>(a, terms, row, gx, gy, gz);
      // Row - 2's points are read by no later row's springs or forces: their forces and positions still in cache
      if (integrates(row - 2)) integrateRows(*a.integrate, row - 2, row - 1);
    }
    for (int row = std::max(y1 - 2, y0); row < y1; ++row)
      if (integrates(row)) integrateRows(*a.integrate, row, row + 1);
  }

  // One coordinate's Verlet step in displacement form, lane by lane: v = keep * v + (f * (1/m)) * dt^2, as
  // integrateVerlet computes it, and x += v; a pinned lane (all bits set) keeps x and gets v = +0.
  static void verletLanes(F& x, F& v, F f, F inv_mass, F pinned, F keep, F dt2) {
    const F ve = V::add(V::mul(keep, v), V::mul(V::mul(f, inv_mass), dt2));
    v = V::select(pinned, V::set1(0.0f), ve);
    x = V::select(pinned, x, V::add(x, ve));
  }
  static void verletScalar(float& x, float& v, float f, float inv_mass, float pinned, float keep, float dt2) {
    if (pinned != pinned) {  // all bits set is a NaN
      v = 0.0f;
      return;
    }
    v = keep * v + f * inv_mass * dt2;
    x += v;
  }

  static void integrate(float* x, float* v, const float* f, const float* inv_mass3, const float* pinned3, float dt2,
                        float keep, long long first, long long last) {
    const F dt2v = V::set1(dt2), keepv = V::set1(keep);
    long long e = first;
    for (; e + kW <= last; e += kW) {
      F xe = V::load(x + e), ve = V::load(v + e);
      verletLanes(xe, ve, V::load(f + e), V::load(inv_mass3 + e), V::load(pinned3 + e), keepv, dt2v);
      V::store(v + e, ve);
      V::store(x + e, xe);
    }
    for (; e < last; ++e)
      verletScalar(x[e], v[e], f[e], inv_mass3[e], pinned3[e], keep, dt2);
  }

  static void integrateRows(const GridIntegrateArgs& a, int y0, int y1) {
    const GridShape& g = a.shape;
    const F dt2v = V::set1(a.dt2), keepv = V::set1(a.keep), zero = V::set1(0.0f);
    float* const soa[6] = {a.x, a.y, a.z, a.vx, a.vy, a.vz};
    for (int row = y0; row < y1; ++row) {
      const std::ptrdiff_t q = at(g, 0, row), first = 3 * std::ptrdiff_t(row) * g.W;
      F negative_zero = zero;
      int i = 0;
      for (; i + kW <= g.W; i += kW) {
        const F pinned = V::load(a.pinned + q + i), inv_mass = V::load(a.inv_mass + q + i);
        F f[3], x[3], v[3];
        V::loadVec3(a.forces + first + 3 * i, f[0], f[1], f[2]);
        for (int c = 0; c < 3; ++c) {
          x[c] = V::load(soa[c] + q + i);
          v[c] = V::load(soa[3 + c] + q + i);
          verletLanes(x[c], v[c], f[c], inv_mass, pinned, keepv, dt2v);
          V::store(soa[c] + q + i, x[c]);
          V::store(soa[3 + c] + q + i, v[c]);
          negative_zero = V::bitOr(negative_zero, V::bitOr(V::negZero(x[c]), V::negZero(v[c])));
        }
        if (a.aos_x) V::storeVec3(a.aos_x + first + 3 * i, x[0], x[1], x[2]);
      }
      bool tail_zero = false;
      for (; i < g.W; ++i) {
        for (int c = 0; c < 3; ++c) {
          float& x = soa[c][q + i];
          float& v = soa[3 + c][q + i];
          verletScalar(x, v, a.forces[first + 3 * i + c], a.inv_mass[q + i], a.pinned[q + i], a.keep, a.dt2);
          if (a.aos_x) a.aos_x[first + 3 * i + c] = x;
          tail_zero = tail_zero || (x == 0.0f && std::signbit(x)) || (v == 0.0f && std::signbit(v));
        }
      }
      a.signed_rows[row] = tail_zero || V::any(negative_zero) ? 1 : 0;
    }
  }

  // quickHealthy's tests lane by lane, |d|^2 summed as it sums it (from b - a: the same squares). Lanes off the grid
  // (the padding holds anything) and springs whose far end is off it are left out; no early exit.
  static bool healthyRows(const GridHealthArgs& a, int y0, int y1) {
    const GridShape& g = a.shape;
    const F sign = V::set1(-0.0f), bound = V::set1(a.bound), finite = V::set1(std::numeric_limits<float>::max());
    const auto within = [&](const float* c, std::ptrdiff_t q, F most) {
      return V::leBits(V::andNot(sign, V::load(c + q)), most);
    };
    int bad = 0;
    for (int row = y0; row < y1; ++row)
      for (int x0 = 0; x0 < g.W; x0 += kW) {
        const std::ptrdiff_t q = at(g, x0, row);
        const F xs = V::add(V::set1(float(x0)), V::iota());
        int ok = within(a.x, q, bound) & within(a.y, q, bound) & within(a.z, q, bound) & within(a.vx, q, finite) &
                 within(a.vy, q, finite) & within(a.vz, q, finite);
        for (int d = 0; d < 6; ++d) {
          if (!a.limit2[d] || row + kDy[d] >= g.H) continue;
          const std::ptrdiff_t far = q + kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
          const F dx = V::sub(V::load(a.x + far), V::load(a.x + q)), dy = V::sub(V::load(a.y + far), V::load(a.y + q)),
                  dz = V::sub(V::load(a.z + far), V::load(a.z + q));
          const F d2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
          ok &= V::leBits(d2, V::load(a.limit2[d] + q)) | ~V::bits(onGrid(xs, kDx[d], g.W));
        }
        bad |= ~ok & V::bits(V::lt(xs, V::set1(float(g.W))));
      }
    return bad == 0;
  }

  static constexpr GridKernels table(const char* name) {
    return {name,
            kW,
            &toSoa,
            &fromSoa,
            &forces,
            &Colours::stretchColour,
            &Colours::xpbdColour,
            &Vbd::vbdPoints,
            &integrate,
            &integrateRows,
            &healthyRows,
            &Contact::pairTerms,
            &StencilKernels<V>::stencilPairs,
            &Contact::scanPairs,
            &Contact::scanCell,
            &Contact::filePairs,
            &Contact::collideObjects,
            &Contact::collideRows,
            &Contact::tileBoxes,
            &Contact::displacementBox,
            &Contact::cellsOf,
            &Contact::tilesMovedApart,
            &Probes::probeAddMul,
            &Probes::probeDivSqrt,
            &Probes::probeTriad};
  }
};

}  // namespace
}  // namespace drape
