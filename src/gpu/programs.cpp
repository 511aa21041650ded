#include "gpu/programs.hpp"

#include "gl/shader.hpp"

#include <stdexcept>
#include <string>

namespace drape::gpu {

const gl::Program& Programs::get(const Plan& plan, Pass pass, int variant) {
  Compiled& c = compiled_[std::size_t(pass)][std::size_t(variant)];
  gl::Defines defines = kernelDefines(plan, pass, variant);
  if (c.program.id() == 0 || defines != c.defines) {
    c.program = gl::compileCompute(kernelRow(pass).file, defines);
    c.defines = std::move(defines);
  }
  return c.program;
}

const gl::Program& Programs::prepared(Pass pass) const {
  const gl::Program& program = compiled_[std::size_t(pass)][0].program;
  if (program.id() == 0)
    throw std::logic_error(std::string("gpu solver: ") + kernelRow(pass).name + " is dispatched but was not prepared");
  return program;
}

void Programs::prepare(const Plan& plan) {
  bool planned[kPassCount] = {};
  planned[std::size_t(Pass::Health)] = true;
  for (const std::vector<Dispatch>* list : {&plan.substep, &plan.frame.substep, &plan.frame.tail, &plan.travel_check})
    for (const Dispatch& d : *list)
      planned[std::size_t(d.pass)] = true;
  for (std::size_t p = 0; p < kPassCount; ++p) {
    if (!planned[p]) continue;
    for (int variant = 0; variant < kernelRow(Pass(p)).variants; ++variant)
      get(plan, Pass(p), variant);
    setFixed(plan, Pass(p));
  }
}

// What stays fixed until the next plan is set once, not on every dispatch.
void Programs::setFixed(const Plan& plan, Pass pass) {
  const gl::Program& program = compiled_[std::size_t(pass)][0].program;
  const std::vector<float>& rests = plan.path.grid_rests;
  const auto setGrid = [&] {
    program.setUniform("u_grid", glm::uvec2(std::uint32_t(plan.width), std::uint32_t(plan.height)));
    if (!rests.empty()) program.setUniform("u_rest", rests);
  };
  const std::uint32_t colours = std::uint32_t(plan.colours);
  const std::uint32_t passes = std::uint32_t(plan.needs.stretch_passes);
  switch (kernelRow(pass).fixed) {
    case Fixed::None:
      return;
    case Fixed::GridForces:
      setGrid();
      return;
    case Fixed::Stretch:
      setGrid();
      program.setUniform("u_colours", colours);
      program.setUniform("u_passes", passes);
      return;
    case Fixed::Group:
      if (!rests.empty()) setGrid();
      program.setUniform("u_stretch_passes", passes);
      program.setUniform("u_colours", plan.needs.gauss_seidel ? colours : 0u);
      return;
  }
}

}  // namespace drape::gpu
