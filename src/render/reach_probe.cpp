#include "render/reach_probe.hpp"

#include "gl/debug.hpp"
#include "gl/shader.hpp"
#include "gpu/gpu_solver.hpp"
#include "render/render_bindings.h"

#include <algorithm>
#include <cstring>

namespace drape {

static_assert(RENDER_REACH_VALUES == ViewReach::kValues, "the pass measures every value of a reach");

namespace {

constexpr std::size_t kResultBytes = sizeof(std::uint32_t) * RENDER_REACH_VALUES;

// The inverse of cloth_reach.comp's orderedBits.
float fromOrderedBits(std::uint32_t u) {
  const std::uint32_t bits = (u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u;
  float f = 0.0f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

}  // namespace

ReachProbe::ReachProbe(Solver& solver) : solver_(&solver), gpu_(dynamic_cast<GpuSolver*>(&solver)) {
  if (!gpu_) return;
  program_ = gl::compileCompute("render/cloth_reach.comp");
  result_ = gl::Buffer::create(kResultBytes, nullptr, 0);
  ring_ = gl::Buffer::createReadMapped(kSlots * kResultBytes);
}

void ReachProbe::measure(const ReachFrame& frame) {
  newest_ = (newest_ + 1) % kSlots;
  Slot& slot = slots_[newest_];
  slot.measured = true;
  slot.t_x = frame.t_x;
  if (!gpu_) {
    slot.cpu = reachOf(solver_->readPositions(), frame);
    return;
  }
  // The slot's last copy is two frames old: long done, and no reader looks at it any more.
  slot.fence.wait();
  result_.clear();
  program_.use();
  program_.setUniform("u_point_count", unsigned(solver_->topology().pointCount()));
  program_.setUniform("u_origin", frame.origin);
  program_.setUniform("u_right", frame.axes.right);
  program_.setUniform("u_up", frame.axes.up);
  program_.setUniform("u_back", frame.axes.back);
  program_.setUniform("u_slopes", glm::vec2(frame.t_x, frame.t_y));
  gpu_->positionBuffer().bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_POSITIONS);
  gpu_->healthBuffer().bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_HEALTH);
  result_.bindBase(GL_SHADER_STORAGE_BUFFER, RENDER_BINDING_REACH);
  const unsigned points = unsigned(solver_->topology().pointCount());
  glDispatchCompute(std::clamp((points + RENDER_REACH_LOCAL_SIZE - 1) / RENDER_REACH_LOCAL_SIZE, 1u,
                               unsigned(RENDER_REACH_MAX_GROUPS)),
                    1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // the copy reads what the pass wrote
  result_.copyTo(ring_, 0, std::size_t(newest_) * kResultBytes, kResultBytes);
  slot.fence = gl::Fence::insert();
  gl::checkDebugErrors();
}

ViewReach ReachProbe::previous() {
  return newest_ < 0 ? ViewReach{} : read((newest_ + kSlots - 1) % kSlots);
}

ViewReach ReachProbe::latest() {
  return newest_ < 0 ? ViewReach{} : read(newest_);
}

void ReachProbe::forget() {
  for (Slot& slot : slots_) {
    slot.fence.wait();  // a copy still in flight would land in a slot read as fresh
    slot = Slot{};
  }
  newest_ = -1;
}

ViewReach ReachProbe::read(int index) {
  Slot& slot = slots_[index];
  if (!slot.measured) return ViewReach{};
  if (!gpu_) return slot.cpu;
  slot.fence.wait();
  std::uint32_t bits[RENDER_REACH_VALUES];
  std::memcpy(bits, static_cast<const std::byte*>(ring_.mapped()) + std::size_t(index) * kResultBytes, kResultBytes);
  std::array<float, ViewReach::kValues> values;
  for (int k = 0; k < ViewReach::kValues; ++k)
    values[k] = bits[k] == 0u ? -1e30f : fromOrderedBits(bits[k]);
  ViewReach reach = ViewReach::fromValues(values, slot.t_x);
  return reach.empty() ? ViewReach{} : reach;
}

}  // namespace drape
