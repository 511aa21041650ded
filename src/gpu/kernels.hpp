// The kernel table: one row per pass (plan.hpp), all a pass is beyond its place in the plan: its name, its
// kernel file, the #defines it is compiled with, the buffers and uniforms a dispatch of it sets, and its bytes
// a point in the traffic model. The table is checked at compile time to hold a row for every Pass, in order
// (kernels.cpp); tests/gpu_plan_test.cpp checks every row's file and defines. GL-free.
#pragma once

#include "gl/shader_source.hpp"
#include "gpu/plan.hpp"
#include "gpu/traffic.hpp"

#include <cstdint>
#include <string>

namespace drape::gpu {

// Buffers a dispatch binds beyond the state and the buffers every pass shares (DeviceCloth::bindShared).
enum Binding : std::uint16_t {
  kBindColouredSprings = 1u << 0,  // ColouredSpring, by colour
  kBindColouredPoints = 1u << 1,   // VBD's points by colour
  kBindColourPartners = 1u << 2,   // ColourPartner table (the one-dispatch and tiled stretch limit, where rests differ)
  kBindTethers = 1u << 3,
  kBindXpbdLambda = 1u << 4,  // XPBD's multipliers, with more than one sweep
  kBindVbdInertia = 1u << 5,  // VBD's prediction, with more than one sweep
  kBindPick = 1u << 6,
  kBindRest = 1u << 7,   // the rest positions, where self-collision skips the pairs held at rest
  kBindFaces = 1u << 8,  // the face contacts' table and features
};

// Uniforms set on every dispatch (those fixed until the next plan are set once: Programs::prepare).
enum Uniform : std::uint8_t {
  kUniformTime = 1u << 0,          // u_time: the wind's time at the start of the substep (with wind)
  kUniformRange = 1u << 1,         // u_first, u_count: the colour's range
  kUniformSweep = 1u << 2,         // u_sweep, with more than one sweep
  kUniformStretchFirst = 1u << 3,  // u_stretch: whether the fused kernel's copy is stretched first
  kUniformGroup = 1u << 4,         // u_substeps, u_phases, u_check_health; the wind's u_first_substep, u_dt
};

// Uniforms fixed until the next plan.
enum class Fixed : std::uint8_t {
  None,
  Stretch,     // u_grid (u_rest on a flat grid), u_colours, u_passes: the tiled stretch limit
  GridForces,  // u_grid, u_rest: the tiled forces
  Group,       // u_stretch_passes, u_colours (0: Jacobi), and u_grid, u_rest on a flat grid
};

// How passes() names a dispatch of the pass: the name, and what the plan fused into it.
enum class Label : std::uint8_t {
  Plain,
  Integrate,       // "forces+predict" for XPBD and VBD; else + "+pairs_check" or "+collide"
  TiledIntegrate,  // + "+pairs_check" or "+collide"
  Contacts,        // + "+collide"
  FusedIntegrate,  // + "+collide"
  Faces,           // + "+collide"
};

struct KernelRow {
  Pass pass;
  const char* name;
  const char* file;  // under glsl/
  Label label;
  void (*defines)(const Plan&, int variant, gl::Defines&);
  std::uint16_t bindings;
  std::uint8_t uniforms;
  Fixed fixed;
  double (*bytes)(const Plan&, const Dispatch&, const TrafficCounts&);  // a point's, in the traffic model
  int variants = 1;                                                     // programs of the pass (pick: two stages)
};

const KernelRow& kernelRow(Pass pass);
std::string passLabel(const Plan& plan, Pass pass);
// The forces+integrate name with what the plan fused into it (`travel`: the lists' travel check too).
std::string integrateLabel(const Fusion& fusion, bool travel);
// What the pass's kernel is compiled with for this plan; variant < kernelRow(pass).variants.
gl::Defines kernelDefines(const Plan& plan, Pass pass, int variant = 0);
// The scene's defines every simulation kernel shares: NUM_SPHERES, NUM_PLANES, SELF_COLLISION, WIND,
// UNIFORM_MASS, and NUM_MESHES, PREDICT, XPBD_LAMBDA, VBD_INERTIA where they apply.
gl::Defines sceneDefines(const SceneNeeds& needs);

}  // namespace drape::gpu
