#include "cpu/parallel.hpp"

namespace drape {

void runOnTeam(int threads, const std::function<void()>& body) {
#pragma omp parallel num_threads(threads)
  body();
}

}  // namespace drape
