// The grid kernels with AVX-512 (sixteen lanes; F, DQ and VL). Compiled with those flags (CMakeLists.txt) and
// called only where the CPU has all three (gridKernels): nothing else may be compiled here (see simd.hpp).
#include "cpu/grid_kernels.inl"

namespace drape {
namespace {

// A tile's row of 8 points (CS184's 50 x 50 files) fills half a vector of sixteen and a whole one of eight, and the
// reductions at a tile's end are wider: there AVX2's kernel (pinned2's check: 401 perf samples against 599).
bool tileBoxes(const TileBoxArgs& a) {
  return a.edge <= simd::Avx2::kWidth ? ContactKernels<simd::Avx2>::tileBoxes(a)
                                      : ContactKernels<simd::Avx512>::tileBoxes(a);
}

// Sixteen pairs at a time: the points by gathers, those kept (and each output's) packed by compresses. A build files
// a few pairs a cell, and filed one at a time as each cell's were found they cost a fifth of the build's search
// (CS184's selfCollision: 4,066 pairs a build, 23 cycles each); scanned over many cells first and filed together
// here, a few cycles each.
void filePairs(const PairFileArgs& a, const std::uint32_t* points, const std::uint32_t* slots, int count,
               FiledPair* const out[2], int counts[2]) {
  const __m512i box = _mm512_set1_epi32(a.box), less_box = _mm512_set1_epi32(-a.box);
  const __m512i side = _mm512_set1_epi32(2 * a.box + 1), far_bit = _mm512_set1_epi32(int(kFarSlot));
  const __m512i low16 = _mm512_set1_epi32(0xffff), split = _mm512_set1_epi32(int(a.split)),
                zero = _mm512_setzero_si512();
  // Pairs 0-15 from two vectors of lower and upper ends interleaved within 128-bit lanes by the unpacks
  const __m512i first_half = _mm512_setr_epi64(0, 1, 8, 9, 2, 3, 10, 11);
  const __m512i second_half = _mm512_setr_epi64(4, 5, 12, 13, 6, 7, 14, 15);
  int n[2] = {0, 0};
  for (int k = 0; k < count; k += 16) {
    const __mmask16 live = count - k >= 16 ? __mmask16(0xffff) : __mmask16((1u << (count - k)) - 1);
    const __m512i p = _mm512_maskz_loadu_epi32(live, points + k), s = _mm512_maskz_loadu_epi32(live, slots + k);
    const __m512i far = _mm512_and_si512(s, far_bit);
    const __m512i i = _mm512_mask_i32gather_epi32(zero, live, p, a.sorted, 4);
    const __m512i j = _mm512_mask_i32gather_epi32(zero, live, _mm512_andnot_si512(far_bit, s), a.sorted, 4);
    const __m512i uv_i = _mm512_mask_i32gather_epi32(zero, live, i, a.uv, 4);
    const __m512i uv_j = _mm512_mask_i32gather_epi32(zero, live, j, a.uv, 4);
    const __m512i du = _mm512_sub_epi32(_mm512_and_si512(uv_j, low16), _mm512_and_si512(uv_i, low16));
    const __m512i dv = _mm512_sub_epi32(_mm512_srli_epi32(uv_j, 16), _mm512_srli_epi32(uv_i, 16));
    const __mmask16 in_box = _mm512_mask_cmple_epi32_mask(live, du, box) & _mm512_cmpge_epi32_mask(du, less_box) &
                             _mm512_cmple_epi32_mask(dv, box) & _mm512_cmpge_epi32_mask(dv, less_box);
    const __m512i at = _mm512_add_epi32(_mm512_mullo_epi32(_mm512_add_epi32(dv, box), side), _mm512_add_epi32(du, box));
    const __m512i kind = _mm512_mask_i32gather_epi32(zero, in_box, at, a.kind, 4);
    const __mmask16 keep = (live & ~in_box) | _mm512_mask_cmpeq_epi32_mask(in_box, kind, zero);
    const __m512i lower = _mm512_min_epu32(i, j), upper = _mm512_or_si512(_mm512_max_epu32(i, j), far);
    const __mmask16 below = _mm512_cmplt_epu32_mask(lower, split);
    for (int d = 0; d < 2; ++d) {
      const __mmask16 to = keep & (d == 0 ? below : __mmask16(~below));
      if (to == 0) continue;
      const __m512i lo = _mm512_maskz_compress_epi32(to, lower), hi = _mm512_maskz_compress_epi32(to, upper);
      const __m512i even = _mm512_unpacklo_epi32(lo, hi), odd = _mm512_unpackhi_epi32(lo, hi);
      __m512i* const at_out = reinterpret_cast<__m512i*>(out[d] + n[d]);
      _mm512_storeu_si512(at_out, _mm512_permutex2var_epi64(even, first_half, odd));
      _mm512_storeu_si512(at_out + 1, _mm512_permutex2var_epi64(even, second_half, odd));
      n[d] += __builtin_popcount(unsigned(to));
    }
  }
  counts[0] = n[0];
  counts[1] = n[1];
}

GridKernels makeTable() {
  GridKernels table = Kernels<simd::Avx512>::table("avx512");
  table.tileBoxes = &tileBoxes;
  table.filePairs = &filePairs;
  return table;
}

}  // namespace

const GridKernels& gridKernelsAvx512() {
  static const GridKernels table = makeTable();
  return table;
}

}  // namespace drape
