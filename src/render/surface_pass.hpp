// The cloth's surface pass on the GPU (glsl/render/cloth_surface.comp; what it computes and why:
// render/cloth_surface.hpp): from the positions the renderer borrows or uploads, the normals, tangents and
// quad centres it draws the cloth with, in buffers it owns, two dispatches a drawn frame.
#pragma once

#include "core/topology.hpp"
#include "gl/objects.hpp"
#include "render/cloth_surface.hpp"

#include <string>

namespace drape {

class SurfacePass {
 public:
  explicit SurfacePass(const Topology& topology);  // needs a current GL 4.5 context

  // Computes the surface from `positions` (a buffer of vec4 per point).
  void update(GLuint positions);
  // Binds what the cloth's vertices are pulled from besides the positions (normals, tangents, UVs, the quad
  // centres) and the element buffer; then draw indexCount() indices. `u_point_count` is points().
  void bindForDraw() const;
  GLsizei indexCount() const { return GLsizei(layout_.triangles.size()); }
  std::uint32_t points() const { return layout_.points; }
  const SurfaceLayout& layout() const { return layout_; }

  // The surface as computed last, read back (for tests).
  std::vector<glm::vec4> downloadNormals() const { return normals_.download<glm::vec4>(layout_.vertices()); }
  std::vector<glm::vec4> downloadTangents() const { return tangents_.download<glm::vec4>(layout_.vertices()); }
  std::vector<glm::vec4> downloadCentres() const { return centres_.download<glm::vec4>(layout_.quads); }

  // Compiles the two programs again; one that fails keeps its old version. Returns the compiler messages.
  std::string reload();

 private:
  SurfaceLayout layout_;
  gl::Buffer faces_, face_offsets_, point_faces_, quad_rest_, uvs_, normals_, tangents_, centres_, triangles_;
  gl::VertexArray vao_;
  gl::Program points_pass_, centres_pass_;
};

}  // namespace drape
