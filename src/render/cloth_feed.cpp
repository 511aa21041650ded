#include "render/cloth_feed.hpp"

#include "gpu/gpu_solver.hpp"

namespace drape {

CpuClothUpload::CpuClothUpload(const Topology& topology)
    : positions_(gl::Buffer::create(sizeof(glm::vec4) * topology.pointCount())) {}

ClothBuffers CpuClothUpload::uploadFrom(Solver& solver) {
  const std::vector<glm::dvec3> x = solver.readPositions();
  positions_cpu_.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    positions_cpu_[i] = glm::vec4(glm::vec3(x[i]), 1.0f);
  positions_.upload(positions_cpu_);
  return buffers();
}

ClothFeed::ClothFeed(Solver& solver) : solver_(&solver) {
  if (!dynamic_cast<GpuSolver*>(&solver)) upload_ = std::make_unique<CpuClothUpload>(solver.topology());
}

ClothBuffers ClothFeed::prepare() {
  if (upload_) return upload_->uploadFrom(*solver_);
  auto& gpu = static_cast<GpuSolver&>(*solver_);
  return {gpu.positionBuffer().id(), gpu.healthBuffer().id()};
}

}  // namespace drape
