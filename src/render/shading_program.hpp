// The renderer's GLSL programs: each one is declared once (files, variant #defines, the uniforms the
// C++ side sets), compiled from glsl/render/, and reloadable at run time. Setting a uniform the
// declaration does not list is an error (a misspelt name is not silence); a listed uniform that the
// driver optimised away is skipped.
#pragma once

#include "gl/objects.hpp"
#include "gl/shader_source.hpp"
#include "render/shading.hpp"

#include <array>
#include <string>
#include <vector>

namespace drape {

enum class ProgramId {
  Wireframe,
  Normal,
  Diffuse,
  Phong,
  Texture,
  Bump,
  Displacement,
  Mirror,
  Toon,
  Shadow,
  Ground,       // the planes and the neutral floor, in every shading model, receiving shadows
  ShadowDepth,  // depth-only pass from the light
  Sky,          // cube-map background behind the mirror
  Pick,         // cloth point and world position under a pixel
};
inline constexpr int kProgramCount = 14;

struct ProgramSpec {
  ProgramId id;
  std::string name;  // for messages
  std::string vert;  // relative to glsl/
  std::string frag;
  gl::Defines defines;
  std::vector<std::string> uniforms;  // every uniform the renderer sets on it
};

const std::array<ProgramSpec, kProgramCount>& programSpecs();
const ProgramSpec& programSpec(ProgramId id);

// Programs drawing the cloth and the colliders for a shading model. Colliders show the model too,
// except where it is about the cloth: wireframe draws springs (colliders are diffuse), texture is the
// fabric (colliders are diffuse), displacement moves cloth vertices (colliders are bump-mapped).
ProgramId clothProgram(Shading shading);
ProgramId colliderProgram(Shading shading);

class ShadingProgram {
 public:
  ShadingProgram() = default;
  // Compiles and links; throws gl::ShaderError with file:line on failure. Samplers get their units.
  explicit ShadingProgram(const ProgramSpec& spec);

  const gl::Program& program() const { return program_; }
  const ProgramSpec& spec() const { return *spec_; }
  void use() const { program_.use(); }

  bool declares(const char* name) const;
  template <class T>
  void set(const char* name, const T& value) const {
    requireDeclared(name);
    program_.setUniformOptional(name, value);
  }

 private:
  void requireDeclared(const char* name) const;

  const ProgramSpec* spec_ = nullptr;
  gl::Program program_;
};

// All programs. reload() compiles each again and keeps the old one of any that fails.
class ProgramSet {
 public:
  ProgramSet() = default;
  static ProgramSet compileAll();  // throws gl::ShaderError on the first failure

  const ShadingProgram& operator[](ProgramId id) const { return programs_[std::size_t(id)]; }

  // Returns the compiler messages of the programs that failed ("" when all compiled).
  std::string reload();

 private:
  std::array<ShadingProgram, kProgramCount> programs_;
};

}  // namespace drape
