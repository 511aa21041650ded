// The health flags without a stall (docs/design.md section 4, "No stalls"): after each frame's health check
// the GPU copies the flags and the list build's state into one slot of a small persistently mapped ring and
// places a fence; the host reads the newest slot whose fence has signalled.
#pragma once

#include "gl/objects.hpp"
#include "gpu/layout.hpp"

#include <optional>

namespace drape::gpu {

// What the frame-end copy writes into each slot.
struct HealthSnapshot {
  Health health;
  PairState pairs;
};

class HealthRing {
 public:
  void allocate();
  // After the frame's health pass: copies `health` (and the lists' state from `pair_control`, when it exists)
  // into the next slot, then a fence. `substeps`: the state checked.
  void snapshot(const gl::Buffer& health, const gl::Buffer& pair_control, long long substeps);
  // The newest slot whose fence has signalled, waiting only for the frame before the newest if even that one is
  // still running; nothing when no frame ended since forget().
  struct Recent {
    HealthSnapshot snapshot;
    long long substeps = -1;
  };
  std::optional<Recent> recent();
  void forget();  // the flags were cleared: no slot answers for the state any more
  std::size_t bytes() const { return ring_.size(); }

 private:
  static constexpr int kSlots = 2;  // the newest frame and the one before it
  struct Slot {
    gl::Fence fence;  // empty: the slot holds nothing yet
    long long substeps = -1;
  };
  gl::Buffer ring_;  // kSlots snapshots, mapped for reading
  Slot slots_[kSlots];
  int newest_ = -1;
};

}  // namespace drape::gpu
