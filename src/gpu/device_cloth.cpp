#include "gpu/device_cloth.hpp"

#include "core/tethers.hpp"
#include "gpu/colliders.hpp"
#include "gpu/face_tables.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace drape::gpu {

namespace {
constexpr GLbitfield kUpdatable = GL_DYNAMIC_STORAGE_BIT;
}  // namespace

DeviceCloth::DeviceCloth(const Scene& scene, const Topology& topo) : topo_(&topo) {
  const std::size_t n = std::size_t(topo.pointCount());
  for (StateBuffers& s : state_) {
    s.position = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, kUpdatable);
    s.displacement = gl::Buffer::create(n * sizeof(glm::vec3), nullptr, kUpdatable);
  }
  params_ = gl::Buffer::create(sizeof(SimParams), nullptr, kUpdatable);
  point_mass_ = gl::Buffer::create(n * sizeof(PointMass), nullptr, kUpdatable);
  colliders_ = gl::Buffer::fromVector(colliders(scene), 0);
  health_ = gl::Buffer::create(sizeof(Health), nullptr, kUpdatable);
  pick_ = gl::Buffer::create(sizeof(PickResult), nullptr, kUpdatable);
  // Built once, as CpuSolver builds its own: the thickness they keep is the scene's at construction.
  const FaceTables faces = faceTables(scene, topo);
  counts_.face_meshes = faces.meshes;
  if (faces.meshes > 0) {
    face_table_ = gl::Buffer::fromVector(faces.table, 0);
    face_features_ = gl::Buffer::fromVector(faces.features, 0);
  }
}

void DeviceCloth::uploadColliders(const Scene& scene) {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  colliders_ = gl::Buffer::fromVector(colliders(scene), 0);
}

void DeviceCloth::uploadParams(const Scene& scene, const ParamsInput& in) {
  const std::vector<PointMass> masses = pointMasses(scene, *topo_);
  ParamsInput with = in;
  with.shortest_spring = shortestStructural(*topo_);
  const SimParams p = simParams(scene, masses, with);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // kernels still reading the old values come first
  point_mass_.upload(masses);
  params_.upload(0, sizeof p, &p);
}

void DeviceCloth::uploadSprings(const SpringColouring& colouring, const SceneNeeds& needs) {
  const Adjacency a = adjacency(*topo_, needs);
  offsets_ = gl::Buffer::fromVector(a.offsets, 0);
  neighbors_ = gl::Buffer::fromVector(a.neighbors, 0);
  counts_.adjacency_entries = a.neighbors.size();
  ColouredSprings coloured = colouredSprings(*topo_, colouring, needs);
  coloured_springs_ = gl::Buffer::fromVector(coloured.springs, 0);
  counts_.colour_start = std::move(coloured.start);
}

// XPBD's multipliers and VBD's prediction need memory only when a substep sweeps more than once (the first
// sweep of a substep starts them afresh and does not read them).
void DeviceCloth::prepareFor(const SceneNeeds& needs, double thickness) {
  const std::size_t n = std::size_t(topo_->pointCount());
  if (needs.contacts && thickness != held_thickness_) {
    held_thickness_ = thickness;
    counts_.held_pairs = mayHoldPairs(*topo_, 2.0 * thickness);
    if (counts_.held_pairs && rest_.id() == 0) rest_ = gl::Buffer::fromVector(restPositions(*topo_), 0);
  }
  if (needs.integrator == Integrator::Xpbd && needs.sweep_state) {
    const std::size_t bytes = std::max<std::size_t>(counts_.colour_start.back(), 1) * sizeof(float);
    if (xpbd_lambda_.id() == 0 || xpbd_lambda_.size() < bytes) xpbd_lambda_ = gl::Buffer::create(bytes, nullptr, 0);
  }
  if (needs.integrator == Integrator::Vbd) {
    if (coloured_points_.id() == 0) {
      const PointColouring colouring = colourPoints(*topo_);
      counts_.point_colour_start = colouring.start;
      coloured_points_ = gl::Buffer::fromVector(colouring.points, 0);
    }
    if (needs.sweep_state && vbd_inertia_.id() == 0)
      vbd_inertia_ = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, 0);
  }
  if (needs.tethers && tethers_.id() == 0) {
    const Tethers t = buildTethers(*topo_);
    counts_.tether_slots = t.slots;
    if (t.slots > 0) tethers_ = gl::Buffer::fromVector(tetherEntries(t), 0);
  }
}

void DeviceCloth::setColourPartners(bool needed, const SpringColouring& colouring, const SceneNeeds& needs) {
  colour_partners_ = needed ? gl::Buffer::fromVector(colourPartners(*topo_, colouring, needs), 0) : gl::Buffer();
}

void DeviceCloth::bindShared() const {
  params_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingParams);
  point_mass_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPointMass);
  offsets_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingOffsets);
  neighbors_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingNeighbors);
  colliders_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingColliders);
  health_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingHealth);
}

void DeviceCloth::bindState() const {
  const StateBuffers& in = state_[current_];
  const StateBuffers& out = state_[1 - current_];
  in.position.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPosIn);
  in.displacement.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingDispIn);
  out.position.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPosOut);
  out.displacement.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingDispOut);
}

void DeviceCloth::bind(std::uint16_t bindings) const {
  struct Entry {
    Binding bit;
    const gl::Buffer& buffer;
    std::uint32_t point;
  };
  const Entry entries[] = {
      {kBindColouredSprings, coloured_springs_, kBindingColouredSprings},
      {kBindColouredPoints, coloured_points_, kBindingColouredPoints},
      {kBindColourPartners, colour_partners_, kBindingColourPartners},
      {kBindTethers, tethers_, kBindingTethers},
      {kBindXpbdLambda, xpbd_lambda_, kBindingXpbdLambda},
      {kBindVbdInertia, vbd_inertia_, kBindingVbdInertia},
      {kBindPick, pick_, kBindingPick},
      {kBindRest, rest_, kBindingRest},
      {kBindFaces, face_table_, kBindingFaceTable},
      {kBindFaces, face_features_, kBindingFaceFeatures},
  };
  for (const Entry& e : entries)
    if ((bindings & e.bit) != 0 && e.buffer.id() != 0) e.buffer.bindBase(GL_SHADER_STORAGE_BUFFER, e.point);
}

void DeviceCloth::reset() {
  const std::size_t n = std::size_t(topo_->pointCount());
  std::vector<glm::vec4> x(n);
  const std::vector<glm::vec3> v(n, glm::vec3(0.0f));
  for (std::size_t i = 0; i < n; ++i)
    x[i] = glm::vec4(glm::vec3(topo_->initial_positions[i]), topo_->pinned[i] ? 1.0f : 0.0f);
  // Uploads must not overtake shader writes still in flight to the same buffers.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  current_ = 0;
  state_[0].position.upload(x);
  state_[0].displacement.upload(v);
  held_ = -1;
}

void DeviceCloth::uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v) {
  const std::size_t n = std::size_t(topo_->pointCount());
  if (x.size() != n || v.size() != n)
    throw std::invalid_argument("GpuSolver::uploadState: expected " + std::to_string(n) + " points");
  std::vector<glm::vec4> px(n);
  std::vector<glm::vec3> pv(n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool pinned = topo_->pinned[i] != 0 || int(i) == held_;
    px[i] = glm::vec4(glm::vec3(x[i]), pinned ? 1.0f : 0.0f);
    pv[i] = glm::vec3(v[i]);
  }
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  state_[current_].position.upload(px);
  state_[current_].displacement.upload(pv);
}

std::vector<glm::dvec3> DeviceCloth::readPositions() const {
  // glGetBufferSubData after shader writes needs this barrier to see them.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const auto x = state_[current_].position.download<glm::vec4>(std::size_t(topo_->pointCount()));
  std::vector<glm::dvec3> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    out[i] = glm::dvec3(glm::vec3(x[i]));
  return out;
}

std::vector<glm::dvec3> DeviceCloth::readDisplacements() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const auto v = state_[current_].displacement.download<glm::vec3>(std::size_t(topo_->pointCount()));
  std::vector<glm::dvec3> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out[i] = glm::dvec3(v[i]);
  return out;
}

void DeviceCloth::writePoint(std::uint32_t index, const glm::vec4* position, const glm::vec3* displacement) {
  if (index >= std::uint32_t(topo_->pointCount()))
    throw std::out_of_range("GpuSolver: point " + std::to_string(index) + " outside a cloth of " +
                            std::to_string(topo_->pointCount()) + " points");
  // Host writes into a buffer that shaders wrote: the update barrier orders them after those writes.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  if (position) state_[current_].position.upload(index * sizeof(glm::vec4), sizeof(glm::vec4), position);
  if (displacement) state_[current_].displacement.upload(index * sizeof(glm::vec3), sizeof(glm::vec3), displacement);
}

void DeviceCloth::setPosition(std::uint32_t index, glm::vec3 position) {
  const bool pinned = (index < topo_->pinned.size() && topo_->pinned[index] != 0) || int(index) == held_;
  const glm::vec4 p(position, pinned ? 1.0f : 0.0f);  // w: the pin flag
  writePoint(index, &p, nullptr);
}

void DeviceCloth::holdPoint(int index, glm::vec3 target) {
  if (held_ >= 0 && held_ != index) releasePoint();
  const glm::vec4 p(target, 1.0f);  // w: pinned, so integrate keeps it where it is and stretch pulls others
  const glm::vec3 v(0.0f);
  writePoint(std::uint32_t(index), &p, &v);
  held_ = index;
}

void DeviceCloth::releasePoint() {
  if (held_ < 0) return;
  // A held point was pinned, so its displacement is zero: it starts again at rest, with its own pin flag in
  // the position's w (xyz stays).
  const float pin = topo_->pinned[std::size_t(held_)] ? 1.0f : 0.0f;
  const glm::vec3 v(0.0f);
  writePoint(std::uint32_t(held_), nullptr, &v);
  state_[current_].position.upload(std::size_t(held_) * sizeof(glm::vec4) + 3 * sizeof(float), sizeof(float), &pin);
  held_ = -1;
}

void DeviceCloth::clearHealth() {
  const Health clean{0u, 0xffffffffu, 0u, 0u};
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  health_.upload(0, sizeof clean, &clean);
}

Health DeviceCloth::readHealth() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  return health_.download<Health>(1)[0];
}

void DeviceCloth::clearPick() {
  const PickResult none{0xffffffffu, 0xffffffffu, 0u, 0u};
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  pick_.upload(0, sizeof none, &none);
}

PickResult DeviceCloth::readPick() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  return pick_.download<PickResult>(1)[0];
}

std::size_t DeviceCloth::bytes() const {
  std::size_t total = 0;
  for (const StateBuffers& s : state_)
    total += s.position.size() + s.displacement.size();
  for (const gl::Buffer* b : {&params_, &point_mass_, &offsets_, &neighbors_, &colliders_, &health_, &pick_,
                              &coloured_springs_, &xpbd_lambda_, &coloured_points_, &vbd_inertia_, &colour_partners_,
                              &tethers_, &rest_, &face_table_, &face_features_})
    total += b->size();
  return total;
}

}  // namespace drape::gpu
