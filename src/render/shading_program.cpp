#include "render/shading_program.hpp"

#include "gl/debug.hpp"
#include "gl/shader.hpp"
#include "render/render_bindings.h"

#include <algorithm>
#include <utility>

namespace drape {

namespace {

using Uniforms = std::vector<std::string>;

Uniforms join(std::initializer_list<Uniforms> groups) {
  Uniforms all;
  for (const Uniforms& g : groups)
    all.insert(all.end(), g.begin(), g.end());
  return all;
}

const Uniforms kTransform = {"u_model", "u_view_projection", "u_normal_matrix", "u_point_count"};
const Uniforms kLight = {"u_light_position", "u_light_intensity"};
const Uniforms kBump = {"u_height_map", "u_height_scaling", "u_normal_scaling"};

std::array<ProgramSpec, kProgramCount> makeSpecs() {
  const std::string vert = "render/surface.vert";
  // clang-format off
  return {{
      {ProgramId::Wireframe, "wireframe", "render/wireframe.vert", "render/flat.frag", {}, {"u_view_projection", "u_colour"}},
      {ProgramId::Normal, "normal", vert, "render/normal.frag", {}, kTransform},
      {ProgramId::Diffuse, "diffuse", vert, "render/diffuse.frag", {}, join({kTransform, kLight, {"u_colour"}})},
      {ProgramId::Phong, "phong", vert, "render/phong.frag", {},
       join({kTransform, kLight, {"u_colour", "u_eye", "u_phong_terms"}})},
      {ProgramId::Texture, "texture", vert, "render/texture.frag", {}, join({kTransform, kLight, {"u_texture"}})},
      {ProgramId::Bump, "bump", vert, "render/bump.frag", {{"TANGENT_SPACE", ""}},
       join({kTransform, kLight, kBump, {"u_colour", "u_eye"}})},
      {ProgramId::Displacement, "displacement", vert, "render/bump.frag", {{"TANGENT_SPACE", ""}, {"DISPLACE", ""}},
       join({kTransform, kLight, kBump, {"u_colour", "u_eye"}})},
      {ProgramId::Mirror, "mirror", vert, "render/mirror.frag", {}, join({kTransform, {"u_eye", "u_environment"}})},
      {ProgramId::Toon, "toon", vert, "render/toon.frag", {},
       join({kTransform, {"u_light_position", "u_colour", "u_eye", "u_toon_levels"}})},
      {ProgramId::Shadow, "shadow", vert, "render/shadow.frag", {{"SHADOW_RECEIVER", ""}},
       join({kTransform, kLight, {"u_colour", "u_eye", "u_light_view_projection", "u_shadow_map"}})},
      {ProgramId::Ground, "ground", vert, "render/ground.frag", {{"SHADOW_RECEIVER", ""}},
       join({kTransform, kLight,
             {"u_colour", "u_light_view_projection", "u_shadow_map", "u_background", "u_fade", "u_shadows"}})},
      {ProgramId::ShadowDepth, "shadow_depth", vert, "render/depth.frag", {{"DEPTH_ONLY", ""}},
       {"u_model", "u_view_projection", "u_point_count"}},
      {ProgramId::Sky, "sky", "render/sky.vert", "render/sky.frag", {}, {"u_environment", "u_inverse_view_projection"}},
      {ProgramId::Pick, "pick", vert, "render/pick.frag", {}, {"u_model", "u_view_projection", "u_point_count", "u_grid_size"}},
  }};
  // clang-format on
}

}  // namespace

const std::array<ProgramSpec, kProgramCount>& programSpecs() {
  static const std::array<ProgramSpec, kProgramCount> specs = makeSpecs();
  return specs;
}

const ProgramSpec& programSpec(ProgramId id) {
  return programSpecs()[std::size_t(id)];
}

ProgramId clothProgram(Shading shading) {
  switch (shading) {
    case Shading::Wireframe:
      return ProgramId::Wireframe;
    case Shading::Normal:
      return ProgramId::Normal;
    case Shading::Diffuse:
      return ProgramId::Diffuse;
    case Shading::Phong:
      return ProgramId::Phong;
    case Shading::Texture:
      return ProgramId::Texture;
    case Shading::Bump:
      return ProgramId::Bump;
    case Shading::Displacement:
      return ProgramId::Displacement;
    case Shading::Mirror:
      return ProgramId::Mirror;
    case Shading::Toon:
      return ProgramId::Toon;
    case Shading::Shadow:
      return ProgramId::Shadow;
  }
  return ProgramId::Phong;
}

ProgramId colliderProgram(Shading shading) {
  switch (shading) {
    case Shading::Wireframe:
    case Shading::Texture:
      return ProgramId::Diffuse;
    case Shading::Displacement:
      return ProgramId::Bump;
    default:
      return clothProgram(shading);
  }
}

ShadingProgram::ShadingProgram(const ProgramSpec& spec)
    : spec_(&spec), program_(gl::compileGraphics(spec.vert, spec.frag, spec.defines)) {
  const std::pair<const char*, int> samplers[] = {{"u_texture", RENDER_UNIT_TEXTURE},
                                                  {"u_height_map", RENDER_UNIT_HEIGHT_MAP},
                                                  {"u_environment", RENDER_UNIT_ENVIRONMENT},
                                                  {"u_shadow_map", RENDER_UNIT_SHADOW_MAP}};
  for (const auto& [name, unit] : samplers)
    if (std::find(spec.uniforms.begin(), spec.uniforms.end(), name) != spec.uniforms.end()) set(name, unit);
}

bool ShadingProgram::declares(const char* name) const {
  return spec_ && std::find(spec_->uniforms.begin(), spec_->uniforms.end(), name) != spec_->uniforms.end();
}

void ShadingProgram::requireDeclared(const char* name) const {
  if (!spec_) throw gl::GlError(std::string("uniform '") + name + "' set on a program that was never compiled");
  if (std::find(spec_->uniforms.begin(), spec_->uniforms.end(), name) == spec_->uniforms.end())
    throw gl::GlError("program " + spec_->name + " does not declare uniform '" + name + "'");
}

ProgramSet ProgramSet::compileAll() {
  ProgramSet set;
  for (const ProgramSpec& spec : programSpecs())
    set.programs_[std::size_t(spec.id)] = ShadingProgram(spec);
  return set;
}

std::string ProgramSet::reload() {
  std::string errors;
  for (const ProgramSpec& spec : programSpecs()) {
    try {
      programs_[std::size_t(spec.id)] = ShadingProgram(spec);
    } catch (const gl::ShaderError& e) {
      errors += std::string(e.what()) + "\n";
    }
  }
  return errors;
}

}  // namespace drape
