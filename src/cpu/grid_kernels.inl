// The grid kernels, written once over a vector type V (cpu/simd.hpp) and included by one translation unit
// per instruction set. Each lane follows the scalar code of cpu/physics.hpp operation for operation: the
// comments name the function whose arithmetic a block repeats. Nothing here may be a non-inline symbol
// shared with other units (see simd.hpp), so everything but the table at the end is in an unnamed namespace.
// The forces, the stretch and XPBD colours and integration are here; self-collision's and the collisions'
// kernels in cpu/grid_kernels_contact.inl, VBD's in cpu/grid_kernels_vbd.inl, the machine probes in
// cpu/grid_kernels_probes.inl, which this file includes.
#include "cpu/grid_kernels.hpp"
#include "cpu/simd.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace drape {
namespace {

// GridShape::at, kept here: the kernels' translation units share no inline function with the rest.
std::ptrdiff_t at(const GridShape& g, int x, int y) {
  return std::ptrdiff_t(y + GridShape::kTop) * g.stride + GridShape::kLeft + x;
}

constexpr int kDx[6] = {1, 0, 1, -1, 2, 0}, kDy[6] = {0, 1, 1, 1, 0, 2};  // core/colouring.hpp, kGridDirections

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

#include "cpu/grid_kernels_contact.inl"
#include "cpu/grid_kernels_probes.inl"
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
        const F len = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
        V::store(s_out + x0, V::div(V::mul(k, V::sub(len, V::load(a.springs.rest[d] + q))), len));
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
    const F xs = V::add(V::set1(float(x0)), V::iota());
    for (int k = 0; k < terms.count; ++k) {
      const Term& t = terms.term[k];
      addSpring<kInterior, kDegenerate>(a, q + t.other, t.s + x0, t.len + x0, kInterior ? F{} : onGrid(xs, t.du, g.W),
                                        X, Y, Z, fx, fy, fz);
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
    for (int row = y0; row < y1; ++row) {
      springRow(a, row, rows);
      rowTerms(a, rows, row, terms);
      // A row's points end springs of that row and the two above
      if (rows.degenerate[row % 3] || (row >= 1 && rows.degenerate[(row - 1) % 3]) ||
          (row >= 2 && rows.degenerate[(row - 2) % 3]))
        rowForces<true>(a, terms, row, gx, gy, gz);
      else
        rowForces<false>(a, terms, row, gx, gy, gz);
    }
  }

  struct End {
    F x, y, z, vx, vy, vz, pinned;
    F w;  // inverse mass (XPBD's ends only)
  };

  // One lane per spring a-b of the colour (valid lanes only): Provot's correction as limitStretchColoured
  // computes it, both ends moved at once. stretchShare, stretchCorrection (cpu/physics.hpp) lane by lane:
  // ca = (share_a (len - max) / len) d with d = x_b - x_a; cb = -ca where the shares are equal, else the
  // same expression seen from b, whose d is exactly -d. A spring within the limit gives +0 (and -ca = -0),
  // which is still added, as the scalar code adds it.
  // Most springs of a colour are within the limit, and a vector of them all within gets +0 at a and -0 (or +0)
  // at b without the square root and the divisions: len^2 under (limit rest)^2 (1 - 2^-20) as computed in
  // float implies sqrt(len^2) <= limit rest as rounded (the margin covers the three roundings), and a NaN or
  // a product that underflows fails the test and takes the full path. Adding +0 changes only a -0 and adding
  // -0 nothing, so such a vector is usually left as it is: returns whether anything is to be stored.
  // Whether every valid lane's spring is within the limit by the test above (the fast path's).
  static bool allClear(F ax, F ay, F az, F bx, F by, F bz, F rest, F limit, F valid) {
    const F dx = V::sub(bx, ax), dy = V::sub(by, ay), dz = V::sub(bz, az);
    const F len2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
    const F max_len = V::mul(limit, rest);
    const F clear = V::lt(len2, V::mul(V::mul(max_len, max_len), V::set1(1.0f - 0x1p-20f)));
    constexpr int kAll = (1 << kW) - 1;
    return ((V::bits(clear) | ~V::bits(valid)) & kAll) == kAll;
  }

  static bool limitSprings(End& a, End& b, F rest, F limit, F valid, bool displacements) {
    const F dx = V::sub(b.x, a.x), dy = V::sub(b.y, a.y), dz = V::sub(b.z, a.z);
    const F max_len = V::mul(limit, rest);
    const F zero = V::set1(0.0f), one = V::set1(1.0f), half = V::set1(0.5f);
    const F share_a = V::select(a.pinned, zero, V::select(b.pinned, one, half));
    const F share_b = V::select(b.pinned, zero, V::select(a.pinned, one, half));
    const F same = V::eq(share_a, share_b);
    const F move_a = V::andNot(a.pinned, valid), move_b = V::andNot(b.pinned, valid);
    F cax, cay, caz, cbx, cby, cbz;
    if (allClear(a.x, a.y, a.z, b.x, b.y, b.z, rest, limit, valid)) {
      const auto neg_zero = [](F p, F q, F r) {
        return V::bitOr(V::bitOr(V::negZero(p), V::negZero(q)), V::negZero(r));
      };
      F at_a = neg_zero(a.x, a.y, a.z), at_b = neg_zero(b.x, b.y, b.z);
      if (displacements) {
        at_a = V::bitOr(at_a, neg_zero(a.vx, a.vy, a.vz));
        at_b = V::bitOr(at_b, neg_zero(b.vx, b.vy, b.vz));
      }
      if (!V::any(V::bitOr(V::bitAnd(at_a, move_a), V::andNot(same, V::bitAnd(at_b, move_b))))) return false;
      cax = cay = caz = zero;
      cbx = cby = cbz = V::select(same, V::neg(zero), zero);
    } else {
      const F len = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
      const F within = V::le(len, max_len);
      const F excess = V::sub(len, max_len);
      const F qa = V::div(V::mul(share_a, excess), len);
      const F qb = V::div(V::mul(share_b, excess), len);
      cax = V::select(within, zero, V::mul(qa, dx));
      cay = V::select(within, zero, V::mul(qa, dy));
      caz = V::select(within, zero, V::mul(qa, dz));
      cbx = V::select(same, V::neg(cax), V::select(within, zero, V::mul(qb, V::neg(dx))));
      cby = V::select(same, V::neg(cay), V::select(within, zero, V::mul(qb, V::neg(dy))));
      cbz = V::select(same, V::neg(caz), V::select(within, zero, V::mul(qb, V::neg(dz))));
    }
    a.x = V::select(move_a, V::add(a.x, cax), a.x);
    a.y = V::select(move_a, V::add(a.y, cay), a.y);
    a.z = V::select(move_a, V::add(a.z, caz), a.z);
    b.x = V::select(move_b, V::add(b.x, cbx), b.x);
    b.y = V::select(move_b, V::add(b.y, cby), b.y);
    b.z = V::select(move_b, V::add(b.z, cbz), b.z);
    if (!displacements) return true;  // x_prev stays where it was: v takes the same corrections
    a.vx = V::select(move_a, V::add(a.vx, cax), a.vx);
    a.vy = V::select(move_a, V::add(a.vy, cay), a.vy);
    a.vz = V::select(move_a, V::add(a.vz, caz), a.vz);
    b.vx = V::select(move_b, V::add(b.vx, cbx), b.vx);
    b.vy = V::select(move_b, V::add(b.vy, cby), b.vy);
    b.vz = V::select(move_b, V::add(b.vz, cbz), b.vz);
    return true;
  }

  // One lane per spring a-b of the colour (valid lanes only): xpbdDistanceCorrection (cpu/physics.hpp) with
  // the spring's multiplier lambda (0 in a single sweep), as solveXpbd computes it, and its moves -w_a p at a
  // and +w_b p at b, w 0 at a pinned end; lambda += dlambda where an end may move (a spring pinned at both ends
  // is skipped, as there). A spring of length <= 0 gives p = 0, whose +-0 moves are still added, as the
  // scalar code adds them. Returns whether anything is to be stored.
  static bool xpbdSprings(End& a, End& b, F rest, F alpha, F& lambda, F valid, bool displacements) {
    const F dx = V::sub(b.x, a.x), dy = V::sub(b.y, a.y), dz = V::sub(b.z, a.z);
    const F len = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
    const F zero = V::set1(0.0f);
    const F wa = V::select(a.pinned, zero, a.w), wb = V::select(b.pinned, zero, b.w);
    const F move_a = V::andNot(a.pinned, valid), move_b = V::andNot(b.pinned, valid);
    const F moves = V::bitOr(move_a, move_b);
    if (!V::any(moves)) return false;
    // (-(len - rest) - alpha lambda) / (w_sum + alpha)
    const F dlambda = V::div(V::sub(V::neg(V::sub(len, rest)), V::mul(alpha, lambda)), V::add(V::add(wa, wb), alpha));
    lambda = V::select(moves, V::add(lambda, dlambda), lambda);
    const F none = V::le(len, zero);
    const F s = V::div(dlambda, len);
    const F px = V::select(none, zero, V::mul(s, dx));
    const F py = V::select(none, zero, V::mul(s, dy));
    const F pz = V::select(none, zero, V::mul(s, dz));
    const F na = V::neg(wa);
    const F cax = V::mul(na, px), cay = V::mul(na, py), caz = V::mul(na, pz);
    const F cbx = V::mul(wb, px), cby = V::mul(wb, py), cbz = V::mul(wb, pz);
    a.x = V::select(move_a, V::add(a.x, cax), a.x);
    a.y = V::select(move_a, V::add(a.y, cay), a.y);
    a.z = V::select(move_a, V::add(a.z, caz), a.z);
    b.x = V::select(move_b, V::add(b.x, cbx), b.x);
    b.y = V::select(move_b, V::add(b.y, cby), b.y);
    b.z = V::select(move_b, V::add(b.z, cbz), b.z);
    if (!displacements) return true;  // x_prev stays: v = x - x_prev is the constrained displacement
    a.vx = V::select(move_a, V::add(a.vx, cax), a.vx);
    a.vy = V::select(move_a, V::add(a.vy, cay), a.vy);
    a.vz = V::select(move_a, V::add(a.vz, caz), a.vz);
    b.vx = V::select(move_b, V::add(b.vx, cbx), b.vx);
    b.vy = V::select(move_b, V::add(b.vy, cby), b.vy);
    b.vz = V::select(move_b, V::add(b.vz, cbz), b.vz);
    return true;
  }

  // What a colour does to its springs: the stretch limit's correction, or XPBD's.
  // lambda: the springs' multipliers where the colour's kernel keeps them (GridStretchArgs::lambda), else 0.
  // kSkipsClear: a vector of springs all within the limit changes nothing where no coordinate of their ends is
  // -0 (adding +0 or -0 changes only a -0), so there it is skipped on its positions alone (skipsClear).
  struct StretchRule {
    static constexpr bool kWeights = false, kSkipsClear = true;
    F limit;
    explicit StretchRule(const GridStretchArgs& a) : limit(V::set1(a.limit)) {}
    bool operator()(End& ea, End& eb, F rest, F&, F valid, bool displacements, int) const {
      return limitSprings(ea, eb, rest, limit, valid, displacements);
    }
    bool skipsClear(F ax, F ay, F az, F bx, F by, F bz, F rest, F valid) const {
      return allClear(ax, ay, az, bx, by, bz, rest, limit, valid);
    }
  };
  struct XpbdRule {
    static constexpr bool kWeights = true, kSkipsClear = false;
    const GridStretchArgs* args;
    explicit XpbdRule(const GridStretchArgs& a) : args(&a) {}
    bool operator()(End& ea, End& eb, F rest, F& lambda, F valid, bool displacements, int d) const {
      return xpbdSprings(ea, eb, rest, V::set1(args->springs.k[d]), lambda, valid, displacements);
    }
    bool skipsClear(F, F, F, F, F, F, F, F) const { return false; }
  };

  // Whether the rows row and row + dy, where a colour's springs from row end, hold no -0 (GridStretchArgs).
  static bool unsignedRows(const GridStretchArgs& a, int row, int dy) {
    return a.signed_rows && !a.signed_rows[row] && !a.signed_rows[row + dy];
  }

  template <class Rule>
  static End loadEnd(const GridStretchArgs& a, std::ptrdiff_t q, bool displacements) {
    End e{V::load(a.x + q), V::load(a.y + q), V::load(a.z + q), {}, {}, {}, V::load(a.pinned + q), {}};
    if (displacements) {
      e.vx = V::load(a.vx + q);
      e.vy = V::load(a.vy + q);
      e.vz = V::load(a.vz + q);
    }
    if (Rule::kWeights) e.w = V::load(a.inv_mass + q);
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
  template <class Rule>
  static void rowColour(const GridStretchArgs& a, const Rule& rule, int d, int row, bool displacements) {
    const GridShape& g = a.shape;
    const int x_first = kDx[d] < 0 ? -kDx[d] : 0, x_end = kDx[d] > 0 ? g.W - kDx[d] : g.W;
    const std::ptrdiff_t offset = kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
    const bool skips = Rule::kSkipsClear && unsignedRows(a, row, kDy[d]);
    for (int x0 = x_first; x0 < x_end; x0 += kW) {
      const std::ptrdiff_t q = at(g, x0, row);
      const F valid = V::lt(V::add(V::set1(float(x0)), V::iota()), V::set1(float(x_end)));
      if (skips &&
          rule.skipsClear(V::load(a.x + q), V::load(a.y + q), V::load(a.z + q), V::load(a.x + q + offset),
                          V::load(a.y + q + offset), V::load(a.z + q + offset), V::load(a.springs.rest[d] + q), valid))
        continue;
      End ea = loadEnd<Rule>(a, q, displacements), eb = loadEnd<Rule>(a, q + offset, displacements);
      F lambda = a.lambda[d] ? V::load(a.lambda[d] + q) : V::set1(0.0f);
      if (!rule(ea, eb, V::load(a.springs.rest[d] + q), lambda, valid, displacements, d)) continue;
      storeEnd(a, q, ea, displacements);
      storeEnd(a, q + offset, eb, displacements);
      if (a.lambda[d]) V::store(a.lambda[d] + q, lambda);
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

  template <bool kPairs, class Rule>
  static void alternatingColour(const GridStretchArgs& a, const Rule& rule, int d, int parity, int row,
                                bool displacements) {
    const GridShape& g = a.shape;
    const int dx = kDx[d];
    F lane_lo = V::iota(), lane_hi = V::add(V::iota(), V::set1(float(kW))), lane_a, lane_b;
    split<kPairs>(lane_lo, lane_hi, lane_a, lane_b);
    const bool skips = Rule::kSkipsClear && unsignedRows(a, row, 0);
    for (int x0 = dx * parity; x0 + dx < g.W; x0 += 2 * kW) {
      const std::ptrdiff_t q = at(g, x0, row);
      const F valid = V::lt(V::add(V::set1(float(x0)), lane_a), V::set1(float(g.W - dx)));
      End ea{}, eb{};  // vx, vy, vz only where displacements are corrected
      F rest, unused;
      splitArray<kPairs>(a.x + q, ea.x, eb.x);
      splitArray<kPairs>(a.y + q, ea.y, eb.y);
      splitArray<kPairs>(a.z + q, ea.z, eb.z);
      splitArray<kPairs>(a.springs.rest[d] + q, rest, unused);
      if (skips && rule.skipsClear(ea.x, ea.y, ea.z, eb.x, eb.y, eb.z, rest, valid)) continue;
      splitArray<kPairs>(a.pinned + q, ea.pinned, eb.pinned);
      if (displacements) {
        splitArray<kPairs>(a.vx + q, ea.vx, eb.vx);
        splitArray<kPairs>(a.vy + q, ea.vy, eb.vy);
        splitArray<kPairs>(a.vz + q, ea.vz, eb.vz);
      }
      if (Rule::kWeights) splitArray<kPairs>(a.inv_mass + q, ea.w, eb.w);
      F lambda = V::set1(0.0f), others = lambda;  // others: the b ends' slots, put back as they were
      if (a.lambda[d]) splitArray<kPairs>(a.lambda[d] + q, lambda, others);
      if (!rule(ea, eb, rest, lambda, valid, displacements, d)) continue;
      if (a.lambda[d]) join<kPairs>(lambda, others, a.lambda[d] + q);
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
  template <class Rule>
  static void colour(const GridStretchArgs& a, int d, int parity, int y0, int y1) {
    const bool displacements = a.vx != nullptr;
    const Rule rule(a);
    for (int row = y0; row < y1; ++row) {
      if (kDy[d] == 0) {
        if (d == 0)
          alternatingColour<false>(a, rule, d, parity, row, displacements);
        else
          alternatingColour<true>(a, rule, d, parity, row, displacements);
        continue;
      }
      const int along = kDy[d] == 2 ? row / 2 : row;
      if (along % 2 == parity && row + kDy[d] < a.shape.H) rowColour(a, rule, d, row, displacements);
    }
  }
  static void stretchColour(const GridStretchArgs& a, int d, int parity, int y0, int y1) {
    colour<StretchRule>(a, d, parity, y0, y1);
  }
  static void xpbdColour(const GridStretchArgs& a, int d, int parity, int y0, int y1) {
    colour<XpbdRule>(a, d, parity, y0, y1);
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

  static constexpr GridKernels table(const char* name) {
    return {name,
            kW,
            &toSoa,
            &fromSoa,
            &forces,
            &stretchColour,
            &xpbdColour,
            &Vbd::vbdPoints,
            &integrate,
            &Contact::pairTerms,
            &Contact::stencilFlags,
            &Contact::scanPairs,
            &Contact::collideObjects,
            &Contact::tileBoxes,
            &Contact::tilesMovedApart,
            &Probes::probeAddMul,
            &Probes::probeDivSqrt,
            &Probes::probeTriad};
  }
};

}  // namespace
}  // namespace drape
