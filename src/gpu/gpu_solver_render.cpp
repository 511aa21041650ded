// GpuSolver: what the renderer and the viewer's mouse need (normals, picking, dragging).
#include "gpu/gpu_solver.hpp"

#include "gl/shader.hpp"
#include "gpu/layout.hpp"

namespace drape {

void GpuSolver::computeNormals() {
  timing_break_ = true;
  if (programs_.normals.id() == 0) programs_.normals = gl::compileCompute("sim/normals.comp");
  bindShared();
  state_[current_].position.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPosIn);
  normals_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingNormals);
  tangents_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingTangents);
  vertex_tri_offsets_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingVertexTriOffsets);
  vertex_tris_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingVertexTris);
  triangles_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingTriangles);
  uvs_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingUvs);
  dispatch(kNormals, programs_.normals, groupsFor(std::uint64_t(topo_.pointCount()), gpu::kLocalSize));
  // dispatch() made the writes visible to shader storage reads (vertex pulling); a renderer that binds
  // the buffers as vertex attributes needs this bit as well.
  glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
}

void GpuSolver::writePoint(std::uint32_t index, const glm::vec4* position, const glm::vec3* displacement) {
  if (index >= std::uint32_t(topo_.pointCount()))
    throw std::out_of_range("GpuSolver: point " + std::to_string(index) + " outside a cloth of " +
                            std::to_string(topo_.pointCount()) + " points");
  // Host writes into a buffer that shaders wrote: the update barrier orders them after those writes.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  if (position) state_[current_].position.upload(index * sizeof(glm::vec4), sizeof(glm::vec4), position);
  if (displacement) state_[current_].displacement.upload(index * sizeof(glm::vec3), sizeof(glm::vec3), displacement);
  health_checked_ = false;
}

void GpuSolver::setPosition(std::uint32_t index, glm::vec3 position) {
  const bool pinned = (index < topo_.pinned.size() && topo_.pinned[index] != 0) || int(index) == held_;
  const glm::vec4 p(position, pinned ? 1.0f : 0.0f);  // w: the pin flag
  writePoint(index, &p, nullptr);
}

void GpuSolver::holdPoint(int index, glm::vec3 target) {
  if (held_ >= 0 && held_ != index) releasePoint();
  const glm::vec4 p(target, 1.0f);  // w: pinned, so integrate keeps it where it is and stretch pulls others
  const glm::vec3 v(0.0f);
  writePoint(std::uint32_t(index), &p, &v);
  held_ = index;
}

void GpuSolver::releasePoint() {
  if (held_ < 0) return;
  // A held point was pinned, so its displacement is zero: it starts again at rest, with its own pin flag
  // in the position's w (xyz stays).
  const float pin = topo_.pinned[std::size_t(held_)] ? 1.0f : 0.0f;
  const glm::vec3 v(0.0f);
  writePoint(std::uint32_t(held_), nullptr, &v);
  state_[current_].position.upload(std::size_t(held_) * sizeof(glm::vec4) + 3 * sizeof(float), sizeof(float), &pin);
  held_ = -1;
}

int GpuSolver::pickPoint(glm::vec3 origin, glm::vec3 direction, float radius) {
  timing_break_ = true;
  const float length = glm::length(direction);
  if (!(length > 0.0f) || !(radius > 0.0f)) return -1;
  if (programs_.pick[0].id() == 0) {
    for (int stage = 0; stage < 2; ++stage)
      programs_.pick[stage] = gl::compileCompute("sim/pick.comp", {{"PICK_STAGE", std::to_string(stage)}});
  }
  bindShared();
  state_[current_].position.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPosIn);
  pick_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPick);
  const gpu::PickResult none{0xffffffffu, 0xffffffffu, 0u, 0u};
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  pick_.upload(0, sizeof none, &none);
  const glm::uvec3 groups = groupsFor(std::uint64_t(topo_.pointCount()), gpu::kLocalSize);
  for (const gl::Program& program : programs_.pick) {
    program.setUniform("u_origin", origin);
    program.setUniform("u_direction", direction / length);
    program.setUniform("u_radius", radius);
    dispatch(kPick, program, groups);
  }
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const gpu::PickResult result = pick_.download<gpu::PickResult>(1)[0];
  return result.index == 0xffffffffu ? -1 : int(result.index);
}

}  // namespace drape
