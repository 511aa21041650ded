// Draws a scene: the cloth straight from storage buffers (ClothBuffers, by vertex pulling with the
// topology's triangles or springs as the element buffer), the spheres slightly shrunk so the cloth
// resting on them does not z-fight, and the ground (each plane, or a neutral floor under a scene without
// one) as a large quad that receives the shadows of everything above it, in one of the shading models.
#pragma once

#include "core/scene.hpp"
#include "core/topology.hpp"
#include "render/camera.hpp"
#include "render/cloth_feed.hpp"
#include "render/framing.hpp"
#include "render/mesh_data.hpp"
#include "render/shading.hpp"
#include "render/shading_program.hpp"
#include "render/surface_pass.hpp"
#include "render/texture_set.hpp"

#include <array>
#include <filesystem>
#include <optional>
#include <string>

namespace drape {

struct Light {
  glm::vec3 position{0.5f, 2.0f, 2.0f};   // world space, m (Renderer::defaultLight places it for a scene)
  glm::vec3 intensity{3.0f, 3.0f, 3.0f};  // per channel; irradiance falls off as 1/r^2
};

struct RenderSettings {
  Shading shading = Shading::Phong;
  glm::vec3 cloth_colour{0.80f, 0.32f, 0.26f};     // diffuse colour of the cloth (not texture, mirror)
  glm::vec3 collider_colour{0.70f, 0.71f, 0.74f};  // spheres
  glm::vec3 plane_colour{0.52f, 0.54f, 0.58f};     // the ground
  glm::vec3 background{0.12f, 0.13f, 0.16f};
  Light light;
  std::array<bool, 3> phong_terms{true, true, true};             // ambient, diffuse, specular
  HeightMap height_map = HeightMap::Cobblestone;                 // bump and displacement
  float normal_scaling = 100.0f;                                 // kn: steepness of bump normals
  float height_scaling = 0.02f;                                  // kh, m: height of the map's white
  int toon_levels = 4;                                           // bands of the toon shading
  std::array<bool, kSpringTypeCount> springs{true, true, true};  // wireframe: types drawn
  bool show_cloth = true;
  bool show_colliders = true;
  bool floor = true;    // a neutral floor under a scene that has no plane
  bool shadows = true;  // the cloth's and the colliders' shadows on the ground (the shadow model: everywhere)
  bool sky = true;      // mirror: the environment as background
};

// Wireframe colours per spring type (structural, shearing, bending).
glm::vec3 springColour(SpringType type);
// The wireframe shows the spring types the cloth enables.
std::array<bool, kSpringTypeCount> enabledSprings(const ClothSpec& cloth);

struct RendererOptions {
  int sphere_latitudes = 40;    // -a
  int sphere_longitudes = 40;   // -o
  float sphere_shrink = 0.98f;  // drawn radius / collision radius
  std::filesystem::path texture_dir = textureDir();
  int shadow_map_size = 1024;  // at most; a smaller picture gets a smaller map
};

// What is under a pixel of the cloth.
struct PickHit {
  int point = -1;            // index of the nearest cloth point
  glm::vec3 position{0.0f};  // world position of the surface under the pixel
};

class Renderer {
 public:
  // Needs a current GL 4.5 context. Throws gl::ShaderError or ImageError (naming the file). The extent says
  // where the cloth goes (the default: where it starts): it places the neutral floor and the light, and the
  // shadow map covers it.
  Renderer(const Scene& scene, const Topology& topology, const RendererOptions& options = {});
  Renderer(const Scene& scene, const Topology& topology, const SceneExtent& extent,
           const RendererOptions& options = {});

  // Draws into the framebuffer bound now, over (0, 0, viewport), clearing it first.
  void draw(const ClothBuffers& cloth, const Camera& camera, glm::ivec2 viewport, const RenderSettings& settings);

  // The cloth point under `pixel` (origin top-left), found on the GPU: the cloth is drawn into an
  // integer target and one pixel is read back. Empty when the pixel shows no cloth.
  std::optional<PickHit> pick(const ClothBuffers& cloth, const Camera& camera, glm::ivec2 viewport, glm::vec2 pixel);

  // Compiles every program again; a program that fails keeps its old version. Returns the compiler
  // messages ("" when all compiled).
  std::string reloadShaders() { return programs_.reload() + surface_.reload(); }
  const ProgramSet& programs() const { return programs_; }

  // What the default camera frames (Camera::frame): the cloth wherever the extent saw it, the colliders
  // (spheres as spheres) and the cloth's footprint on the ground; and the box around all of it.
  const FramingSubject& framingSubject() const { return subject_; }
  const Bounds& sceneBounds() const { return bounds_; }
  const Ground& ground() const { return ground_; }
  // A light above the scene and to the left of the default view, as far from it as the default light is
  // from the unit scenes, with the same irradiance there: shadows fall to the right and back, in view.
  Light defaultLight() const;
  // The light's frustum, around everything that casts a shadow.
  glm::mat4 lightViewProjection(const Light& light) const;

  // Borrowed storage buffers are bound at RENDER_BINDING_* only while drawing; the renderer keeps
  // no copy of the cloth. These count the cloth's draws, for tests and the panel.
  long long clothDraws() const { return cloth_draws_; }
  // The cloth's surface as last computed for a draw (normals, tangents, quad centres), for tests.
  const SurfacePass& surface() const { return surface_; }

 private:
  struct GpuMesh {
    gl::Buffer positions, normals, tangents, uvs, indices;
    gl::VertexArray vao;
    GLsizei count = 0;
  };
  struct ClothGeometry {  // what the wireframe draws: the springs, by type
    std::array<gl::Buffer, kSpringTypeCount> springs;
    std::array<gl::VertexArray, kSpringTypeCount> spring_vaos;
    std::array<GLsizei, kSpringTypeCount> spring_counts{};
  };
  struct DepthTarget {
    gl::Texture depth;
    gl::UniqueName<gl::FramebufferDeleter> framebuffer;
  };
  struct PickTarget {
    glm::ivec2 size{0};
    gl::Texture point, position;
    gl::Renderbuffer depth;
    gl::UniqueName<gl::FramebufferDeleter> framebuffer;
  };
  struct Frame;  // per-draw values offered to every program

  static GpuMesh uploadMesh(const MeshData& mesh);
  void renderShadowMap(const ClothBuffers& cloth, const Frame& frame);
  void drawColliders(ProgramId id, const Frame& frame);
  void drawGround(const Frame& frame);
  void drawCloth(ProgramId id, const ClothBuffers& cloth, const Frame& frame);
  void drawWireframe(const ClothBuffers& cloth, const Frame& frame);
  void drawSky(const Frame& frame);
  void ensurePickTarget(glm::ivec2 size);
  void ensureShadowMap(int size);  // texels across

  const Scene* scene_;
  const Topology* topology_;
  RendererOptions options_;
  ProgramSet programs_;
  TextureSet textures_;
  FramingSubject subject_;
  Bounds bounds_;   // of subject_
  Bounds casters_;  // what casts shadows
  Ground ground_;
  GpuMesh sphere_;
  std::vector<GpuMesh> planes_;     // the scene's, or the neutral floor
  std::vector<GpuMesh> obstacles_;  // the scene's mesh obstacles, in scene coordinates
  SurfacePass surface_;             // the cloth's normals, tangents and quad centres
  ClothGeometry cloth_;
  gl::VertexArray empty_vao_;
  gl::Buffer no_health_;   // zero flags, for what has no solver behind it
  gl::Buffer no_centres_;  // bound for the colliders, which have no quad centres
  DepthTarget shadow_;
  PickTarget pick_;
  long long cloth_draws_ = 0;
};

}  // namespace drape
