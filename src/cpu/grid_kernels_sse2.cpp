// The grid kernels at the x86-64 baseline (SSE2, four lanes), and the choice between instruction sets.
#include "cpu/grid_kernels.inl"

#include <stdexcept>

namespace drape {

GridShape GridShape::of(int w, int h) {
  GridShape g;
  g.W = w;
  g.H = h;
  // Room on the right for the widest overrun (two vectors of the widest set from the last spring of a row), so
  // that no lane of a row reaches the next row's padding, which another thread may be reading; whole cache lines.
  g.stride = (w + kLeft + 2 * kMaxWidth + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  g.size = std::size_t(h + kTop + 3) * std::size_t(g.stride);
  return g;
}

std::ptrdiff_t GridShape::at(int x, int y) const {
  return drape::at(*this, x, y);
}

const GridKernels& gridKernelsSse2() {
  static const GridKernels table = Kernels<simd::Sse2>::table("sse2");
  return table;
}

bool cpuHasAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

bool cpuHasAvx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
}

const GridKernels& gridKernels(GridIsa isa) {
  switch (isa) {
    case GridIsa::Sse2:
      return gridKernelsSse2();
    case GridIsa::Avx2:
      if (!cpuHasAvx2()) throw std::runtime_error("this CPU has no AVX2: the grid kernels run with SSE2");
      return gridKernelsAvx2();
    case GridIsa::Avx512:
      if (!cpuHasAvx512())
        throw std::runtime_error("this CPU has no AVX-512 (F, DQ, VL): the grid kernels run without");
      return gridKernelsAvx512();
    case GridIsa::Auto:
      break;
  }
  if (cpuHasAvx512()) return gridKernelsAvx512();
  return cpuHasAvx2() ? gridKernelsAvx2() : gridKernelsSse2();
}

}  // namespace drape
