// Runs a plan's dispatches: binds what each kernel row names, sets its per-dispatch uniforms, dispatches it
// with its extent, keeps the state's ping-pong, and puts the storage barrier after it that the next pass needs.
// Also the one dispatch outside the plan: picking, for the viewer's mouse.
#pragma once

#include "gpu/device_cloth.hpp"
#include "gpu/pair_lists.hpp"
#include "gpu/pass_timer.hpp"
#include "gpu/plan.hpp"
#include "gpu/programs.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace drape::gpu {

class PlanRunner {
 public:
  PlanRunner(DeviceCloth& cloth, PairLists& lists, Programs& programs, PassTimer& timer, std::uint32_t max_groups_x)
      : cloth_(cloth), lists_(lists), programs_(programs), timer_(timer), max_groups_x_(max_groups_x) {}

  // The buffers every pass shares, bound before a run of dispatches: the renderer may have bound its own to the
  // same points in between.
  void bindShared() const;
  // Runs the dispatches in order. `substeps`: the substeps taken, which
  // each dispatch that completes one advances (the wind's time). Frame repeats: `repeat` of the frame's substep.
  void run(const Plan& plan, const std::vector<Dispatch>& dispatches, long long& substeps, int repeat = 0);
  // Whether the current positions' travel for the self-collision lists was checked by forces+integrate.
  bool travelChecked() const { return travel_checked_; }
  void forgetTravel() { travel_checked_ = false; }
  // Whether the last dispatch was a health check of the current state.
  bool checkedHealth() const { return checked_health_; }

  int pickPoint(const Plan& plan, glm::vec3 origin, glm::vec3 direction, float radius);

 private:
  void dispatch(const Plan& plan, const Dispatch& d, long long substeps, int repeat);
  void setUniforms(const Plan& plan, const Dispatch& d, const gl::Program& program, long long substeps,
                   int repeat) const;
  glm::uvec3 groupsFor(std::uint64_t invocations) const;
  // Runs one dispatch (timed when timing is on), then the storage barrier the next pass needs.
  template <class F>
  void timed(Pass pass, F&& run);

  DeviceCloth& cloth_;
  PairLists& lists_;
  Programs& programs_;
  PassTimer& timer_;
  std::uint32_t max_groups_x_;
  bool travel_checked_ = false;
  bool checked_health_ = false;
};

}  // namespace drape::gpu
