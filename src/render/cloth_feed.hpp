// Where the renderer reads the cloth from: a storage buffer of one vec4 position per point (the renderer
// computes the normals and tangents it draws with from these: render/surface_pass.hpp). With the GPU solver
// it is the solver's own buffer, borrowed: nothing goes through the CPU. With a CPU solver the positions
// are uploaded once per drawn frame, explicitly, by CpuClothUpload.
#pragma once

#include "core/solver.hpp"
#include "gl/objects.hpp"

#include <glm/glm.hpp>

#include <memory>
#include <vector>

namespace drape {

struct ClothBuffers {
  GLuint positions = 0;  // vec4: xyz position (m)
  GLuint health = 0;     // uint blow-up flags first (shared/layout.h Health): nonzero hides the cloth; 0: none
};

class CpuClothUpload {
 public:
  explicit CpuClothUpload(const Topology& topology);

  // The once-per-frame upload: reads the solver's positions (a CPU solver holds them in memory) and
  // uploads them.
  ClothBuffers uploadFrom(Solver& solver);
  ClothBuffers buffers() const { return {positions_.id()}; }

 private:
  std::vector<glm::vec4> positions_cpu_;
  gl::Buffer positions_;
};

// One interface for the viewer and `drape render`: prepare() once per drawn frame gives the buffers
// to draw. For the GPU solver it hands out the solver's own buffers.
class ClothFeed {
 public:
  explicit ClothFeed(Solver& solver);
  ClothBuffers prepare();
  bool borrowsSolverBuffers() const { return upload_ == nullptr; }

 private:
  Solver* solver_;
  std::unique_ptr<CpuClothUpload> upload_;
};

}  // namespace drape
