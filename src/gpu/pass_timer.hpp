// The time of every pass: a GPU timestamp after each dispatch, collected once the GPU has written it; where
// timer queries do not work (llvmpipe), the wall clock around glFinish on both sides of the dispatch, which
// stalls. Without timing on, the dispatches are only counted.
#pragma once

#include "core/solver.hpp"
#include "gl/objects.hpp"
#include "gpu/plan.hpp"

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace drape::gpu {

class PassTimer {
 public:
  void configure(bool timing, bool timer_queries);
  bool timing() const { return timing_; }
  // The host may pause before the next dispatch (a substep, a pick, a frame drawn): the next timed
  // dispatch starts a new run of timestamps, so that the pause is not counted as its time.
  void pause() { break_ = true; }

  // Runs one dispatch as `pass`, counted (and timed when timing is on).
  template <class F>
  void timed(Pass pass, F&& run) {
    PassTiming& timing = times_[std::size_t(pass)];
    ++timing.calls;
    if (!timing_) {
      run();
    } else if (timer_queries_) {
      if (pending_.empty() || break_) pending_.push_back({Pass::Count, takeQuery()});
      break_ = false;
      run();
      pending_.push_back({pass, takeQuery()});
      if (pending_.size() >= 4096) resolve(true);  // bounded memory; results are ready long before
    } else {
      gl::finish();
      const auto start = std::chrono::steady_clock::now();
      run();
      gl::finish();
      timing.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
  }

  // The passes dispatched since the last reset(), in Pass order, named by `name`.
  std::vector<PassTiming> timings(const std::function<std::string(Pass)>& name) const;
  void reset();

 private:
  struct Pending {
    Pass pass;  // the pass that ended at this timestamp; Pass::Count: a start
    gl::Query query;
  };
  gl::Query takeQuery();  // a timestamp query, recorded now
  // Adds up the pass times of the timestamps the GPU has written; with `wait`, of all of them.
  void resolve(bool wait) const;

  bool timing_ = false, timer_queries_ = false;
  bool break_ = true;
  mutable std::vector<PassTiming> times_ = std::vector<PassTiming>(kPassCount);
  mutable std::vector<Pending> pending_;
  mutable std::vector<gl::Query> spare_;
};

}  // namespace drape::gpu
