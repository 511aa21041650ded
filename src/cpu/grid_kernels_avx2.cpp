// The grid kernels with AVX2 (eight lanes). Compiled with -mavx2 (CMakeLists.txt) and called only where the
// CPU has it (gridKernels): nothing else may be compiled here (see simd.hpp).
#include "cpu/grid_kernels.inl"

namespace drape {

const GridKernels& gridKernelsAvx2() {
  static const GridKernels table = Kernels<simd::Avx2>::table("avx2");
  return table;
}

}  // namespace drape
