// VBD's grid kernel over the vector type V, each lane following the scalar code it names operation for
// operation: part of cpu/grid_kernels.inl (which includes this file once, inside the same rules: nothing here
// may be a non-inline symbol shared with other units), kept apart for its size.
#pragma once

namespace drape {
namespace {

template <class V>
struct VbdKernels : Lanes<V> {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;
  using Lanes<V>::onGrid;

  // VBD, one sweep: each lane one point of the colour, as solveVbd computes it (f = 0 and the block m/dt^2 I
  // from the prediction, then vbdAddSpring for every enabled spring in the adjacency's order: per direction
  // the spring that ends at the point, then the one that starts there; then vbdStep), the point and its
  // neighbours gathered by their padded indices and the point scattered back. Lanes past `last` repeat the
  // first point and are dropped.
  static void vbdPoints(const GridVbdArgs& a, long long first, long long last) {
    const GridShape& g = a.shape;
    const bool displacements = a.vx != nullptr;
    const F zero = V::set1(0.0f), one = V::set1(1.0f), dt2 = V::set1(a.dt2);
    alignas(32) std::int32_t q[kW], o[kW];
    alignas(32) float xs_lane[kW], ys_lane[kW];
    for (long long k0 = first; k0 < last; k0 += kW) {
      const int count = int(std::min<long long>(kW, last - k0));
      for (int l = 0; l < kW; ++l) {
        const long long e = k0 + (l < count ? l : 0);
        q[l] = a.padded[e];
        xs_lane[l] = a.column[e];
        ys_lane[l] = a.row[e];
      }
      const F px = V::load(xs_lane), py = V::load(ys_lane);
      const F live = V::lt(V::iota(), V::set1(float(count)));
      const F X = V::gather(a.x, q), Y = V::gather(a.y, q), Z = V::gather(a.z, q);
      const F moves = V::andNot(V::gather(a.pinned, q), live);
      if (!V::any(moves)) continue;
      const F inertia = V::div(one, V::mul(V::gather(a.inv_mass, q), dt2));  // m / dt^2
      F fx = zero, fy = zero, fz = zero, hxx = inertia, hyy = inertia, hzz = inertia, hxy = zero, hxz = zero,
        hyz = zero;
      if (a.target_x && a.sweep > 0) {  // (-inertia) (x - y)
        const F ni = V::neg(inertia);
        fx = V::mul(ni, V::sub(X, V::gather(a.target_x, q)));
        fy = V::mul(ni, V::sub(Y, V::gather(a.target_y, q)));
        fz = V::mul(ni, V::sub(Z, V::gather(a.target_z, q)));
      }
      // vbdAddSpring in the lanes of `exists`
      const auto spring = [&](F exists, const float* rest_at_base, std::ptrdiff_t other, F k) {
        for (int l = 0; l < kW; ++l)
          o[l] = std::int32_t(q[l] + other);
        const F dx = V::sub(V::gather(a.x, o), X), dy = V::sub(V::gather(a.y, o), Y), dz = V::sub(V::gather(a.z, o), Z);
        const F rest = V::gather(rest_at_base, other < 0 ? o : q);
        const F len = V::sqrt(V::add(V::add(V::mul(dx, dx), V::mul(dy, dy)), V::mul(dz, dz)));
        const F on = V::andNot(V::le(len, zero), exists);  // the scalar code returns where len <= 0
        const F c = V::div(V::mul(k, V::sub(len, rest)), len);
        fx = V::select(on, V::add(fx, V::mul(c, dx)), fx);
        fy = V::select(on, V::add(fy, V::mul(c, dy)), fy);
        fz = V::select(on, V::add(fz, V::mul(c, dz)), fz);
        const F s = V::select(V::lt(rest, len), V::sub(one, V::div(rest, len)), zero);
        const F aa = V::div(V::mul(k, V::sub(one, s)), V::mul(len, len));
        const F bb = V::mul(k, s);
        const F ax = V::mul(aa, dx), ay = V::mul(aa, dy);
        hxx = V::select(on, V::add(hxx, V::add(V::mul(ax, dx), bb)), hxx);
        hyy = V::select(on, V::add(hyy, V::add(V::mul(ay, dy), bb)), hyy);
        hzz = V::select(on, V::add(hzz, V::add(V::mul(V::mul(aa, dz), dz), bb)), hzz);
        hxy = V::select(on, V::add(hxy, V::mul(ax, dy)), hxy);
        hxz = V::select(on, V::add(hxz, V::mul(ax, dz)), hxz);
        hyz = V::select(on, V::add(hyz, V::mul(ay, dz)), hyz);
      };
      for (int d = 0; d < 6; ++d) {
        if (!a.springs.enabled[d]) continue;
        const F k = V::set1(a.springs.k[d]);
        const std::ptrdiff_t offset = kDx[d] + std::ptrdiff_t(kDy[d]) * g.stride;
        const F rows_before = V::le(V::set1(float(kDy[d])), py);  // py - dy >= 0
        const F rows_after = V::lt(V::add(py, V::set1(float(kDy[d]))), V::set1(float(g.H)));
        spring(V::bitAnd(V::bitAnd(rows_before, onGrid(px, -kDx[d], g.W)), moves), a.springs.rest[d], -offset, k);
        spring(V::bitAnd(V::bitAnd(rows_after, onGrid(px, kDx[d], g.W)), moves), a.springs.rest[d], offset, k);
      }
      // vbdStep: the LDL^T solve, no step where a pivot is not positive (NaN included)
      const F d0 = hxx;
      const F l10 = V::div(hxy, d0), l20 = V::div(hxz, d0);
      const F d1 = V::sub(hyy, V::mul(l10, hxy));
      const F l21 = V::div(V::sub(hyz, V::mul(l20, hxy)), d1);
      const F d2 = V::sub(V::sub(hzz, V::mul(l20, hxz)), V::mul(V::mul(l21, l21), d1));
      const F ok = V::bitAnd(V::bitAnd(V::lt(zero, d0), V::lt(zero, d1)), V::lt(zero, d2));
      const F z0 = fx, z1 = V::sub(fy, V::mul(l10, z0));
      const F z2 = V::sub(V::sub(fz, V::mul(l20, z0)), V::mul(l21, z1));
      const F x2 = V::div(z2, d2);
      const F x1 = V::sub(V::div(z1, d1), V::mul(l21, x2));
      const F x0 = V::sub(V::sub(V::div(z0, d0), V::mul(l10, x1)), V::mul(l20, x2));
      const F sx = V::select(ok, x0, zero), sy = V::select(ok, x1, zero), sz = V::select(ok, x2, zero);
      alignas(32) float nx[kW], ny[kW], nz[kW], vx[kW], vy[kW], vz[kW];
      V::store(nx, V::add(X, sx));
      V::store(ny, V::add(Y, sy));
      V::store(nz, V::add(Z, sz));
      if (displacements) {
        V::store(vx, V::add(V::gather(a.vx, q), sx));
        V::store(vy, V::add(V::gather(a.vy, q), sy));
        V::store(vz, V::add(V::gather(a.vz, q), sz));
      }
      const int write = V::bits(moves);
      alignas(32) float px0[kW], py0[kW], pz0[kW];
      const bool keep_target = a.target_x && a.sweep == 0;
      if (keep_target) {
        V::store(px0, X);
        V::store(py0, Y);
        V::store(pz0, Z);
      }
      for (int l = 0; l < count; ++l) {
        if (!(write >> l & 1)) continue;
        if (keep_target) {
          a.target_x[q[l]] = px0[l];
          a.target_y[q[l]] = py0[l];
          a.target_z[q[l]] = pz0[l];
        }
        a.x[q[l]] = nx[l];
        a.y[q[l]] = ny[l];
        a.z[q[l]] = nz[l];
        if (!displacements) continue;
        a.vx[q[l]] = vx[l];
        a.vy[q[l]] = vy[l];
        a.vz[q[l]] = vz[l];
      }
    }
  }
};

}  // namespace
}  // namespace drape
