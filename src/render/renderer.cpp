#include "render/renderer.hpp"

#include "core/mesh_obstacle.hpp"
#include "gl/debug.hpp"
#include "render/render_bindings.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace drape {

glm::vec3 springColour(SpringType type) {
  switch (type) {
    case SpringType::Structural:
      return {1.0f, 0.80f, 0.20f};
    case SpringType::Shearing:
      return {0.20f, 0.75f, 1.0f};
    case SpringType::Bending:
      return {1.0f, 0.30f, 0.55f};
  }
  return glm::vec3(1.0f);
}

std::array<bool, kSpringTypeCount> enabledSprings(const ClothSpec& cloth) {
  std::array<bool, kSpringTypeCount> enabled{};
  for (int t = 0; t < kSpringTypeCount; ++t)
    enabled[t] = cloth.springEnabled(SpringType(t));
  return enabled;
}

struct Renderer::Frame {
  const RenderSettings* settings = nullptr;
  glm::mat4 view_projection{1.0f};
  glm::mat4 light_view_projection{1.0f};
  glm::vec3 eye{0.0f};
};

namespace {

// The renderer offers every program the values of this frame; each takes those it declares.
template <class T>
void offer(const ShadingProgram& program, const char* name, const T& value) {
  if (program.declares(name)) program.set(name, value);
}

GLint currentDrawFramebuffer() {
  GLint framebuffer = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  return framebuffer;
}

void bindStorage(GLuint binding, GLuint buffer) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer);
}

// The default light's offset from the scene's centre, in units of the scene's radius, along the default
// view's right, world up and towards the camera: above, left and in front.
constexpr glm::vec3 kLightOffset{-1.1f, 2.2f, 1.0f};
// The default light is as far from a scene (in its radii) as Light's own default is from the unit
// scenes' centre (0.5, 0.5, 0.5), about 2.1 m, at 3 units of intensity.
constexpr float kUnitSceneLightDistance = 2.12f;
// u_point_count for the colliders: every vertex is a point, none a quad centre.
constexpr std::uint32_t kNoCentres = 0xffffffffu;

}  // namespace

Renderer::Renderer(const Scene& scene, const Topology& topology, const RendererOptions& options)
    : Renderer(scene, topology, SceneExtent(scene, topology), options) {}

Renderer::Renderer(const Scene& scene, const Topology& topology, const SceneExtent& extent,
                   const RendererOptions& options)
    : scene_(&scene),
      topology_(&topology),
      options_(options),
      programs_(ProgramSet::compileAll()),
      textures_(TextureSet::load(options.texture_dir)),
      subject_(extent.subject()),
      bounds_(subject_.bounds()),
      casters_(extent.casterBounds()),
      ground_(extent.ground()),
      surface_(topology) {
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);

  for (const MeshSpec& m : scene.meshes)
    obstacles_.push_back(uploadMesh(buildObstacleMesh(m.mesh->positions, m.mesh->triangles)));
  sphere_ = uploadMesh(buildSphereMesh(options.sphere_latitudes, options.sphere_longitudes));
  // Large enough to reach the horizon from any sensible camera position; the ground shader fades it out
  // well before its edge.
  const float plane_size = std::max(10.0f, 40.0f * bounds_.radius());
  const glm::vec3 centre = casters_.centre();
  for (const PlaneSpec& p : scene.planes) {
    const glm::vec3 n = glm::normalize(glm::vec3(p.normal)), point = glm::vec3(p.point);
    planes_.push_back(uploadMesh(buildPlaneMesh(centre - glm::dot(centre - point, n) * n, n, plane_size)));
  }
  if (!ground_.from_scene) {
    const glm::vec3 n = ground_.normal;
    planes_.push_back(uploadMesh(buildPlaneMesh(centre - glm::dot(centre - ground_.point, n) * n, n, plane_size)));
  }

  for (int t = 0; t < kSpringTypeCount; ++t) {
    std::vector<std::uint32_t> lines;
    for (const Spring& s : topology.springs)
      if (int(s.type) == t) lines.insert(lines.end(), {s.a, s.b});
    cloth_.springs[t] = gl::Buffer::fromVector(lines, 0);
    cloth_.spring_counts[t] = GLsizei(lines.size());
    cloth_.spring_vaos[t] = gl::VertexArray::create();
    glVertexArrayElementBuffer(cloth_.spring_vaos[t].id(), cloth_.springs[t].id());
  }
  empty_vao_ = gl::VertexArray::create();
  const std::uint32_t no_flags[4] = {};
  no_health_ = gl::Buffer::create(sizeof no_flags, no_flags, 0);
  const glm::vec4 no_centre(0.0f);
  no_centres_ = gl::Buffer::create(sizeof no_centre, &no_centre, 0);

  ensureShadowMap(options.shadow_map_size);
  gl::checkDebugErrors();
}

void Renderer::ensureShadowMap(int size) {
  if (shadow_.depth.id() != 0 && shadow_.depth.width() == size) return;
  shadow_ = DepthTarget{};
  shadow_.depth = gl::Texture::create2D(size, size, GL_DEPTH_COMPONENT24);
  shadow_.depth.setSampling(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
  // Comparison sampling: the hardware filters the four depth tests of a lookup (sampler2DShadow).
  glTextureParameteri(shadow_.depth.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(shadow_.depth.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  GLuint framebuffer = 0;
  glCreateFramebuffers(1, &framebuffer);
  shadow_.framebuffer = gl::UniqueName<gl::FramebufferDeleter>(framebuffer);
  glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, shadow_.depth.id(), 0);
  glNamedFramebufferDrawBuffer(framebuffer, GL_NONE);
  glNamedFramebufferReadBuffer(framebuffer, GL_NONE);
  if (glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw gl::GlError("shadow-map framebuffer is incomplete");
}

Renderer::GpuMesh Renderer::uploadMesh(const MeshData& mesh) {
  GpuMesh gpu;
  gpu.positions = gl::Buffer::fromVector(mesh.positions, 0);
  gpu.normals = gl::Buffer::fromVector(mesh.normals, 0);
  gpu.tangents = gl::Buffer::fromVector(mesh.tangents, 0);
  gpu.uvs = gl::Buffer::fromVector(mesh.uvs, 0);
  gpu.indices = gl::Buffer::fromVector(mesh.triangles, 0);
  gpu.count = GLsizei(mesh.triangles.size());
  gpu.vao = gl::VertexArray::create();
  glVertexArrayElementBuffer(gpu.vao.id(), gpu.indices.id());
  return gpu;
}

Light Renderer::defaultLight() const {
  const ViewAxes axes = Camera::defaultAxes();
  const glm::vec3 up = ground_.normal;
  const glm::vec3 right = glm::normalize(axes.right - glm::dot(axes.right, up) * up);
  const glm::vec3 towards_camera = glm::cross(right, up);
  const float radius = std::max(bounds_.radius(), 1e-3f);
  const glm::vec3 offset = radius * (kLightOffset.x * right + kLightOffset.y * up + kLightOffset.z * towards_camera);
  Light light;
  light.position = casters_.centre() + offset;
  const float ratio = glm::length(offset) / kUnitSceneLightDistance;
  light.intensity = Light{}.intensity * ratio * ratio;
  return light;
}

glm::mat4 Renderer::lightViewProjection(const Light& light) const {
  const glm::vec3 centre = casters_.centre();
  // The casters are where the extent saw them; a margin for a run that strays a little (another device's
  // rounding, a cloth dragged in the viewer).
  const float radius = std::max(1.05f * casters_.radius(), 1e-3f);
  const glm::vec3 to_centre = centre - light.position;
  const float distance = std::max(glm::length(to_centre), 1.05f * radius);
  const glm::vec3 direction = glm::normalize(glm::length(to_centre) > 0.0f ? to_centre : glm::vec3(0, -1, 0));
  const glm::vec3 up = std::abs(direction.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  const float fov = 2.0f * std::asin(std::min(radius / distance, 0.95f));
  const float near_plane = std::max(distance - radius, 0.01f * distance);
  const glm::mat4 view = glm::lookAt(light.position, light.position + direction, up);
  return glm::perspective(fov, 1.0f, near_plane, distance + radius) * view;
}

void Renderer::draw(const ClothBuffers& cloth, const Camera& camera, glm::ivec2 viewport,
                    const RenderSettings& settings) {
  const GLint target = currentDrawFramebuffer();
  Frame frame;
  frame.settings = &settings;
  frame.view_projection = camera.viewProjection(float(viewport.x) / float(std::max(viewport.y, 1)));
  frame.light_view_projection = lightViewProjection(settings.light);
  frame.eye = camera.position();

  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);  // cloth has two sides
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);

  if (settings.show_cloth) surface_.update(cloth.positions);
  const bool ground_shown = ground_.from_scene ? settings.show_colliders : settings.floor;
  if (settings.shading == Shading::Shadow || (settings.shadows && ground_shown)) {
    // About as many texels across as the image has pixels (a power of two, 256 at least, the option's size
    // at most): the shadows are as sharp as the picture, and a small picture pays for a small map.
    int size = 256;
    while (size < std::max(viewport.x, viewport.y) && size < options_.shadow_map_size)
      size *= 2;
    ensureShadowMap(std::min(size, options_.shadow_map_size));
    renderShadowMap(cloth, frame);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(target));
  }
  glViewport(0, 0, viewport.x, viewport.y);
  glClearColor(settings.background.x, settings.background.y, settings.background.z, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  textures_.fabric.bind(RENDER_UNIT_TEXTURE);
  textures_.heightMap(settings.height_map).bind(RENDER_UNIT_HEIGHT_MAP);
  textures_.sky.bind(RENDER_UNIT_ENVIRONMENT);
  shadow_.depth.bind(RENDER_UNIT_SHADOW_MAP);

  if (settings.shading == Shading::Mirror && settings.sky) drawSky(frame);
  if (settings.show_colliders) drawColliders(colliderProgram(settings.shading), frame);
  drawGround(frame);
  if (settings.show_cloth) {
    if (settings.shading == Shading::Wireframe)
      drawWireframe(cloth, frame);
    else
      drawCloth(clothProgram(settings.shading), cloth, frame);
  }
  glBindVertexArray(0);
  gl::checkDebugErrors();
}

void Renderer::renderShadowMap(const ClothBuffers& cloth, const Frame& frame) {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, shadow_.framebuffer.get());
  glViewport(0, 0, shadow_.depth.width(), shadow_.depth.height());
  glClear(GL_DEPTH_BUFFER_BIT);
  // Pushes the stored depth back a little, against self-shadowing stripes on lit surfaces.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 4.0f);
  Frame light_frame = frame;
  light_frame.view_projection = frame.light_view_projection;
  if (frame.settings->show_colliders) drawColliders(ProgramId::ShadowDepth, light_frame);
  if (frame.settings->show_cloth) drawCloth(ProgramId::ShadowDepth, cloth, light_frame);
  glDisable(GL_POLYGON_OFFSET_FILL);
}

namespace {

void offerFrame(const ShadingProgram& p, const RenderSettings& s, const glm::mat4& view_projection,
                const glm::mat4& light_view_projection, const glm::vec3& eye) {
  offer(p, "u_view_projection", view_projection);
  offer(p, "u_light_position", s.light.position);
  offer(p, "u_light_intensity", s.light.intensity);
  offer(p, "u_eye", eye);
  offer(p, "u_phong_terms", glm::vec3(s.phong_terms[0], s.phong_terms[1], s.phong_terms[2]));
  offer(p, "u_height_scaling", s.height_scaling);
  offer(p, "u_normal_scaling", s.normal_scaling);
  offer(p, "u_toon_levels", s.toon_levels);
  offer(p, "u_light_view_projection", light_view_projection);
}

void offerModel(const ShadingProgram& p, const glm::mat4& model, const glm::vec3& colour) {
  offer(p, "u_model", model);
  offer(p, "u_normal_matrix", glm::mat3(glm::transpose(glm::inverse(model))));
  offer(p, "u_colour", colour);
}

}  // namespace

void Renderer::drawColliders(ProgramId id, const Frame& frame) {
  const ShadingProgram& program = programs_[id];
  const RenderSettings& s = *frame.settings;
  program.use();
  offerFrame(program, s, frame.view_projection, frame.light_view_projection, frame.eye);
  bindStorage(RENDER_BINDING_HEALTH, no_health_.id());
  bindStorage(RENDER_BINDING_CENTRES, no_centres_.id());
  offer(program, "u_point_count", kNoCentres);
  const auto bindMesh = [](const GpuMesh& mesh) {
    bindStorage(RENDER_BINDING_POSITIONS, mesh.positions.id());
    bindStorage(RENDER_BINDING_NORMALS, mesh.normals.id());
    bindStorage(RENDER_BINDING_TANGENTS, mesh.tangents.id());
    bindStorage(RENDER_BINDING_UVS, mesh.uvs.id());
    mesh.vao.bind();
  };
  bindMesh(sphere_);
  for (const SphereSpec& sphere : scene_->spheres) {
    const float radius = float(sphere.radius) * options_.sphere_shrink;
    const glm::mat4 model = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(sphere.origin)), glm::vec3(radius));
    offerModel(program, model, s.collider_colour);
    glDrawElements(GL_TRIANGLES, sphere_.count, GL_UNSIGNED_INT, nullptr);
  }
  for (const GpuMesh& obstacle : obstacles_) {
    bindMesh(obstacle);
    offerModel(program, glm::mat4(1.0f), s.collider_colour);
    glDrawElements(GL_TRIANGLES, obstacle.count, GL_UNSIGNED_INT, nullptr);
  }
}

// The planes receive shadows but cast none (nothing lies beneath them that could be shadowed), in one
// program whatever the shading model: the ground is the stage, not the subject.
void Renderer::drawGround(const Frame& frame) {
  const RenderSettings& s = *frame.settings;
  const ShadingProgram& program = programs_[ProgramId::Ground];
  program.use();
  offerFrame(program, s, frame.view_projection, frame.light_view_projection, frame.eye);
  program.set("u_background", s.background);
  program.set("u_shadows", s.shadows);
  // Gone at 12 radii of the scene from its centre: past the framed view's corners, well before the quad's edge.
  const glm::vec3 centre =
      bounds_.centre() - glm::dot(bounds_.centre() - ground_.point, ground_.normal) * ground_.normal;
  program.set("u_fade", glm::vec4(centre, 12.0f * std::max(bounds_.radius(), 1e-3f)));
  bindStorage(RENDER_BINDING_HEALTH, no_health_.id());
  bindStorage(RENDER_BINDING_CENTRES, no_centres_.id());
  program.set("u_point_count", kNoCentres);
  // Cloth resting on a plane lies SURFACE_OFFSET (0.1 mm) above it: push the plane back in depth.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 2.0f);
  for (std::size_t i = 0; i < planes_.size(); ++i) {
    const bool scene_plane = i < scene_->planes.size();
    if (scene_plane ? !s.show_colliders : !s.floor) continue;
    const GpuMesh& plane = planes_[i];
    bindStorage(RENDER_BINDING_POSITIONS, plane.positions.id());
    bindStorage(RENDER_BINDING_NORMALS, plane.normals.id());
    bindStorage(RENDER_BINDING_TANGENTS, plane.tangents.id());
    bindStorage(RENDER_BINDING_UVS, plane.uvs.id());
    plane.vao.bind();
    offerModel(program, glm::mat4(1.0f), s.plane_colour);
    glDrawElements(GL_TRIANGLES, plane.count, GL_UNSIGNED_INT, nullptr);
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
}

void Renderer::drawCloth(ProgramId id, const ClothBuffers& cloth, const Frame& frame) {
  const ShadingProgram& program = programs_[id];
  program.use();
  offerFrame(program, *frame.settings, frame.view_projection, frame.light_view_projection, frame.eye);
  offerModel(program, glm::mat4(1.0f), frame.settings->cloth_colour);
  program.set("u_point_count", surface_.points());
  bindStorage(RENDER_BINDING_POSITIONS, cloth.positions);
  bindStorage(RENDER_BINDING_HEALTH, cloth.health != 0 ? cloth.health : no_health_.id());
  surface_.bindForDraw();
  glDrawElements(GL_TRIANGLES, surface_.indexCount(), GL_UNSIGNED_INT, nullptr);
  ++cloth_draws_;
}

void Renderer::drawWireframe(const ClothBuffers& cloth, const Frame& frame) {
  const ShadingProgram& program = programs_[ProgramId::Wireframe];
  program.use();
  program.set("u_view_projection", frame.view_projection);
  bindStorage(RENDER_BINDING_POSITIONS, cloth.positions);
  bindStorage(RENDER_BINDING_HEALTH, cloth.health != 0 ? cloth.health : no_health_.id());
  for (int t = 0; t < kSpringTypeCount; ++t) {
    if (!frame.settings->springs[t] || cloth_.spring_counts[t] == 0) continue;
    program.set("u_colour", springColour(SpringType(t)));
    cloth_.spring_vaos[t].bind();
    glDrawElements(GL_LINES, cloth_.spring_counts[t], GL_UNSIGNED_INT, nullptr);
  }
  ++cloth_draws_;
}

void Renderer::drawSky(const Frame& frame) {
  const ShadingProgram& program = programs_[ProgramId::Sky];
  program.use();
  program.set("u_inverse_view_projection", glm::inverse(frame.view_projection));
  glDisable(GL_DEPTH_TEST);
  empty_vao_.bind();
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glEnable(GL_DEPTH_TEST);
}

void Renderer::ensurePickTarget(glm::ivec2 size) {
  if (pick_.size == size && pick_.framebuffer.get() != 0) return;
  pick_ = PickTarget{};
  pick_.size = size;
  pick_.point = gl::Texture::create2D(size.x, size.y, GL_R32UI);
  pick_.position = gl::Texture::create2D(size.x, size.y, GL_RGBA32F);
  pick_.depth = gl::Renderbuffer::create(size.x, size.y, GL_DEPTH_COMPONENT24);
  GLuint framebuffer = 0;
  glCreateFramebuffers(1, &framebuffer);
  pick_.framebuffer = gl::UniqueName<gl::FramebufferDeleter>(framebuffer);
  glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, pick_.point.id(), 0);
  glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT1, pick_.position.id(), 0);
  glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, pick_.depth.id());
  const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer, 2, buffers);
  if (glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw gl::GlError("picking framebuffer is incomplete");
}

std::optional<PickHit> Renderer::pick(const ClothBuffers& cloth, const Camera& camera, glm::ivec2 viewport,
                                      glm::vec2 pixel) {
  const glm::ivec2 p{int(std::floor(pixel.x)), viewport.y - 1 - int(std::floor(pixel.y))};
  if (p.x < 0 || p.y < 0 || p.x >= viewport.x || p.y >= viewport.y) return std::nullopt;
  const GLint target = currentDrawFramebuffer();
  ensurePickTarget(viewport);
  surface_.update(cloth.positions);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, pick_.framebuffer.get());
  glViewport(0, 0, viewport.x, viewport.y);
  const GLuint no_point = 0;
  const GLfloat no_position[4] = {0, 0, 0, 0};
  const GLfloat far_depth = 1.0f;
  glClearNamedFramebufferuiv(pick_.framebuffer.get(), GL_COLOR, 0, &no_point);
  glClearNamedFramebufferfv(pick_.framebuffer.get(), GL_COLOR, 1, no_position);
  glClearNamedFramebufferfv(pick_.framebuffer.get(), GL_DEPTH, 0, &far_depth);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);

  const ShadingProgram& program = programs_[ProgramId::Pick];
  program.use();
  program.set("u_model", glm::mat4(1.0f));
  program.set("u_view_projection", camera.viewProjection(float(viewport.x) / float(std::max(viewport.y, 1))));
  program.set("u_grid_size", glm::vec2(float(topology_->W), float(topology_->H)));
  program.set("u_point_count", surface_.points());
  bindStorage(RENDER_BINDING_POSITIONS, cloth.positions);
  bindStorage(RENDER_BINDING_HEALTH, cloth.health != 0 ? cloth.health : no_health_.id());
  surface_.bindForDraw();
  glDrawElements(GL_TRIANGLES, surface_.indexCount(), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);

  // The one explicit read-back of picking: a single pixel of each target.
  GLuint point = 0;
  glm::vec4 position{0.0f};
  glGetTextureSubImage(pick_.point.id(), 0, p.x, p.y, 0, 1, 1, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, sizeof(point),
                       &point);
  glGetTextureSubImage(pick_.position.id(), 0, p.x, p.y, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof(position), &position);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(target));
  gl::checkDebugErrors();
  if (point == 0 || int(point) > topology_->pointCount()) return std::nullopt;
  return PickHit{int(point) - 1, glm::vec3(position)};
}

}  // namespace drape
