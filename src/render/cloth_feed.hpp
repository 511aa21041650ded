// Where the renderer reads the cloth from: storage buffers of one vec4 per point (positions, unit
// normals, tangents). With the GPU solver they are the solver's own buffers, borrowed: nothing goes
// through the CPU. With a CPU solver the positions are uploaded once per drawn frame, explicitly,
// by CpuClothUpload, which also computes normals and tangents.
#pragma once

#include "core/solver.hpp"
#include "gl/objects.hpp"

#include <glm/glm.hpp>

#include <memory>
#include <vector>

namespace drape {

struct ClothBuffers {
  GLuint positions = 0;  // vec4: xyz position (m)
  GLuint normals = 0;    // vec4: xyz unit normal
  GLuint tangents = 0;   // vec4: xyz unit tangent along +u, w = bitangent sign (B = w * cross(N, T))
  GLuint health = 0;     // uint blow-up flags first (shared/layout.h Health): nonzero hides the cloth; 0: none
};

// Area-weighted vertex normals and UV tangents of the cloth's triangles, on the CPU. A point whose
// triangles all have zero area keeps a normal of +y.
void computeNormalsAndTangents(const Topology& topology, const std::vector<glm::vec4>& positions,
                               std::vector<glm::vec4>& normals, std::vector<glm::vec4>& tangents);

class CpuClothUpload {
 public:
  explicit CpuClothUpload(const Topology& topology);

  // The once-per-frame upload: reads the solver's positions (a CPU solver holds them in memory),
  // computes normals and tangents, uploads all three.
  ClothBuffers uploadFrom(Solver& solver);
  ClothBuffers buffers() const { return {positions_.id(), normals_.id(), tangents_.id()}; }

 private:
  const Topology* topology_;
  std::vector<glm::vec4> positions_cpu_, normals_cpu_, tangents_cpu_;
  gl::Buffer positions_, normals_, tangents_;
};

// One interface for the viewer and `drape render`: prepare() once per drawn frame gives the buffers
// to draw. For the GPU solver it runs the solver's normal pass (on the GPU) and hands out its buffers.
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
