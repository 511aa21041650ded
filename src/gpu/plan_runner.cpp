#include "gpu/plan_runner.hpp"

#include "gpu/kernels.hpp"

namespace drape::gpu {

template <class F>
void PlanRunner::timed(Pass pass, F&& run) {
  timer_.timed(pass, run);
  // Every later pass reads through SSBOs what this one wrote. Shader storage writes are incoherent: without
  // this barrier the next dispatch may still read the old values.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void PlanRunner::bindShared() const {
  cloth_.bindShared();
  lists_.bind();
}

void PlanRunner::run(const Plan& plan, const std::vector<Dispatch>& dispatches, long long& substeps, int repeat) {
  for (const Dispatch& d : dispatches) {
    dispatch(plan, d, substeps, repeat);
    substeps += d.advances;
  }
}

void PlanRunner::setUniforms(const Plan& plan, const Dispatch& d, const gl::Program& program, long long substeps,
                             int repeat) const {
  const std::uint8_t uniforms = kernelRow(d.pass).uniforms;
  if ((uniforms & kUniformTime) != 0 && plan.needs.wind)
    program.setUniform("u_time", float(double(substeps) * plan.dt));
  if ((uniforms & kUniformRange) != 0) {
    program.setUniform("u_first", d.first);
    program.setUniform("u_count", d.count);
  }
  if ((uniforms & kUniformSweep) != 0 && plan.needs.sweep_state) program.setUniform("u_sweep", d.sweep);
  if ((uniforms & kUniformStretchFirst) != 0) program.setUniform("u_stretch", repeat > 0 || d.stretch_first);
  if ((uniforms & kUniformGroup) != 0) {
    program.setUniform("u_substeps", d.substeps);
    program.setUniform("u_phases", d.phases);
    program.setUniform("u_check_health", d.check_health);
    if (plan.needs.wind) {
      program.setUniform("u_first_substep", double(substeps));
      program.setUniform("u_dt", plan.dt);
    }
  }
}

void PlanRunner::dispatch(const Plan& plan, const Dispatch& d, long long substeps, int repeat) {
  const gl::Program& program = programs_.prepared(d.pass);
  const KernelRow& row = kernelRow(d.pass);
  cloth_.bind(row.bindings);
  setUniforms(plan, d, program, substeps, repeat);
  cloth_.bindState();
  switch (d.extent) {
    case Extent::Points:
      timed(d.pass, [&] { program.dispatch(groupsFor(std::uint64_t(plan.points))); });
      break;
    case Extent::One:
      timed(d.pass, [&] { program.dispatch({1, 1, 1}); });
      break;
    case Extent::Range:
      timed(d.pass, [&] { program.dispatch(groupsFor(d.count)); });
      break;
    case Extent::Indirect:
      glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, lists_.control().id());
      timed(d.pass, [&] { program.dispatchIndirect(PairLists::commandOffset(d.command)); });
      break;
    case Extent::Tiles:
      timed(d.pass, [&] { program.dispatch({tileCount(plan.width, d.tile), tileCount(plan.height, d.tile), 1}); });
      break;
  }
  if (d.ping_pong) cloth_.swapState();
  if (d.writes_commands) glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
  // Integrate checks the travel for the lists when self-collision follows; self-collision consumes it.
  if (d.pass == Pass::ForcesIntegrate || d.pass == Pass::ForcesIntegrateTiled) travel_checked_ = d.checks_travel;
  if (d.pass == Pass::SelfCollide) travel_checked_ = false;
  checked_health_ = d.pass == Pass::Health || d.check_health;
}

glm::uvec3 PlanRunner::groupsFor(std::uint64_t invocations) const {
  return gpu::groupsFor(invocations, max_groups_x_);
}

int PlanRunner::pickPoint(const Plan& plan, glm::vec3 origin, glm::vec3 direction, float radius) {
  timer_.pause();
  const float length = glm::length(direction);
  if (!(length > 0.0f) || !(radius > 0.0f)) return -1;
  const gl::Program* stages[] = {&programs_.get(plan, Pass::Pick, 0), &programs_.get(plan, Pass::Pick, 1)};
  cloth_.bindShared();
  cloth_.position().bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPosIn);
  cloth_.bind(kernelRow(Pass::Pick).bindings);
  cloth_.clearPick();
  for (const gl::Program* program : stages) {
    program->setUniform("u_origin", origin);
    program->setUniform("u_direction", direction / length);
    program->setUniform("u_radius", radius);
    timed(Pass::Pick, [&] { program->dispatch(groupsFor(std::uint64_t(plan.points))); });
  }
  const PickResult result = cloth_.readPick();
  return result.index == 0xffffffffu ? -1 : int(result.index);
}

}  // namespace drape::gpu
