#include "gpu/health_ring.hpp"

#include <cstddef>
#include <cstring>

namespace drape::gpu {

static_assert(sizeof(HealthSnapshot) == sizeof(Health) + sizeof(PairState), "the ring's layout");

void HealthRing::allocate() {
  ring_ = gl::Buffer::createReadMapped(kSlots * sizeof(HealthSnapshot));
}

void HealthRing::snapshot(const gl::Buffer& health, const gl::Buffer& pair_control, long long substeps) {
  newest_ = (newest_ + 1) % kSlots;
  Slot& slot = slots_[newest_];
  // The slot's previous fence signalled long ago (it is two frames old); waiting on it keeps the mapped bytes
  // from being overwritten while a reader could still look at them.
  slot.fence.wait();
  const std::size_t at = std::size_t(newest_) * sizeof(HealthSnapshot);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // the copies read what the kernels wrote
  health.copyTo(ring_, 0, at + offsetof(HealthSnapshot, health), sizeof(Health));
  if (pair_control.id() != 0)
    pair_control.copyTo(ring_, offsetof(PairControl, state), at + offsetof(HealthSnapshot, pairs), sizeof(PairState));
  slot.fence = gl::Fence::insert();
  slot.substeps = substeps;
}

void HealthRing::forget() {
  for (Slot& slot : slots_) {
    slot.fence.wait();  // a copy still in flight would land in a slot read as fresh
    slot = Slot{};
  }
  newest_ = -1;
}

std::optional<HealthRing::Recent> HealthRing::recent() {
  if (newest_ < 0) return std::nullopt;
  int slot = newest_;
  const int older = (slot + kSlots - 1) % kSlots;
  if (!slots_[slot].fence.signalled() && !slots_[older].fence.empty()) slot = older;
  slots_[slot].fence.wait();
  Recent out;
  std::memcpy(&out.snapshot, static_cast<const std::byte*>(ring_.mapped()) + slot * sizeof(HealthSnapshot),
              sizeof out.snapshot);
  out.substeps = slots_[slot].substeps;
  return out;
}

}  // namespace drape::gpu
