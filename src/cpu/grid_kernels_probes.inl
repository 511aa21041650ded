// The machine probes of `drape bench --roofline` (cpu/machine_peak.hpp) in the grid kernels' vectors: part of
// cpu/grid_kernels.inl (which includes this file once, inside the same rules: nothing here may be a non-inline symbol
// shared with other units), kept apart for its size.
#pragma once

namespace drape {
namespace {

template <class V>
struct ProbeKernels : Lanes<V> {
  using F = typename V::F;
  static constexpr int kW = V::kWidth;
  using Lanes<V>::sum;

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
};

}  // namespace
}  // namespace drape
