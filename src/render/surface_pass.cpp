#include "render/surface_pass.hpp"

#include "gl/debug.hpp"
#include "gl/shader.hpp"
#include "render/render_bindings.h"

namespace drape {

namespace {

// A buffer of at least one element: GL refuses a storage of zero bytes (a mesh cloth may have no quads).
template <class T>
gl::Buffer storageOf(std::vector<T> values) {
  if (values.empty()) values.emplace_back();
  return gl::Buffer::fromVector(values, 0);
}

gl::Buffer writable(std::size_t count, std::size_t element_bytes) {
  return gl::Buffer::create(std::max<std::size_t>(count, 1) * element_bytes, nullptr, 0);
}

GLuint groups(std::uint32_t items) {
  return (items + RENDER_SURFACE_LOCAL_SIZE - 1) / RENDER_SURFACE_LOCAL_SIZE;
}

}  // namespace

SurfacePass::SurfacePass(const Topology& topology)
    : layout_(buildSurfaceLayout(topology)),
      faces_(storageOf(layout_.faces)),
      face_offsets_(storageOf(layout_.face_offsets)),
      point_faces_(storageOf(layout_.point_faces)),
      quad_rest_(storageOf(layout_.quad_rest)),
      uvs_(storageOf(layout_.uvs)),
      normals_(writable(layout_.vertices(), sizeof(glm::vec4))),
      tangents_(writable(layout_.vertices(), sizeof(glm::vec4))),
      centres_(writable(layout_.quads, sizeof(glm::vec4))),
      triangles_(storageOf(layout_.triangles)),
      vao_(gl::VertexArray::create()),
      points_pass_(gl::compileCompute("render/cloth_surface.comp")),
      centres_pass_(gl::compileCompute("render/cloth_surface.comp", {{"CENTRES", ""}})) {
  glVertexArrayElementBuffer(vao_.id(), triangles_.id());
}

void SurfacePass::update(GLuint positions) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_POSITIONS, positions);
  normals_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_NORMALS);
  tangents_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_TANGENTS);
  uvs_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_UVS);
  faces_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_FACES);
  face_offsets_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_FACE_OFFSETS);
  point_faces_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_POINT_FACES);
  quad_rest_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_QUAD_REST);
  centres_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_CENTRES);
  // The positions were written by the solver's kernels or uploaded: both are visible to this dispatch once
  // the solver's own barrier (or the upload) has run.
  points_pass_.use();
  points_pass_.setUniformOptional("u_point_count", layout_.points);
  points_pass_.setUniformOptional("u_quad_count", layout_.quads);
  glDispatchCompute(groups(layout_.points), 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // the centres read the points' normals
  if (layout_.quads > 0) {
    centres_pass_.use();
    centres_pass_.setUniformOptional("u_point_count", layout_.points);
    centres_pass_.setUniformOptional("u_quad_count", layout_.quads);
    glDispatchCompute(groups(layout_.quads), 1, 1);
  }
  // What follows pulls these as vertices from storage buffers.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  gl::checkDebugErrors();
}

void SurfacePass::bindForDraw() const {
  normals_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_NORMALS);
  tangents_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_TANGENTS);
  uvs_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_UVS);
  centres_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_CENTRES);
  vao_.bind();
}

std::string SurfacePass::reload() {
  try {
    gl::Program points = gl::compileCompute("render/cloth_surface.comp");
    gl::Program centres = gl::compileCompute("render/cloth_surface.comp", {{"CENTRES", ""}});
    points_pass_ = std::move(points);
    centres_pass_ = std::move(centres);
  } catch (const gl::ShaderError& e) {
    return std::string(e.what()) + "\n";
  }
  return {};
}

}  // namespace drape
