// The stretch limit's and XPBD's colour kernels over the vector type V, each lane following the scalar code it
// names operation for operation: part of cpu/grid_kernels.inl (which includes this file once, inside the same
// rules: nothing here may be a non-inline symbol shared with other units), kept apart for its size.
#pragma once

namespace drape {
namespace {

template <class V>
struct ColourKernels : Lanes<V> {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;

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
  // valid: the valid lanes as bits. The compare stays a bit mask (on AVX-512 a mask register): a vector of it made
  // and turned back into bits was two fifths of rowColour's time, on the path to the branch.
  static bool allClear(F ax, F ay, F az, F bx, F by, F bz, F rest, F limit, int valid) {
    const F dx = V::sub(bx, ax), dy = V::sub(by, ay), dz = V::sub(bz, az);
    const F len2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
    const F max_len = V::mul(limit, rest);
    const int clear = V::ltBits(len2, V::mul(V::mul(max_len, max_len), V::set1(1.0f - 0x1p-20f)));
    constexpr int kAll = (1 << kW) - 1;
    return ((clear | ~valid) & kAll) == kAll;
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
    if (allClear(a.x, a.y, a.z, b.x, b.y, b.z, rest, limit, V::bits(valid))) {
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
    bool skipsClear(F ax, F ay, F az, F bx, F by, F bz, F rest, int valid) const {
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
    bool skipsClear(F, F, F, F, F, F, F, int) const { return false; }
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
      const F lanes = V::add(V::set1(float(x0)), V::iota()), end = V::set1(float(x_end));
      if (skips && rule.skipsClear(V::load(a.x + q), V::load(a.y + q), V::load(a.z + q), V::load(a.x + q + offset),
                                   V::load(a.y + q + offset), V::load(a.z + q + offset), V::load(a.springs.rest[d] + q),
                                   V::ltBits(lanes, end)))
        continue;
      const F valid = V::lt(lanes, end);
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
      const F lanes = V::add(V::set1(float(x0)), lane_a), end = V::set1(float(g.W - dx));
      End ea{}, eb{};  // vx, vy, vz only where displacements are corrected
      F rest, unused;
      splitArray<kPairs>(a.x + q, ea.x, eb.x);
      splitArray<kPairs>(a.y + q, ea.y, eb.y);
      splitArray<kPairs>(a.z + q, ea.z, eb.z);
      splitArray<kPairs>(a.springs.rest[d] + q, rest, unused);
      if (skips && rule.skipsClear(ea.x, ea.y, ea.z, eb.x, eb.y, eb.z, rest, V::ltBits(lanes, end))) continue;
      const F valid = V::lt(lanes, end);
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
};

}  // namespace
}  // namespace drape
