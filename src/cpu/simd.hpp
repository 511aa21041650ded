// Vectors of floats for the grid kernels (cpu/grid_kernels.inl): one struct per instruction set, the same
// operations under the same names, so a kernel is written once and compiled for each. Only the kernels'
// translation units include this, each compiled for its own target (grid_kernels_sse2.cpp at the x86-64
// baseline, grid_kernels_avx2.cpp with -mavx2, grid_kernels_avx512.cpp with AVX-512 F, DQ and VL), and
// everything here is inline in an unnamed namespace:
// an AVX2 copy of a shared inline function must never be what the linker picks for the baseline code.
//
// Every operation is one IEEE-754 operation per lane, rounded to nearest (add, sub, mul, div, sqrt, and
// compares and bit selections that round nothing), so a lane computes exactly what the scalar expression
// computes: no reciprocal estimates, no fused multiply-add (the build keeps -ffp-contract=off).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>

namespace drape::simd {
namespace {

// Splitting consecutive points into even and odd ones, or into pairs, and back: the same shuffles in every set,
// made from its own (S::shuffle and S::unpack, which work within each 128-bit part of a vector). lo = p0..p(w-1) and
// hi = pw..p(2w-1) become the even and odd points in an order of their own (within each 128-bit part), which
// interleave undoes, or the pairs (p0 p1, p4 p5, ...) and (p2 p3, p6 p7, ...), which interleavePairs undoes. Also
// what every set makes alike from its compares.
template <class S>
struct LaneShuffles {
  // A compare's lanes as bits, bits(lt(a, b)) and the like: AVX-512 has its own, straight from the mask register
  // with no vector made of it
  template <class F>
  static int ltBits(F a, F b) {
    return S::bits(S::lt(a, b));
  }
  template <class F>
  static int leBits(F a, F b) {
    return S::bits(S::le(a, b));
  }
  template <class F>
  static int geBits(F a, F b) {
    return S::bits(S::ge(a, b));
  }
  template <class F>
  static F evens(F lo, F hi) {
    return S::template shuffle<_MM_SHUFFLE(2, 0, 2, 0)>(lo, hi);
  }
  template <class F>
  static F odds(F lo, F hi) {
    return S::template shuffle<_MM_SHUFFLE(3, 1, 3, 1)>(lo, hi);
  }
  template <class F>
  static void interleave(F e, F o, F& lo, F& hi) {
    lo = S::unpackLo(e, o);
    hi = S::unpackHi(e, o);
  }
  template <class F>
  static F pairsA(F lo, F hi) {
    return S::template shuffle<_MM_SHUFFLE(1, 0, 1, 0)>(lo, hi);
  }
  template <class F>
  static F pairsB(F lo, F hi) {
    return S::template shuffle<_MM_SHUFFLE(3, 2, 3, 2)>(lo, hi);
  }
  template <class F>
  static void interleavePairs(F a, F b, F& lo, F& hi) {
    lo = pairsA(a, b);
    hi = pairsB(a, b);
  }
  // Four vec3s a 128-bit part, x y z x y z ..., to and from a vector per coordinate (Intel's 3-way shuffle):
  // m0 = x0 y0 z0 x1, m1 = y1 z1 x2 y2, m2 = z2 x3 y3 z3 in each 128-bit lane.
  template <class V>
  static void split(V m0, V m1, V m2, V& x, V& y, V& z) {
    const V xy = S::template shuffle<_MM_SHUFFLE(2, 1, 3, 2)>(m1, m2);  // x2 y2 x3 y3
    const V yz = S::template shuffle<_MM_SHUFFLE(1, 0, 2, 1)>(m0, m1);  // y0 z0 y1 z1
    x = S::template shuffle<_MM_SHUFFLE(2, 0, 3, 0)>(m0, xy);
    y = S::template shuffle<_MM_SHUFFLE(3, 1, 2, 0)>(yz, xy);
    z = S::template shuffle<_MM_SHUFFLE(3, 0, 3, 1)>(yz, m2);
  }
  // A whole vector of vec3s whose indices lie within a few of the first, as a list's owners do (sorted, a few
  // entries each), from two loads instead of a gather: only where the set has a permute across the vector (AVX-512);
  // false where it has none or the indices do not qualify, and the caller gathers.
  template <class V>
  static bool loadVec3Near(const float*, const std::uint32_t*, std::size_t, V&, V&, V&) {
    return false;
  }
  // gatherVec3 of a whole vector (every lane live), where a set has a faster way for that
  template <class V>
  static void gatherVec3Whole(const float* x, const std::uint32_t* idx, V& gx, V& gy, V& gz, V& live) {
    S::gatherVec3(x, idx, S::kWidth, gx, gy, gz, live);
  }
  template <class V>
  static void join(V x, V y, V z, V& m0, V& m1, V& m2) {
    const V xy = S::template shuffle<_MM_SHUFFLE(2, 0, 2, 0)>(x, y);  // x0 x2 y0 y2
    const V yz = S::template shuffle<_MM_SHUFFLE(3, 1, 3, 1)>(y, z);  // y1 y3 z1 z3
    const V zx = S::template shuffle<_MM_SHUFFLE(3, 1, 2, 0)>(z, x);  // z0 z2 x1 x3
    m0 = S::template shuffle<_MM_SHUFFLE(2, 0, 2, 0)>(xy, zx);
    m1 = S::template shuffle<_MM_SHUFFLE(3, 1, 2, 0)>(yz, xy);
    m2 = S::template shuffle<_MM_SHUFFLE(3, 1, 3, 1)>(zx, yz);
  }
};

// Four lanes, the x86-64 baseline (SSE2 is part of it).
struct Sse2 : LaneShuffles<Sse2> {
  static constexpr int kWidth = 4;
  using F = __m128;
  static F load(const float* p) { return _mm_loadu_ps(p); }
  static void store(float* p, F v) { _mm_storeu_ps(p, v); }
  static F set1(float v) { return _mm_set1_ps(v); }
  static F iota() { return _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F div(F a, F b) { return _mm_div_ps(a, b); }
  // Each lane converted to int32 (truncated; |a| < 2^31), the int's bits in the lane
  static F intBits(F a) { return _mm_castsi128_ps(_mm_cvttps_epi32(a)); }
  // sqrt and div in the first `lanes` lanes (the others: anything); on the wider sets a narrower instruction where
  // those fit one, as the divider takes time by the lanes it is given (a 50-point row is three full vectors of
  // sixteen and one of two)
  static F sqrtFirst(F a, int) { return sqrt(a); }
  static F divFirst(F a, F b, int) { return div(a, b); }
  static F sqrt(F a) { return _mm_sqrt_ps(a); }
  static F neg(F a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
  static F le(F a, F b) { return _mm_cmple_ps(a, b); }  // false where either is NaN, as a scalar <=
  static F lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static F eq(F a, F b) { return _mm_cmpeq_ps(a, b); }
  static F andNot(F m, F a) { return _mm_andnot_ps(m, a); }  // ~m & a
  static F bitAnd(F a, F b) { return _mm_and_ps(a, b); }
  static F bitOr(F a, F b) { return _mm_or_ps(a, b); }
  static F ge(F a, F b) { return _mm_cmpge_ps(a, b); }  // false where either is NaN
  static bool any(F m) { return _mm_movemask_ps(m) != 0; }
  static int bits(F m) { return _mm_movemask_ps(m); }  // lane l's mask in bit l
  // base + l for each bit l of `lanes`, ascending, to out[0 ...], `mark` or-ed into the words of the lanes that
  // `marked` has; every lane's word may be written
  static void storeLanesMarked(std::uint32_t* out, int lanes, std::uint32_t base, int marked, std::uint32_t mark) {
    for (int k = 0; lanes != 0; lanes &= lanes - 1, ++k) {
      const int l = __builtin_ctz(unsigned(lanes));
      out[k] = (base + std::uint32_t(l)) | ((marked >> l) & 1 ? mark : 0);
    }
  }
  static void fill(std::uint32_t* out, std::uint32_t v) {  // v to out[0 ... kWidth - 1]
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_set1_epi32(int(v)));
  }
  static F min(F a, F b) { return _mm_min_ps(a, b); }  // b where either is NaN
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static F select(F m, F a, F b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }  // m ? a : b
  // floor, for |a| < 2^31 (no SSE4.1 round here): truncate, then one less where that rounded up
  static F floor(F a) {
    const F t = _mm_cvtepi32_ps(_mm_cvttps_epi32(a));
    return _mm_sub_ps(t, _mm_and_ps(_mm_cmpgt_ps(t, a), _mm_set1_ps(1.0f)));
  }
  // The least and the greatest lane (of finite lanes; which zero of +0 and -0 is not said)
  static float hmin(F a) {
    a = _mm_min_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(_mm_min_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1))));
  }
  static float hmax(F a) {
    a = _mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(_mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1))));
  }
  static F negZero(F a) {  // lanes holding -0 exactly (an == compare would take +0 too)
    return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_castps_si128(a), _mm_set1_epi32(INT32_MIN)));
  }
  // The vec3s x[idx[l]] of the first `count` lanes (count <= kWidth), and those lanes' mask. No gather
  // instruction before AVX2: loaded one by one.
  static void gatherVec3(const float* x, const std::uint32_t* idx, int count, F& gx, F& gy, F& gz, F& live) {
    float a[4] = {}, b[4] = {}, c[4] = {}, m[4] = {};
    const std::uint32_t all = ~std::uint32_t(0);
    for (int l = 0; l < count; ++l) {
      a[l] = x[3 * std::size_t(idx[l])];
      b[l] = x[3 * std::size_t(idx[l]) + 1];
      c[l] = x[3 * std::size_t(idx[l]) + 2];
      std::memcpy(&m[l], &all, sizeof(float));
    }
    gx = load(a);
    gy = load(b);
    gz = load(c);
    live = load(m);
  }
  // base[idx[l]] in lane l: loaded one by one.
  static F gather(const float* base, const std::int32_t* idx) {
    return _mm_set_ps(base[idx[3]], base[idx[2]], base[idx[1]], base[idx[0]]);
  }
  // kWidth vec3s, x y z x y z ..., to and from a vector per coordinate (Intel's 3-way shuffle).
  static void loadVec3(const float* p, F& x, F& y, F& z) { split(load(p), load(p + 4), load(p + 8), x, y, z); }
  static void storeVec3(float* p, F x, F y, F z) {
    F m0, m1, m2;
    join(x, y, z, m0, m1, m2);
    store(p, m0);
    store(p + 4, m1);
    store(p + 8, m2);
  }
  template <int kImm>
  static __m128 shuffle(__m128 a, __m128 b) {
    return _mm_shuffle_ps(a, b, kImm);
  }
  static __m128 unpackLo(__m128 a, __m128 b) { return _mm_unpacklo_ps(a, b); }
  static __m128 unpackHi(__m128 a, __m128 b) { return _mm_unpackhi_ps(a, b); }
};

#ifdef __AVX2__
// Eight lanes. The shuffles work within each 128-bit half, so evens/odds and the pairs come out in an order
// of their own; interleave puts every point back where it was, which is all the kernels need.
struct Avx2 : LaneShuffles<Avx2> {
  static constexpr int kWidth = 8;
  using F = __m256;
  static F load(const float* p) { return _mm256_loadu_ps(p); }
  static void store(float* p, F v) { _mm256_storeu_ps(p, v); }
  static F set1(float v) { return _mm256_set1_ps(v); }
  static F iota() { return _mm256_set_ps(7.0f, 6.0f, 5.0f, 4.0f, 3.0f, 2.0f, 1.0f, 0.0f); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F div(F a, F b) { return _mm256_div_ps(a, b); }
  static F intBits(F a) { return _mm256_castsi256_ps(_mm256_cvttps_epi32(a)); }
  static F sqrt(F a) { return _mm256_sqrt_ps(a); }
  static F sqrtFirst(F a, int lanes) {
    return lanes <= 4 ? _mm256_zextps128_ps256(_mm_sqrt_ps(_mm256_castps256_ps128(a))) : sqrt(a);
  }
  static F divFirst(F a, F b, int lanes) {
    return lanes <= 4 ? _mm256_zextps128_ps256(_mm_div_ps(_mm256_castps256_ps128(a), _mm256_castps256_ps128(b)))
                      : div(a, b);
  }
  static F neg(F a) { return _mm256_xor_ps(a, _mm256_set1_ps(-0.0f)); }
  static F le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  static F lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static F eq(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
  static F andNot(F m, F a) { return _mm256_andnot_ps(m, a); }
  static F bitAnd(F a, F b) { return _mm256_and_ps(a, b); }
  static F bitOr(F a, F b) { return _mm256_or_ps(a, b); }
  static F ge(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
  static bool any(F m) { return _mm256_movemask_ps(m) != 0; }
  static int bits(F m) { return _mm256_movemask_ps(m); }
  static void storeLanesMarked(std::uint32_t* out, int lanes, std::uint32_t base, int marked, std::uint32_t mark) {
    Sse2::storeLanesMarked(out, lanes, base, marked, mark);
  }
  static void fill(std::uint32_t* out, std::uint32_t v) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_set1_epi32(int(v)));
  }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
  static F select(F m, F a, F b) { return _mm256_blendv_ps(b, a, m); }
  static F floor(F a) { return _mm256_floor_ps(a); }
  static float hmin(F a) { return Sse2::hmin(_mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1))); }
  static float hmax(F a) { return Sse2::hmax(_mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1))); }
  static F negZero(F a) {
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_castps_si256(a), _mm256_set1_epi32(INT32_MIN)));
  }
  // Nothing is read for the lanes past `count` (they are 0). Each point's x, y, z by a masked 128-bit load
  // (the fourth float is not read), then transposed: three gathers cost about three times as much here (Zen 4,
  // the self-collision sweep's lists).
  static void gatherVec3(const float* x, const std::uint32_t* idx, int count, F& gx, F& gy, F& gz, F& live) {
    live = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(count), _mm256_set_epi32(7, 6, 5, 4, 3, 2, 1, 0)));
    const __m128i xyz = _mm_set_epi32(0, -1, -1, -1);
    __m128 p[8];
    if (count >= 8) {
      for (int l = 0; l < 8; ++l)
        p[l] = _mm_maskload_ps(x + 3 * std::size_t(idx[l]), xyz);
    } else {
      for (int l = 0; l < 8; ++l)
        p[l] = l < count ? _mm_maskload_ps(x + 3 * std::size_t(idx[l]), xyz) : _mm_setzero_ps();
    }
    // Points 0-3 in the low halves, 4-7 in the high ones, each half a 4 x 4 transpose
    const F r0 = _mm256_insertf128_ps(_mm256_castps128_ps256(p[0]), p[4], 1);
    const F r1 = _mm256_insertf128_ps(_mm256_castps128_ps256(p[1]), p[5], 1);
    const F r2 = _mm256_insertf128_ps(_mm256_castps128_ps256(p[2]), p[6], 1);
    const F r3 = _mm256_insertf128_ps(_mm256_castps128_ps256(p[3]), p[7], 1);
    const F t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1);  // x0 x1 y0 y1, z0 z1 - -
    const F t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3);
    gx = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    gy = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    gz = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
  }
  // base[idx[l]] in lane l (every index valid).
  static F gather(const float* base, const std::int32_t* idx) {
    // Eight loads: a gather instruction costs more here (Zen 4)
    return _mm256_setr_ps(base[idx[0]], base[idx[1]], base[idx[2]], base[idx[3]], base[idx[4]], base[idx[5]],
                          base[idx[6]], base[idx[7]]);
  }
  template <int kImm>
  static F shuffle(F a, F b) {
    return _mm256_shuffle_ps(a, b, kImm);
  }
  static F unpackLo(F a, F b) { return _mm256_unpacklo_ps(a, b); }
  static F unpackHi(F a, F b) { return _mm256_unpackhi_ps(a, b); }
  // Points 0-3 in the low halves, 4-7 in the high ones, then the 128-bit split and join on both at once.
  static void loadVec3(const float* p, F& x, F& y, F& z) {
    const F m0 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p)), _mm_loadu_ps(p + 12), 1);
    const F m1 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p + 4)), _mm_loadu_ps(p + 16), 1);
    const F m2 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p + 8)), _mm_loadu_ps(p + 20), 1);
    split(m0, m1, m2, x, y, z);
  }
  static void storeVec3(float* p, F x, F y, F z) {
    F m0, m1, m2;
    join(x, y, z, m0, m1, m2);
    _mm_storeu_ps(p, _mm256_castps256_ps128(m0));
    _mm_storeu_ps(p + 4, _mm256_castps256_ps128(m1));
    _mm_storeu_ps(p + 8, _mm256_castps256_ps128(m2));
    _mm_storeu_ps(p + 12, _mm256_extractf128_ps(m0, 1));
    _mm_storeu_ps(p + 16, _mm256_extractf128_ps(m1, 1));
    _mm_storeu_ps(p + 20, _mm256_extractf128_ps(m2, 1));
  }
};
#endif

#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
// Sixteen lanes. A mask is a vector with all bits set or clear in a lane, as in the narrower sets, so the kernels'
// bit operations on masks stay as they are: a compare goes through a mask register and back (movm, DQ), a select
// the other way. Shuffles work within each 128-bit quarter, as AVX2's within each half. A vec3 load or store, a
// gather, a reduction: two of AVX2's, one a half.
struct Avx512 : LaneShuffles<Avx512> {
  static constexpr int kWidth = 16;
  using F = __m512;
  using Half = __m256;
  static F fromMask(__mmask16 k) { return _mm512_castsi512_ps(_mm512_movm_epi32(k)); }
  static __mmask16 toMask(F m) { return _mm512_movepi32_mask(_mm512_castps_si512(m)); }
  static F halves(Half lo, Half hi) { return _mm512_insertf32x8(_mm512_castps256_ps512(lo), hi, 1); }
  static Half low(F a) { return _mm512_castps512_ps256(a); }
  static Half high(F a) { return _mm512_extractf32x8_ps(a, 1); }
  static F load(const float* p) { return _mm512_loadu_ps(p); }
  static void store(float* p, F v) { _mm512_storeu_ps(p, v); }
  static F set1(float v) { return _mm512_set1_ps(v); }
  static F iota() { return _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
  static F add(F a, F b) { return _mm512_add_ps(a, b); }
  static F sub(F a, F b) { return _mm512_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
  static F div(F a, F b) { return _mm512_div_ps(a, b); }
  static F intBits(F a) { return _mm512_castsi512_ps(_mm512_cvttps_epi32(a)); }
  static F sqrt(F a) { return _mm512_sqrt_ps(a); }
  static F sqrtFirst(F a, int lanes) {
    if (lanes <= 4) return _mm512_zextps128_ps512(_mm_sqrt_ps(_mm512_castps512_ps128(a)));
    if (lanes <= 8) return _mm512_zextps256_ps512(_mm256_sqrt_ps(_mm512_castps512_ps256(a)));
    return sqrt(a);
  }
  static F divFirst(F a, F b, int lanes) {
    if (lanes <= 4) return _mm512_zextps128_ps512(_mm_div_ps(_mm512_castps512_ps128(a), _mm512_castps512_ps128(b)));
    if (lanes <= 8) return _mm512_zextps256_ps512(_mm256_div_ps(_mm512_castps512_ps256(a), _mm512_castps512_ps256(b)));
    return div(a, b);
  }
  static F neg(F a) { return _mm512_xor_ps(a, _mm512_set1_ps(-0.0f)); }
  static F le(F a, F b) { return fromMask(_mm512_cmp_ps_mask(a, b, _CMP_LE_OQ)); }
  static F lt(F a, F b) { return fromMask(_mm512_cmp_ps_mask(a, b, _CMP_LT_OQ)); }
  static F eq(F a, F b) { return fromMask(_mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ)); }
  static F ge(F a, F b) { return fromMask(_mm512_cmp_ps_mask(a, b, _CMP_GE_OQ)); }
  static F andNot(F m, F a) { return _mm512_andnot_ps(m, a); }
  static F bitAnd(F a, F b) { return _mm512_and_ps(a, b); }
  static F bitOr(F a, F b) { return _mm512_or_ps(a, b); }
  static bool any(F m) { return toMask(m) != 0; }
  static int bits(F m) { return int(toMask(m)); }
  static int ltBits(F a, F b) { return int(_mm512_cmp_ps_mask(a, b, _CMP_LT_OQ)); }
  static int leBits(F a, F b) { return int(_mm512_cmp_ps_mask(a, b, _CMP_LE_OQ)); }
  static int geBits(F a, F b) { return int(_mm512_cmp_ps_mask(a, b, _CMP_GE_OQ)); }
  // The lanes' numbers compressed in a register and stored whole: no branch a lane (the memory form of compress is
  // microcoded on Intel)
  static void storeLanesMarked(std::uint32_t* out, int lanes, std::uint32_t base, int marked, std::uint32_t mark) {
    const __m512i numbers = _mm512_add_epi32(_mm512_set1_epi32(int(base)),
                                             _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
    const __m512i words = _mm512_mask_or_epi32(numbers, __mmask16(marked), numbers, _mm512_set1_epi32(int(mark)));
    _mm512_storeu_si512(out, _mm512_maskz_compress_epi32(__mmask16(lanes), words));
  }
  static void fill(std::uint32_t* out, std::uint32_t v) { _mm512_storeu_si512(out, _mm512_set1_epi32(int(v))); }
  static F min(F a, F b) { return _mm512_min_ps(a, b); }
  static F max(F a, F b) { return _mm512_max_ps(a, b); }
  static F select(F m, F a, F b) { return _mm512_mask_blend_ps(toMask(m), b, a); }
  static F floor(F a) { return _mm512_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
  static float hmin(F a) { return Avx2::hmin(_mm256_min_ps(low(a), high(a))); }
  static float hmax(F a) { return Avx2::hmax(_mm256_max_ps(low(a), high(a))); }
  static F negZero(F a) {
    return fromMask(_mm512_cmpeq_epi32_mask(_mm512_castps_si512(a), _mm512_set1_epi32(INT32_MIN)));
  }
  static void gatherVec3(const float* x, const std::uint32_t* idx, int count, F& gx, F& gy, F& gz, F& live) {
    Half ax, ay, az, al, bx, by, bz, bl;
    Avx2::gatherVec3(x, idx, count < 8 ? count : 8, ax, ay, az, al);
    if (count > 8) {
      Avx2::gatherVec3(x, idx + 8, count - 8, bx, by, bz, bl);
    } else {
      bx = by = bz = bl = _mm256_setzero_ps();
    }
    gx = halves(ax, bx);
    gy = halves(ay, by);
    gz = halves(az, bz);
    live = halves(al, bl);
  }
  static F gather(const float* base, const std::int32_t* idx) {
    return halves(Avx2::gather(base, idx), Avx2::gather(base, idx + 8));
  }
  // On Intel, three gather instructions: measured there (Sapphire Rapids) a sixteen-lane gather costs less than the
  // sixteen loads and transposes of gatherVec3 (a list's partners in pairTerms: 2.5 against 3.8 cycles an entry for
  // both ends in a loop of their own; CS184's selfCollision 0.99 of the time on one thread). Elsewhere gatherVec3:
  // AVX2's gathers measured three times the loads' cost on Zen 4, and no AMD processor was at hand to measure these.
  static void gatherVec3Whole(const float* x, const std::uint32_t* idx, F& gx, F& gy, F& gz, F& live) {
    static const bool intel = __builtin_cpu_is("intel");
    if (!intel) return gatherVec3(x, idx, kWidth, gx, gy, gz, live);
    __m512i at = _mm512_loadu_si512(idx);
    at = _mm512_add_epi32(at, _mm512_add_epi32(at, at));
    gx = _mm512_i32gather_ps(at, x, 4);
    gy = _mm512_i32gather_ps(at, x + 1, 4);
    gz = _mm512_i32gather_ps(at, x + 2, 4);
    live = _mm512_castsi512_ps(_mm512_set1_epi32(-1));
  }
  // Sixteen indices within kNear - 1 of the first, whose 3 kNear floats lie inside the `points` vec3s at x: each
  // coordinate one permute of the 32 floats from the first point on. CS184's selfCollision: 76% of the list's vectors
  // of owners span 9 or fewer; their two gathers' loads and transposes were half of pairTerms' time.
  static constexpr std::uint32_t kNear = 10;
  static bool loadVec3Near(const float* x, const std::uint32_t* idx, std::size_t points, F& gx, F& gy, F& gz) {
    const std::uint32_t first = idx[0];
    if (3 * std::size_t(first) + 32 > 3 * points) return false;  // the two loads' 32 floats, not only those used
    const __m512i from = _mm512_sub_epi32(_mm512_loadu_si512(idx), _mm512_set1_epi32(int(first)));
    if (_mm512_cmpgt_epu32_mask(from, _mm512_set1_epi32(int(kNear - 1))) != 0) return false;
    const __m512i at = _mm512_add_epi32(from, _mm512_add_epi32(from, from)), one = _mm512_set1_epi32(1);
    const float* p = x + 3 * std::size_t(first);
    const __m512 a = _mm512_loadu_ps(p), b = _mm512_loadu_ps(p + 16);
    gx = _mm512_permutex2var_ps(a, at, b);
    gy = _mm512_permutex2var_ps(a, _mm512_add_epi32(at, one), b);
    gz = _mm512_permutex2var_ps(a, _mm512_add_epi32(at, _mm512_add_epi32(one, one)), b);
    return true;
  }
  template <int kImm>
  static F shuffle(F a, F b) {
    return _mm512_shuffle_ps(a, b, kImm);
  }
  static F unpackLo(F a, F b) { return _mm512_unpacklo_ps(a, b); }
  static F unpackHi(F a, F b) { return _mm512_unpackhi_ps(a, b); }
  static void loadVec3(const float* p, F& x, F& y, F& z) {
    Half ax, ay, az, bx, by, bz;
    Avx2::loadVec3(p, ax, ay, az);
    Avx2::loadVec3(p + 24, bx, by, bz);
    x = halves(ax, bx);
    y = halves(ay, by);
    z = halves(az, bz);
  }
  static void storeVec3(float* p, F x, F y, F z) {
    Avx2::storeVec3(p, low(x), low(y), low(z));
    Avx2::storeVec3(p + 24, high(x), high(y), high(z));
  }
};
#endif

}  // namespace
}  // namespace drape::simd
