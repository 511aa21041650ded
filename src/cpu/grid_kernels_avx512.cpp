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

GridKernels makeTable() {
  GridKernels table = Kernels<simd::Avx512>::table("avx512");
  table.tileBoxes = &tileBoxes;
  return table;
}

}  // namespace

const GridKernels& gridKernelsAvx512() {
  static const GridKernels table = makeTable();
  return table;
}

}  // namespace drape
