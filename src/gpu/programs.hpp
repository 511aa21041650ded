// The kernels a plan dispatches, compiled with the defines the kernel table gives each for the plan, and kept
// until those change: a new plan (after a live parameter change) recompiles only the kernels whose defines
// differ.
#pragma once

#include "gl/objects.hpp"
#include "gpu/kernels.hpp"
#include "gpu/plan.hpp"

#include <array>

namespace drape::gpu {

class Programs {
 public:
  // Every kernel the plan dispatches and the health check, so that one that does not compile fails here; then
  // the uniforms that stay until the next plan.
  void prepare(const Plan& plan);
  // The pass's program for this plan, compiled on first use (picking is compiled when first asked).
  const gl::Program& get(const Plan& plan, Pass pass, int variant = 0);
  // A program prepare() compiled for the current plan, without working out its defines again.
  const gl::Program& prepared(Pass pass) const;

 private:
  struct Compiled {
    gl::Program program;
    gl::Defines defines;
  };
  void setFixed(const Plan& plan, Pass pass);

  std::array<std::array<Compiled, 2>, kPassCount> compiled_;
};

}  // namespace drape::gpu
