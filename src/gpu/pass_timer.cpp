#include "gpu/pass_timer.hpp"

namespace drape::gpu {

void PassTimer::configure(bool timing, bool timer_queries) {
  timing_ = timing;
  timer_queries_ = timer_queries;
}

gl::Query PassTimer::takeQuery() {
  gl::Query query;
  if (spare_.empty()) {
    query = gl::Query::create(GL_TIMESTAMP);
  } else {
    query = std::move(spare_.back());
    spare_.pop_back();
  }
  query.timestamp();
  return query;
}

// Timestamps arrive in order, so the available ones are a prefix of pending_. The last one stays as the start
// of the passes after it.
void PassTimer::resolve(bool wait) const {
  std::size_t done = 0;
  while (done + 1 < pending_.size() && (wait || pending_[done + 1].query.resultAvailable())) {
    const Pending& before = pending_[done];
    const Pending& after = pending_[done + 1];
    if (after.pass != Pass::Count)
      times_[std::size_t(after.pass)].ms += double(after.query.result() - before.query.result()) * 1e-6;
    ++done;
  }
  for (std::size_t i = 0; i < done; ++i)
    spare_.push_back(std::move(pending_[i].query));
  pending_.erase(pending_.begin(), pending_.begin() + std::ptrdiff_t(done));
}

std::vector<PassTiming> PassTimer::timings(const std::function<std::string(Pass)>& name) const {
  resolve(false);
  std::vector<PassTiming> out;
  for (std::size_t p = 0; p < kPassCount; ++p) {
    if (times_[p].calls == 0) continue;
    out.push_back(times_[p]);
    out.back().name = name(Pass(p));
  }
  return out;
}

void PassTimer::reset() {
  resolve(false);
  times_.assign(kPassCount, PassTiming{});
}

}  // namespace drape::gpu
