// The grid kernels' instruction sets this CPU runs, for the tests that hold each against the scalar code or the others:
// SSE2 always, AVX2 and AVX-512 where it has them.
#pragma once

#include "cpu/grid_kernels.hpp"

#include <vector>

namespace drape::test {

inline std::vector<GridIsa> cpuIsas() {
  std::vector<GridIsa> out = {GridIsa::Sse2};
  if (cpuHasAvx2()) out.push_back(GridIsa::Avx2);
  if (cpuHasAvx512()) out.push_back(GridIsa::Avx512);
  return out;
}

inline std::vector<const GridKernels*> kernelSets() {
  std::vector<const GridKernels*> out;
  for (const GridIsa isa : cpuIsas())
    out.push_back(&gridKernels(isa));
  return out;
}

}  // namespace drape::test
