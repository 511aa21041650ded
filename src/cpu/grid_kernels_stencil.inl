// The grid kernel of self-collision's stencil (GridStencilArgs), over the vector type V: part of
// cpu/grid_kernels.inl (which includes this file once, inside the same rules: nothing here may be a non-inline
// symbol shared with other units), kept apart for its size.
#pragma once

namespace drape {
namespace {

template <class V>
struct StencilKernels : Lanes<V> {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;
  using Lanes<V>::onGrid;

  // A row's stencil offsets whose partner row is on the grid, worked out once a row (per vector they were
  // a fifth of the kernel's instructions): the partner's padded index and point index less the point's, its
  // column less the point's, and whether some pairs there are held at rest.
  struct StencilTerm {
    std::ptrdiff_t padded, point;
    int du;
    bool mixed;
  };
  // Whether the squares rule tests out (GridStencilArgs::active), or record their least distances
  enum StencilTiles { kAllTested, kTilesRuleOut, kTilesRecord };

  // The squares a vector's lanes lie in: from `first`, `count` of them (two at most where a square is as wide as a
  // vector, three where sixteen lanes cross a square of 9 to 15 points), each square's accumulators `stride` floats
  // after the one before
  struct Squares {
    int first, count;
    std::ptrdiff_t stride;
  };

  // One offset's test of the vector of points at (u0, v), the first point `first`: its pairs in range appended to
  // a.lower and a.upper at `found`, and where kRecord each lane's least distance into the accumulators of the squares
  // the lanes lie in (from least, as `squares` says; a NaN distance is -inf there, so that nothing is ruled out until
  // the next build)
  template <bool kInterior, bool kRecord>
  static void stencilTest(const GridStencilArgs& a, const StencilTerm& t, std::ptrdiff_t q, F X, F Y, F Z, F us,
                          int own, F r2, std::uint32_t first, int& found, float* least, const Squares& squares) {
    const GridShape& g = a.shape;
    // The padding keeps every partner load inside the arrays (|du| <= kMaxStencilBox < 2 rows)
    const std::ptrdiff_t p = q + t.padded;
    const F dx = V::sub(X, V::load(a.x + p)), dy = V::sub(Y, V::load(a.y + p)), dz = V::sub(Z, V::load(a.z + p));
    const F d2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
    // The lanes as bits (onGrid's two compares): on AVX-512 straight from the mask registers, where a vector of each
    // compare and its conversion back lay on the path to the pairs' branch (selfCollision and pinned2 0.97 and 0.93 of
    // the time with these and the colours' all-clear test on bits)
    const int lanes =
        kInterior ? own : V::leBits(V::set1(float(-t.du)), us) & V::ltBits(us, V::set1(float(g.W - t.du))) & own;
    if constexpr (kRecord) {
      const F inf = V::set1(__builtin_inff());
      const F on = kInterior ? V::eq(us, us) : V::bitAnd(onGrid(us, t.du, g.W), V::lt(us, V::set1(float(g.W))));
      const F value = V::select(on, V::select(V::ge(d2, V::set1(0.0f)), d2, V::neg(inf)), inf);
      for (int s = 0; s < squares.count; ++s, least += squares.stride)
        V::store(least, V::min(V::load(least), value));
    }
    // not d2 >= range^2: a NaN distance is a pair, for the scalar sum to see
    int pair = ~V::geBits(d2, r2) & lanes;
    if (t.mixed && pair != 0) {  // heldAtRest(rest_i, rest_j, range): d . d < range^2
      const F ex = V::sub(V::load(a.rx + q), V::load(a.rx + p)), ey = V::sub(V::load(a.ry + q), V::load(a.ry + p)),
              ez = V::sub(V::load(a.rz + q), V::load(a.rz + p));
      const F e2 = V::add(V::add(V::mul(ex, ex), V::mul(ey, ey)), V::mul(ez, ez));
      pair &= ~V::ltBits(e2, r2);
    }
    for (int bits = pair; bits != 0; bits &= bits - 1) {
      const auto i = first + std::uint32_t(__builtin_ctz(unsigned(bits)));
      a.lower[found] = i;
      a.upper[found] = std::uint32_t(std::ptrdiff_t(i) + t.point);
      ++found;
    }
  }

  // The vector of points at (u0, v) against the row's offsets: all of them (terms, count of them), or, by the
  // squares its lanes lie in, the offsets they do not rule out (by offset number: terms[k] on the row where row has
  // bit k); where recording, into the accumulators of those squares (from acc: kW lanes an offset)
  template <bool kInterior, int kTiles>
  static void stencilVector(const GridStencilArgs& a, const StencilTerm* terms, int count, std::uint64_t row, int u0,
                            int v, F r2, const Squares& squares, float* acc, int& found) {
    const GridShape& g = a.shape;
    const std::ptrdiff_t q = at(g, u0, v);
    const F X = V::load(a.x + q), Y = V::load(a.y + q), Z = V::load(a.z + q);
    const F us = V::add(V::set1(float(u0)), V::iota());
    const int own = kInterior ? (1 << kW) - 1 : V::ltBits(us, V::set1(float(g.W)));
    const auto first = std::uint32_t(std::ptrdiff_t(v) * g.W + u0);
    if constexpr (kTiles == kAllTested) {
      for (int k = 0; k < count; ++k)
        stencilTest<kInterior, false>(a, terms[k], q, X, Y, Z, us, own, r2, first, found, nullptr, squares);
    } else if constexpr (kTiles == kTilesRuleOut) {
      std::uint64_t active = 0;
      for (int s = 0; s < squares.count; ++s)
        active |= a.active[squares.first + s];
      for (std::uint64_t m = active & row; m != 0; m &= m - 1)
        stencilTest<kInterior, false>(a, terms[std::countr_zero(m)], q, X, Y, Z, us, own, r2, first, found, nullptr,
                                      squares);
    } else {
      for (std::uint64_t m = row; m != 0; m &= m - 1) {
        const int k = std::countr_zero(m);
        stencilTest<kInterior, true>(a, terms[k], q, X, Y, Z, us, own, r2, first, found, acc + k * kW, squares);
      }
    }
  }

  template <int kTiles>
  static int stencilRows(const GridStencilArgs& a, int y0, int y1) {
    const GridShape& g = a.shape;
    const F r2 = V::set1(a.range2);
    int side = 0;  // the columns an offset reaches either way
    for (int k = 0; k < a.count; ++k)
      side = a.du[k] > side ? a.du[k] : (-a.du[k] > side ? -a.du[k] : side);
    int found = 0;
    static thread_local std::vector<StencilTerm> terms;
    terms.resize(std::size_t(a.count));
    // With the squares: the columns of squares each vector's first and last lanes lie in (a division each, per
    // vector, was a third of the kernel's time)
    static thread_local std::vector<std::pair<int, int>> columns;
    if (kTiles != kAllTested) {
      columns.resize(std::size_t((g.W + kW - 1) / kW));
      for (int u0 = 0; u0 < g.W; u0 += kW)
        columns[std::size_t(u0 / kW)] = {u0 / a.edge, (u0 + kW < g.W ? u0 + kW - 1 : g.W - 1) / a.edge};
    }
    // Recording: per column of squares and offset, each lane's least distance over the square's rows so far, made
    // into the square's least at its last row (a horizontal minimum per test cost three times the test)
    static thread_local std::vector<float> acc;
    const auto flush = [&](int tile_row) {
      float* const row =
          tile_row == a.shared_row * a.across ? a.shared_min2 : a.min2 + std::ptrdiff_t(tile_row) * a.count;
      for (int c = 0; c < a.across; ++c)
        for (int k = 0; k < a.count; ++k) {
          float* lanes = acc.data() + (std::size_t(c) * std::size_t(a.count) + std::size_t(k)) * kW;
          float* least = row + std::ptrdiff_t(c) * a.count + k;
          for (int l = 0; l < kW; ++l) {
            *least = lanes[l] < *least ? lanes[l] : *least;
            lanes[l] = __builtin_inff();
          }
        }
    };
    if (kTiles == kTilesRecord) acc.assign(std::size_t(a.across) * std::size_t(a.count) * kW, __builtin_inff());
    for (int v = y0; v < y1; ++v) {
      int count = 0;
      std::uint64_t row = 0;  // with the squares: the offsets on the grid from this row, terms by offset number
      for (int k = 0; k < a.count; ++k) {
        if (v + a.dv[k] < 0 || v + a.dv[k] >= g.H) continue;
        row |= std::uint64_t(1) << (k & 63);
        terms[std::size_t(kTiles == kAllTested ? count++ : k)] = {std::ptrdiff_t(a.dv[k]) * g.stride + a.du[k],
                                                                  std::ptrdiff_t(a.dv[k]) * g.W + a.du[k], a.du[k],
                                                                  a.mixed[k] != 0};
      }
      const int tile_row = kTiles == kAllTested ? 0 : v / a.edge * a.across;
      // Vectors whose every lane's partners are on the grid need no lane masks
      for (int u0 = 0; u0 < g.W; u0 += kW) {
        Squares squares{0, 0, std::ptrdiff_t(a.count) * kW};
        if (kTiles != kAllTested) {
          const auto& [c0, c1] = columns[std::size_t(u0 / kW)];
          squares.first = tile_row + c0;
          squares.count = c1 - c0 + 1;
        }
        float* const at_square = kTiles == kTilesRecord
                                     ? acc.data() + std::size_t(squares.first - tile_row) * std::size_t(a.count) * kW
                                     : nullptr;
        if (u0 >= side && u0 + kW + side <= g.W)
          stencilVector<true, kTiles>(a, terms.data(), count, row, u0, v, r2, squares, at_square, found);
        else
          stencilVector<false, kTiles>(a, terms.data(), count, row, u0, v, r2, squares, at_square, found);
      }
      if (kTiles == kTilesRecord && ((v + 1) % a.edge == 0 || v + 1 == y1)) flush(tile_row);
    }
    return found;
  }

  static int stencilPairs(const GridStencilArgs& a, int y0, int y1) {
    if (!a.min2) return stencilRows<kAllTested>(a, y0, y1);
    if (a.record) return stencilRows<kTilesRecord>(a, y0, y1);
    return stencilRows<kTilesRuleOut>(a, y0, y1);
  }
};

}  // namespace
}  // namespace drape
