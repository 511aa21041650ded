// The grid kernels of self-collision and collisions, over the vector type V: part of cpu/grid_kernels.inl
// (which includes this file once, inside the same rules: nothing here may be a non-inline symbol shared with
// other units), kept apart for its size. Each lane follows the scalar code it names operation for operation.
#pragma once

namespace drape {
namespace {

template <class V>
struct ContactKernels : Lanes<V> {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;
  using Lanes<V>::onGrid;
  using Lanes<V>::sum;

  // HashGrid::cellOf's coordinate: floor(q), NaN to 0, clamped to +-2^30 (clamping first gives the same
  // cell and keeps floor's argument where it is exact)
  static F cellCoordinate(F q) {
    const float limit = float(1 << 30);
    const F finite = V::select(V::eq(q, q), q, V::set1(0.0f));
    return V::floor(V::min(V::max(finite, V::set1(-limit)), V::set1(limit)));
  }

  // HashGrid::build's cells: cellOf of points [first, last) of x (vec3s) into cells (ivec3s), the box of them widened
  // into box (least x, y, z, then greatest). The cells are whole floats until stored: the box is taken on them.
  static void cellsOf(const float* x, std::size_t first, std::size_t last, float inv_cell_size, int* cells, int* box) {
    if (first >= last) return;
    const F inv = V::set1(inv_cell_size);
    F lo[3], hi[3];
    for (int c = 0; c < 3; ++c) {
      lo[c] = V::set1(float(box[c]));
      hi[c] = V::set1(float(box[3 + c]));
    }
    const auto cellsAt = [&](const float* p, float* out, int live) {
      F q[3];
      V::loadVec3(p, q[0], q[1], q[2]);
      const F in = V::lt(V::iota(), V::set1(float(live)));
      for (int c = 0; c < 3; ++c) {
        q[c] = cellCoordinate(V::mul(q[c], inv));
        lo[c] = V::select(in, V::min(lo[c], q[c]), lo[c]);
        hi[c] = V::select(in, V::max(hi[c], q[c]), hi[c]);
      }
      V::storeVec3(out, V::intBits(q[0]), V::intBits(q[1]), V::intBits(q[2]));
    };
    std::size_t i = first;
    for (; i + kW <= last; i += kW)
      cellsAt(x + 3 * i, reinterpret_cast<float*>(cells + 3 * i), kW);
    if (i < last) {  // the last few through a vector's room of zeros
      float p[3 * kW] = {}, out[3 * kW];
      const std::size_t live = last - i;
      std::memcpy(p, x + 3 * i, sizeof(float) * 3 * live);
      cellsAt(p, out, int(live));
      std::memcpy(cells + 3 * i, out, sizeof(float) * 3 * live);
    }
    for (int c = 0; c < 3; ++c) {
      box[c] = int(V::hmin(lo[c]));
      box[3 + c] = int(V::hmax(hi[c]));
    }
  }

  static int pairTerms(const float* x, std::size_t points, const std::uint32_t* owner, const std::uint32_t* partner,
                       std::uint32_t first, std::uint32_t last, float thickness, float inv_range, PairTermOut* out) {
    const float range = 2.0f * thickness;  // as physics::selfCollisionCorrections computes it
    const F range2 = V::set1(range * range), zero = V::set1(0.0f), one = V::set1(1.0f), inv = V::set1(inv_range);
    int count = 0;
    for (std::uint32_t k = first; k < last; k += kW) {
      const int lanes = int(last - k < std::uint32_t(kW) ? last - k : std::uint32_t(kW));
      F ix, iy, iz, jx, jy, jz, live;
      // A list's owners are sorted and close together: loaded whole where the set can (the partners' gather sets live)
      if (lanes != kW || !V::loadVec3Near(x, owner + k, points, ix, iy, iz))
        V::gatherVec3(x, owner + k, lanes, ix, iy, iz, live);
      if (lanes == kW)
        V::gatherVec3Whole(x, partner + k, jx, jy, jz, live);
      else
        V::gatherVec3(x, partner + k, lanes, jx, jy, jz, live);
      const F dx = V::sub(ix, jx), dy = V::sub(iy, jy), dz = V::sub(iz, jz);
      const F dist2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
      const int live_bits = (1 << lanes) - 1;
      int bits = ~(V::geBits(dist2, range2) | V::leBits(dist2, zero)) & live_bits;
      if (bits == 0) continue;
      const int nan = V::bits(V::andNot(V::eq(dist2, dist2), live));
      const F dist = V::sqrt(dist2), f = V::div(V::sub(V::set1(range), dist), dist);
      // xj - xi, not -(xi - xj): the two differ in the sign of a zero
      const F c[6] = {V::mul(f, dx),
                      V::mul(f, dy),
                      V::mul(f, dz),
                      V::mul(f, V::sub(jx, ix)),
                      V::mul(f, V::sub(jy, iy)),
                      V::mul(f, V::sub(jz, iz))};
      // cellOrder(cell of i, cell of j) = 13 + 9 dz + 3 dy + dx for cell steps d in {-1, 0, 1}; from j, 26 less it.
      // The cells are whole floats: a rounded difference within 1 is exact.
      const F ex = V::sub(cellCoordinate(V::mul(jx, inv)), cellCoordinate(V::mul(ix, inv))),
              ey = V::sub(cellCoordinate(V::mul(jy, inv)), cellCoordinate(V::mul(iy, inv))),
              ez = V::sub(cellCoordinate(V::mul(jz, inv)), cellCoordinate(V::mul(iz, inv)));
      const F minus = V::set1(-1.0f);
      const F near =
          V::bitAnd(V::bitAnd(V::bitAnd(V::le(ex, one), V::ge(ex, minus)), V::bitAnd(V::le(ey, one), V::ge(ey, minus))),
                    V::bitAnd(V::le(ez, one), V::ge(ez, minus)));
      const F order = V::add(V::add(V::set1(13.0f), V::mul(V::set1(9.0f), ez)), V::add(V::mul(V::set1(3.0f), ey), ex));
      float lane[8][kW];
      for (int q = 0; q < 6; ++q)
        V::store(lane[q], c[q]);
      V::store(lane[6], V::select(near, order, V::set1(-1.0f)));
      for (; bits != 0; bits &= bits - 1) {
        const int l = __builtin_ctz(unsigned(bits));
        PairTermOut& o = out[count++];
        o.k = k + std::uint32_t(l);
        const int oi = int(lane[6][l]);
        o.order_i = (nan >> l) & 1 ? -2 : oi;
        o.order_j = oi < 0 ? -1 : 26 - oi;
        for (int q = 0; q < 3; ++q) {
          o.ci[q] = lane[q][l];
          o.cj[q] = lane[3 + q][l];
        }
      }
    }
    return count;
  }

  // Each sphere, then each plane, on the lanes of `free`: X..VZ moved in place (collidePoint: x += c, v += c).
  // Returns the lanes some object moved. Inlined: called a vector at a time, GCC kept it a call, which passed the six
  // vectors through memory (sphere, plane and selfCollision 0.96-0.98 of the time inlined).
  [[gnu::always_inline]] static F collideLanes(const CollideArgs& a, F free, F& X, F& Y, F& Z, F& VX, F& VY, F& VZ) {
    const F zero = V::set1(0.0f), one = V::set1(1.0f);
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
    return moved;
  }

  static long long collideObjects(const CollideArgs& a, long long first, long long last) {
    const F all = V::eq(V::set1(0.0f), V::set1(0.0f));
    long long i = first;
    for (; i + kW <= last; i += kW) {
      F X, Y, Z, VX, VY, VZ;
      V::loadVec3(a.x + 3 * i, X, Y, Z);
      V::loadVec3(a.v + 3 * i, VX, VY, VZ);
      if (V::any(collideLanes(a, V::andNot(V::load(a.pinned + i), all), X, Y, Z, VX, VY, VZ))) {
        V::storeVec3(a.x + 3 * i, X, Y, Z);
        V::storeVec3(a.v + 3 * i, VX, VY, VZ);
      }
    }
    return i;
  }

  // collideObjects on rows [y0, y1) of a grid path's padded arrays: every point, the padding's lanes left alone.
  static void collideRows(const CollideRowsArgs& r, int y0, int y1) {
    const GridShape& g = r.shape;
    const F all = V::eq(V::set1(0.0f), V::set1(0.0f));
    for (int v = y0; v < y1; ++v)
      for (int u0 = 0; u0 < g.W; u0 += kW) {
        const std::ptrdiff_t q = at(g, u0, v);
        F X = V::load(r.x + q), Y = V::load(r.y + q), Z = V::load(r.z + q);
        F VX = V::load(r.vx + q), VY = V::load(r.vy + q), VZ = V::load(r.vz + q);
        F free = V::andNot(V::load(r.pinned + q), all);
        if (u0 + kW > g.W) free = V::bitAnd(free, V::lt(V::add(V::set1(float(u0)), V::iota()), V::set1(float(g.W))));
        if (V::any(collideLanes(r.objects, free, X, Y, Z, VX, VY, VZ))) {
          V::store(r.x + q, X);
          V::store(r.y + q, Y);
          V::store(r.z + q, Z);
          V::store(r.vx + q, VX);
          V::store(r.vy + q, VY);
          V::store(r.vz + q, VZ);
        }
      }
  }

  static bool tileBoxes(const TileBoxArgs& a) {
    const std::ptrdiff_t n = std::ptrdiff_t(a.w) * a.h;
    const float inf = __builtin_inff();
    const F big = V::set1(inf), small = V::set1(-inf), zero = V::set1(0.0f);
    // d * 0 is 0 for every finite d and NaN otherwise: one sum tells whether every displacement was finite.
    F finite = zero;
    bool finite_tail = true;
    for (int tv = a.tv0; tv < a.tv1 && tv * a.edge < a.h; ++tv)
      for (int tu = 0; tu * a.edge < a.w; ++tu) {
        const int u0 = tu * a.edge, u1 = u0 + a.edge < a.w ? u0 + a.edge : a.w;
        const int v0 = tv * a.edge, v1 = v0 + a.edge < a.h ? v0 + a.edge : a.h;
        F box[12] = {big, big, big, small, small, small, big, big, big, small, small, small};
        float tail[12] = {inf, inf, inf, -inf, -inf, -inf, inf, inf, inf, -inf, -inf, -inf};
        // A vector of positions P and anchors A of `lanes` points of the tile (the others: the next tile's)
        const auto add = [&](const F(&P)[3], const F(&A)[3], int lanes) {
          if (lanes == kW) {
            for (int c = 0; c < 3; ++c) {
              const F d = V::sub(P[c], A[c]);
              finite = V::add(finite, V::mul(d, zero));
              box[c] = V::min(box[c], d);
              box[3 + c] = V::max(box[3 + c], d);
              box[6 + c] = V::min(box[6 + c], P[c]);
              box[9 + c] = V::max(box[9 + c], P[c]);
            }
            return;
          }
          // The lanes past the tile hold the next tile's points: each box takes its neutral value there
          const F live = V::lt(V::iota(), V::set1(float(lanes)));
          for (int c = 0; c < 3; ++c) {
            const F d = V::sub(P[c], A[c]);
            finite = V::add(finite, V::mul(V::select(live, d, zero), zero));
            box[c] = V::min(box[c], V::select(live, d, big));
            box[3 + c] = V::max(box[3 + c], V::select(live, d, small));
            box[6 + c] = V::min(box[6 + c], V::select(live, P[c], big));
            box[9 + c] = V::max(box[9 + c], V::select(live, P[c], small));
          }
        };
        if (a.px)  // padded rows: every load stays in the arrays
          for (int v = v0; v < v1; ++v)
            for (int u = u0; u < u1; u += kW) {
              const std::ptrdiff_t q = at(a.shape, u, v);
              const F P[3] = {V::load(a.px + q), V::load(a.py + q), V::load(a.pz + q)};
              const F A[3] = {V::load(a.ax + q), V::load(a.ay + q), V::load(a.az + q)};
              add(P, A, u1 - u < kW ? u1 - u : kW);
            }
        for (int v = v0; v < v1 && !a.px; ++v)
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
            add(P, A, lanes);
          }
        float* out = a.out + 12 * (std::ptrdiff_t(tv) * a.across + tu);
        for (int k = 0; k < 12; ++k) {
          const float r = (k / 3) % 2 == 0 ? V::hmin(box[k]) : V::hmax(box[k]);
          out[k] = (k / 3) % 2 == 0 ? (r < tail[k] ? r : tail[k]) : (r > tail[k] ? r : tail[k]);
        }
      }
    return finite_tail && V::bits(V::eq(finite, zero)) == (1 << kW) - 1;
  }

  static bool displacementBox(const TileBoxArgs& a, int y0, int y1, float* out) {
    const float inf = __builtin_inff();
    const F zero = V::set1(0.0f);
    F lo[3] = {V::set1(inf), V::set1(inf), V::set1(inf)}, hi[3] = {V::set1(-inf), V::set1(-inf), V::set1(-inf)};
    F finite = zero;  // d * 0 summed: 0 where every d was finite
    const float* const p[3] = {a.px, a.py, a.pz};
    const float* const anchor[3] = {a.ax, a.ay, a.az};
    for (int v = y0; v < y1; ++v)
      for (int u = 0; u < a.shape.W; u += kW) {
        const std::ptrdiff_t q = at(a.shape, u, v);
        // The lanes past the row's end read its padding: they take each box's neutral value
        const bool whole = a.shape.W - u >= kW;
        const F live = whole ? F{} : V::lt(V::iota(), V::set1(float(a.shape.W - u)));
        for (int c = 0; c < 3; ++c) {
          F d = V::sub(V::load(p[c] + q), V::load(anchor[c] + q));
          if (!whole) d = V::select(live, d, zero);
          finite = V::add(finite, V::mul(d, zero));
          lo[c] = V::min(lo[c], whole ? d : V::select(live, d, V::set1(inf)));
          hi[c] = V::max(hi[c], whole ? d : V::select(live, d, V::set1(-inf)));
        }
      }
    for (int c = 0; c < 3; ++c) {
      out[c] = V::hmin(lo[c]);
      out[3 + c] = V::hmax(hi[c]);
    }
    return V::bits(V::eq(finite, zero)) == (1 << kW) - 1;
  }

  static bool tilesMovedApart(const TileCompareArgs& a) {
    // The boxes as 12 rows of tiles, padded with empty tiles (minima +inf, maxima -inf), which are never near
    alignas(64) float rows[12][kMaxCompareTiles + kW];
    const float inf = __builtin_inff();
    const int padded = (a.count + kW - 1) / kW * kW;
    for (int k = 0; k < 12; ++k)
      for (int t = 0; t < padded; ++t)
        rows[k][t] = t < a.count ? a.boxes[12 * t + k] : ((k / 3) % 2 == 0 ? inf : -inf);
    const F zero = V::set1(0.0f), all = V::eq(zero, zero), apart2 = V::set1(a.apart2), limit2 = V::set1(a.limit2);
    for (int p = a.first; p < a.count; p += a.step) {
      if (a.stop->load(std::memory_order_relaxed)) return false;
      const float* b = a.boxes + 12 * p;
      if (!(b[6] <= b[9])) continue;  // an empty tile
      // From the vector that holds p: the tiles before it in that vector are compared twice, which changes
      // no answer.
      for (int c = p / kW * kW; c < a.count; c += kW) {
        F gap2 = zero, box2 = zero;
        for (int k = 0; k < 3; ++k) {
          // glm::max(vec3(0), glm::max(q.lo - p.hi, p.lo - q.hi)), and the displacements' box
          const F gap = V::max(zero, V::max(V::sub(V::load(rows[6 + k] + c), V::set1(b[9 + k])),
                                            V::sub(V::set1(b[6 + k]), V::load(rows[9 + k] + c))));
          const F box =
              V::sub(V::max(V::set1(b[3 + k]), V::load(rows[3 + k] + c)), V::min(V::set1(b[k]), V::load(rows[k] + c)));
          gap2 = k == 0 ? V::mul(gap, gap) : V::add(gap2, V::mul(gap, gap));
          box2 = k == 0 ? V::mul(box, box) : V::add(box2, V::mul(box, box));
        }
        const F near = V::andNot(V::ge(gap2, apart2), all), moved = V::andNot(V::le(box2, limit2), all);
        const F both = V::bitAnd(near, moved);
        if (!V::any(both)) continue;
        if (!a.found) return true;
        for (int bits = V::bits(both); bits != 0; bits &= bits - 1) {
          const int q = c + __builtin_ctz(unsigned(bits));
          if (q < p) continue;  // the pair of q, p, found from q
          if (*a.found_count >= a.capacity) return true;
          a.found[2 * *a.found_count] = std::uint32_t(p);
          a.found[2 * *a.found_count + 1] = std::uint32_t(q);
          ++*a.found_count;
        }
      }
    }
    return false;
  }

  static int scanPairs(const PairScanArgs& a, std::uint32_t first, std::uint32_t last, std::uint32_t* out) {
    int count = 0;
    std::uint32_t s = first;
    const F px = V::set1(a.px), py = V::set1(a.py), pz = V::set1(a.pz), pu = V::set1(a.pu), pv = V::set1(a.pv);
    const F reach2 = V::set1(a.reach2), a2 = V::set1(a.a2), b2 = V::set1(a.b2);
    const F near_below = V::set1(a.near_below);
    // Buckets hold a few candidates each: the last vector of a range reads past it (the arrays are padded,
    // PairScanArgs) and drops those lanes rather than testing them one at a time.
    for (; s < last; s += kW) {
      const F dx = V::sub(px, V::load(a.x + s)), dy = V::sub(py, V::load(a.y + s)), dz = V::sub(pz, V::load(a.z + s));
      const F d2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
      const F du = V::sub(V::load(a.u + s), pu), dv = V::sub(V::load(a.v + s), pv);
      const F nominal = V::add(V::mul(V::mul(du, du), a2), V::mul(V::mul(dv, dv), b2));
      int bits = V::ltBits(d2, reach2) & ~V::ltBits(nominal, near_below);
      if (last - s < std::uint32_t(kW)) bits &= (1 << (last - s)) - 1;
      while (bits != 0) {
        const int l = __builtin_ctz(unsigned(bits));
        bits &= bits - 1;
        out[count++] = s + std::uint32_t(l);
      }
    }
    return count;
  }

  // scanPairs' test of the points at slots [p0, p1) against each range of slots: a cell's few points, so each
  // vector of candidates is loaded once for all of them.
  struct ScanTest {
    F reach2, a2, b2, near_below, near2;
  };
  static int scanCell(const PairScanArgs& a, std::uint32_t p0, std::uint32_t p1, const CellRange* ranges, int count_of,
                      std::uint32_t* points, std::uint32_t* slots) {
    const ScanTest test{V::set1(a.reach2), V::set1(a.a2), V::set1(a.b2), V::set1(a.near_below), V::set1(a.near2)};
    int count = 0;
    for (int r = 0; r < count_of; ++r)
      count += scanRange(a, test, p0, p1, ranges[r], points + count, slots + count);
    return count;
  }
  // One pair at a time, without a branch on what becomes of it (which end is lower, whether it is kept, and where, are
  // as likely as not): the instruction sets without a compress (AVX-512's own: grid_kernels_avx512.cpp).
  static void filePairs(const PairFileArgs& a, const std::uint32_t* points, const std::uint32_t* slots, int count,
                        FiledPair* const out[2], int counts[2]) {
    const int side = 2 * a.box + 1;
    int n[2] = {0, 0};
    for (int k = 0; k < count; ++k) {
      const std::uint32_t i = a.sorted[points[k]], j = a.sorted[slots[k] & ~kFarSlot], far = slots[k] & kFarSlot;
      const int du = int(a.uv[j] & 0xffff) - int(a.uv[i] & 0xffff), dv = int(a.uv[j] >> 16) - int(a.uv[i] >> 16);
      const bool in_box = du >= -a.box && du <= a.box && dv >= -a.box && dv <= a.box;
      const bool keep = !in_box || a.kind[in_box ? (dv + a.box) * side + du + a.box : 0] == 0;
      const FiledPair pair{std::min(i, j), std::max(i, j) | far};
      const int d = pair.lower >= a.split;
      out[d][n[d]] = pair;
      n[d] += keep;
    }
    counts[0] = n[0];
    counts[1] = n[1];
  }
  static int scanRange(const PairScanArgs& a, const ScanTest& test, std::uint32_t p0, std::uint32_t p1,
                       const CellRange& range, std::uint32_t* points, std::uint32_t* slots) {
    // The arrays and the range in locals: the stores below may alias anything, and the pointers were loaded again for
    // every point
    const float *const x = a.x, *const y = a.y, *const z = a.z, *const u = a.u, *const v = a.v;
    const std::uint32_t last = range.last;
    const bool own = range.own;
    int count = 0;
    for (std::uint32_t s = range.first; s < last; s += kW) {
      const F X = V::load(x + s), Y = V::load(y + s), Z = V::load(z + s), U = V::load(u + s), W = V::load(v + s);
      const int live = last - s < std::uint32_t(kW) ? (1 << (last - s)) - 1 : (1 << kW) - 1;
      for (std::uint32_t p = p0; p < p1; ++p) {
        int lanes = live;
        if (own && p >= s) {  // the slots up to the point's own are not its candidates
          if (p - s + 1 >= std::uint32_t(kW)) continue;
          lanes &= ~((1 << (p - s + 1)) - 1);
        }
        const F dx = V::sub(V::set1(x[p]), X), dy = V::sub(V::set1(y[p]), Y), dz = V::sub(V::set1(z[p]), Z);
        const F d2 = V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz));
        const F du = V::sub(U, V::set1(u[p])), dv = V::sub(W, V::set1(v[p]));
        const F nominal = V::add(V::mul(V::mul(du, du), test.a2), V::mul(V::mul(dv, dv), test.b2));
        // Within reach and not nominally near: the two compares' bits (on AVX-512 mask registers) combined, and the
        // pairs written whole vectors at a time (on AVX-512 without a branch: whether a vector holds one was
        // mispredicted at about half of them)
        const int bits = V::ltBits(d2, test.reach2) & ~V::ltBits(nominal, test.near_below) & lanes;
        V::fill(points + count, p);
        V::storeLanesMarked(slots + count, bits, s, V::geBits(d2, test.near2), kFarSlot);
        count += __builtin_popcount(unsigned(bits));
      }
    }
    return count;
  }
};

}  // namespace
}  // namespace drape
