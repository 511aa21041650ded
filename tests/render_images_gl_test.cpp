// Images the renderer makes of the sphere scene, checked pixel by pixel against where the cloth must be
// (its triangles projected on the CPU from an explicit read-back), never against a stored picture.
#include "core/scene.hpp"
#include "cpu/cpu_solver.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "render/reach_probe.hpp"
#include "render/renderer.hpp"
#include "test_paths.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

namespace drape {
namespace {

constexpr glm::ivec2 kSize{160, 120};
constexpr int kFrames = 12;  // the cloth has fallen a little and is still above the sphere

using Mask = std::vector<std::uint8_t>;  // kSize.x * kSize.y, row 0 at the top

struct Picture {
  std::vector<std::uint8_t> rgba;  // rows top to bottom
  const std::uint8_t* at(int x, int y) const { return &rgba[(std::size_t(y) * kSize.x + x) * 4]; }
  bool differs(const Picture& other, int x, int y) const {
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(at(x, y)[c]) - int(other.at(x, y)[c])) > 2) return true;
    return false;
  }
};

glm::vec2 toPixel(const glm::mat4& vp, const glm::vec3& p) {
  const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {(ndc.x * 0.5f + 0.5f) * float(kSize.x), (0.5f - ndc.y * 0.5f) * float(kSize.y)};
}

float edge(glm::vec2 a, glm::vec2 b, glm::vec2 p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Pixels whose centre lies inside a projected cloth triangle.
Mask projectCloth(const Topology& topo, const std::vector<glm::dvec3>& x, const glm::mat4& vp) {
  Mask mask(std::size_t(kSize.x) * kSize.y, 0);
  for (std::size_t t = 0; t < topo.triangles.size(); t += 3) {
    const glm::vec2 a = toPixel(vp, glm::vec3(x[topo.triangles[t]])),
                    b = toPixel(vp, glm::vec3(x[topo.triangles[t + 1]])),
                    c = toPixel(vp, glm::vec3(x[topo.triangles[t + 2]]));
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x})))),
              x1 = std::min(kSize.x - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y})))),
              y1 = std::min(kSize.y - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    for (int py = y0; py <= y1; ++py)
      for (int px = x0; px <= x1; ++px) {
        const glm::vec2 p{float(px) + 0.5f, float(py) + 0.5f};
        const float e0 = edge(a, b, p), e1 = edge(b, c, p), e2 = edge(c, a, p);
        if ((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0))
          mask[std::size_t(py) * kSize.x + px] = 1;
      }
  }
  return mask;
}

// Grows (grow > 0) or shrinks (grow < 0) a mask by |grow| pixels in the chessboard metric.
Mask morph(const Mask& mask, int grow) {
  const int r = std::abs(grow);
  Mask out(mask.size(), 0);
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      bool any = false, all = true;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int sx = x + dx, sy = y + dy;
          const bool v = sx >= 0 && sy >= 0 && sx < kSize.x && sy < kSize.y && mask[std::size_t(sy) * kSize.x + sx];
          any |= v;
          all &= v;
        }
      out[std::size_t(y) * kSize.x + x] = grow > 0 ? any : all;
    }
  return out;
}

// Screen rectangle around each sphere's bounding box, grown by two pixels.
Mask sphereBoxes(const Scene& scene, const glm::mat4& vp) {
  Mask mask(std::size_t(kSize.x) * kSize.y, 0);
  for (const SphereSpec& s : scene.spheres) {
    glm::vec2 lo{1e9f}, hi{-1e9f};
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 sign{corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 1.0 : -1.0};
      const glm::vec2 p = toPixel(vp, glm::vec3(s.origin + sign * s.radius));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    for (int y = std::max(0, int(lo.y) - 2); y <= std::min(kSize.y - 1, int(hi.y) + 2); ++y)
      for (int x = std::max(0, int(lo.x) - 2); x <= std::min(kSize.x - 1, int(hi.x) + 2); ++x)
        mask[std::size_t(y) * kSize.x + x] = 1;
  }
  return mask;
}

std::size_t count(const Mask& mask) {
  return std::size_t(std::count(mask.begin(), mask.end(), 1));
}

// One scene, one solver, one renderer, drawing into a small offscreen target.
struct Stage {
  Scene scene;
  std::unique_ptr<Solver> solver;
  std::unique_ptr<ClothFeed> feed;
  std::unique_ptr<Renderer> renderer;
  gl::Framebuffer target;
  Camera camera;

  Stage(Scene s, std::unique_ptr<Solver> made, int frames) : scene(std::move(s)), solver(std::move(made)) {
    for (int f = 0; f < frames; ++f)
      solver->stepFrame();
    feed = std::make_unique<ClothFeed>(*solver);
    renderer = std::make_unique<Renderer>(scene, solver->topology());
    target = gl::Framebuffer::createColorDepth(kSize.x, kSize.y);
    camera.frame(renderer->sceneBounds(), float(kSize.x) / float(kSize.y));
    // These pictures need room around the scene (a point lifted above the cloth, a displaced surface):
    // the distance at which the box's enclosing sphere fits, as the camera framed before it fitted the box.
    const float half_fov = 0.5f * Camera::kFovY;
    camera.zoom(1.05f * renderer->sceneBounds().radius() / std::sin(half_fov) / camera.distance());
  }

  Picture draw(const RenderSettings& settings) {
    target.bind();
    renderer->draw(feed->prepare(), camera, kSize, settings);
    return {target.readPixelsRGBA()};
  }
  glm::mat4 viewProjection() const { return camera.viewProjection(float(kSize.x) / float(kSize.y)); }
  Mask expectedCloth() { return projectCloth(solver->topology(), solver->readPositions(), viewProjection()); }
  // Pixels the cloth changes: the picture with it against the picture without it. Without shadows on the
  // floor: the cloth's shadow changes pixels away from the cloth.
  Mask drawnCloth(RenderSettings settings) {
    settings.shadows = false;
    const Picture with = draw(settings);
    settings.show_cloth = false;
    const Picture without = draw(settings);
    Mask mask(std::size_t(kSize.x) * kSize.y, 0);
    for (int y = 0; y < kSize.y; ++y)
      for (int x = 0; x < kSize.x; ++x)
        mask[std::size_t(y) * kSize.x + x] = with.differs(without, x, y);
    return mask;
  }
};

Scene sphereScene() {
  return loadScene(std::filesystem::path(drape::test::sourceDir()) / "scenes" / "sphere.json");
}

class RenderImageTest : public GlTest {
 protected:
  // Shared by the tests that only look: stepping the solver is the slow part on llvmpipe.
  static Stage& fallen() {
    static Stage stage(sphereScene(), std::make_unique<GpuSolver>(sphereScene()), kFrames);
    return stage;
  }
};

class ShadingImageTest : public RenderImageTest, public ::testing::WithParamInterface<Shading> {};

TEST_P(ShadingImageTest, ClothCoversExactlyWhereItsTrianglesProject) {
  Stage& stage = fallen();
  RenderSettings settings;
  settings.shading = GetParam();
  const Mask expected = stage.expectedCloth();
  const Mask drawn = stage.drawnCloth(settings);
  const Mask inside = morph(expected, -1);
  const Mask near = morph(expected, 2);
  const Mask spheres = sphereBoxes(stage.scene, stage.viewProjection());
  ASSERT_GT(count(inside), 800u) << "the cloth should fill a good part of a framed view";

  std::size_t inside_drawn = 0, outside_drawn = 0;
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    if (inside[i]) inside_drawn += drawn[i];
    if (!near[i] && !spheres[i]) outside_drawn += drawn[i];
  }
  // Lines of a 50x50 grid are denser than these pixels, but a line rasterises to fewer pixels than a
  // surface, so the wireframe may leave a few interior pixels unlit.
  const double min_fraction = GetParam() == Shading::Wireframe ? 0.85 : 0.99;
  EXPECT_GE(double(inside_drawn), min_fraction * double(count(inside)))
      << inside_drawn << " of " << count(inside) << " interior pixels show the cloth";
  EXPECT_EQ(outside_drawn, 0u) << "pixels changed by the cloth away from where it projects";
}

INSTANTIATE_TEST_SUITE_P(Every, ShadingImageTest, ::testing::ValuesIn(allShadings()),
                         [](const auto& test) { return std::string(shadingName(test.param)); });

TEST_F(RenderImageTest, MirrorDiffersFromPhongOnTheCloth) {
  Stage& stage = fallen();
  RenderSettings phong, mirror;
  mirror.shading = Shading::Mirror;
  mirror.sky = false;  // same background, so only the surfaces differ
  const Picture a = stage.draw(phong), b = stage.draw(mirror);
  const Mask inside = morph(stage.expectedCloth(), -1);
  double total = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      if (!inside[std::size_t(y) * kSize.x + x]) continue;
      for (int c = 0; c < 3; ++c)
        total += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
      ++n;
    }
  ASSERT_GT(n, 0u);
  EXPECT_GT(total / double(3 * n), 20.0) << "mean difference per channel on the cloth";
}

TEST_F(RenderImageTest, DisplacementChangesTheSilhouetteBumpDoesNot) {
  Stage& stage = fallen();
  RenderSettings settings;
  settings.height_scaling = 0.05f;
  settings.normal_scaling = 20.0f;
  settings.shading = Shading::Phong;
  const Mask phong = stage.drawnCloth(settings);
  settings.shading = Shading::Bump;
  const Mask bump = stage.drawnCloth(settings);
  settings.shading = Shading::Displacement;
  const Mask displaced = stage.drawnCloth(settings);
  std::size_t bump_changed = 0, displacement_changed = 0;
  for (std::size_t i = 0; i < phong.size(); ++i) {
    bump_changed += phong[i] != bump[i];
    displacement_changed += phong[i] != displaced[i];
  }
  EXPECT_EQ(bump_changed, 0u);
  EXPECT_GT(displacement_changed, count(phong) / 50) << "of " << count(phong) << " cloth pixels";
}

TEST_F(RenderImageTest, WireframeDrawsOnlyTheEnabledSpringTypes) {
  Stage& stage = fallen();
  const auto pixelsOf = [](const Picture& p, SpringType type) {
    const glm::ivec3 colour = glm::ivec3(glm::round(springColour(type) * 255.0f));
    std::size_t n = 0;
    for (int y = 0; y < kSize.y; ++y)
      for (int x = 0; x < kSize.x; ++x) {
        const std::uint8_t* c = p.at(x, y);
        n += std::abs(c[0] - colour.x) <= 1 && std::abs(c[1] - colour.y) <= 1 && std::abs(c[2] - colour.z) <= 1;
      }
    return n;
  };
  ClothSpec cloth = stage.scene.cloth;
  RenderSettings settings;
  settings.shading = Shading::Wireframe;
  settings.springs = enabledSprings(cloth);
  const Picture all = stage.draw(settings);
  EXPECT_GT(pixelsOf(all, SpringType::Shearing), 50u);
  cloth.enable_shearing = false;
  settings.springs = enabledSprings(cloth);
  const Picture no_shearing = stage.draw(settings);
  EXPECT_EQ(pixelsOf(no_shearing, SpringType::Shearing), 0u);
  EXPECT_GT(pixelsOf(no_shearing, SpringType::Structural), 50u);
  EXPECT_GT(pixelsOf(no_shearing, SpringType::Bending), 50u);
}

TEST_F(RenderImageTest, PickFindsThePointUnderThePixel) {
  Stage& stage = fallen();
  const Topology& topo = stage.solver->topology();
  const std::vector<glm::dvec3> x = stage.solver->readPositions();
  for (glm::ivec2 grid : {glm::ivec2(25, 25), glm::ivec2(10, 40), glm::ivec2(40, 8)}) {
    const int index = grid.y * topo.W + grid.x;
    const glm::vec2 pixel = toPixel(stage.viewProjection(), glm::vec3(x[std::size_t(index)]));
    const std::optional<PickHit> hit = stage.renderer->pick(stage.feed->prepare(), stage.camera, kSize, pixel);
    ASSERT_TRUE(hit.has_value()) << "no cloth under the projection of point " << index;
    EXPECT_LE(std::abs(hit->point % topo.W - grid.x), 1);
    EXPECT_LE(std::abs(hit->point / topo.W - grid.y), 1);
    EXPECT_LT(glm::distance(hit->position, glm::vec3(x[std::size_t(index)])), 0.03f);
  }
  EXPECT_FALSE(stage.renderer->pick(stage.feed->prepare(), stage.camera, kSize, {1.0f, 1.0f}).has_value());
}

// The renderer draws from the solver's own buffers: a point moved on the GPU shows in the next image,
// and nothing about the cloth went through the CPU on the way.
TEST_F(RenderImageTest, DrawsStraightFromTheSolverBuffers) {
  auto made = std::make_unique<GpuSolver>(sphereScene());
  GpuSolver& gpu = *made;
  Stage stage(sphereScene(), std::move(made), 0);
  ASSERT_TRUE(stage.feed->borrowsSolverBuffers());
  const ClothBuffers buffers = stage.feed->prepare();
  EXPECT_EQ(buffers.positions, gpu.positionBuffer().id());
  EXPECT_EQ(buffers.health, gpu.healthBuffer().id());

  RenderSettings settings;
  const Picture before = stage.draw(settings);
  const Mask cloth_before = morph(stage.expectedCloth(), 1);
  const int centre = 25 * gpu.topology().W + 25;
  const glm::vec3 lifted =
      glm::vec3(gpu.topology().initial_positions[std::size_t(centre)]) + glm::vec3(0.0f, 0.3f, 0.0f);
  gpu.setPosition(std::uint32_t(centre), lifted);  // the solver's own upload, into its buffer
  const Picture after = stage.draw(settings);

  // The spike changes the picture, and rises above the cloth's outline: pixels that showed no cloth before.
  const glm::vec2 tip = toPixel(stage.viewProjection(), lifted);
  ASSERT_TRUE(tip.x >= 0 && tip.y >= 0 && tip.x < kSize.x && tip.y < kSize.y) << "the spike is in the frame";
  std::size_t changed = 0, beyond_outline = 0;
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x)
      if (after.differs(before, x, y)) {
        ++changed;
        beyond_outline += cloth_before[std::size_t(y) * kSize.x + x] == 0;
      }
  EXPECT_GT(changed, 20u);
  EXPECT_GT(beyond_outline, 3u) << "the spike's tip at " << tip.x << ", " << tip.y;
}

// A cloth whose blow-up flags are raised is hidden by the vertex shaders, which read the flags on the GPU:
// the viewer learns of a blow-up a frame late (Solver::recentHealth) and must not draw the garbage
// meanwhile. Surface and wireframe both; the colliders stay. The draw itself reads nothing back.
TEST_F(RenderImageTest, AClothWithRaisedFlagsIsNotDrawn) {
  auto made = std::make_unique<GpuSolver>(sphereScene());
  GpuSolver& gpu = *made;
  Stage stage(sphereScene(), std::move(made), 0);
  for (const Shading shading : {Shading::Phong, Shading::Wireframe}) {
    RenderSettings settings;
    settings.shading = shading;
    ASSERT_GT(count(stage.drawnCloth(settings)), 100u) << "a healthy cloth is drawn";
  }
  std::vector<glm::dvec3> x = gpu.topology().initial_positions;
  const std::vector<glm::dvec3> v(x.size(), glm::dvec3(0));
  x[7].y = 2e5;  // beyond the sane bound, yet finite: the rest of the cloth would still be drawn
  gpu.uploadState(x, v, 0);
  gpu.checkHealth();
  for (const Shading shading : {Shading::Phong, Shading::Wireframe}) {
    RenderSettings settings;
    settings.shading = shading;
    gl::DispatchRecorder recorder;
    stage.target.bind();
    stage.renderer->draw(stage.feed->prepare(), stage.camera, kSize, settings);
    EXPECT_TRUE(recorder.waits().empty()) << recorder.waits().front().what;
    EXPECT_EQ(count(stage.drawnCloth(settings)), 0u) << "shading " << int(shading);
  }
  ASSERT_FALSE(gpu.health().ok());  // the flags the shaders saw
  gpu.reset();
  RenderSettings settings;
  EXPECT_GT(count(stage.drawnCloth(settings)), 100u) << "drawn again once the flags are cleared";
}

// The CPU path (an explicit upload) matches the GPU path: same coverage at the start. The renderer's surface
// pass on the GPU agrees with its CPU reference on the fallen cloth: normals, tangents with the bitangent's
// sign, and the quad centres.
TEST_F(RenderImageTest, CpuFeedMatchesGpuFeedAndTheSurfacePassItsReference) {
  Stage gpu_stage(sphereScene(), std::make_unique<GpuSolver>(sphereScene()), 0);
  Stage cpu_stage(sphereScene(), std::make_unique<CpuSolver<float>>(sphereScene()), 0);
  EXPECT_FALSE(cpu_stage.feed->borrowsSolverBuffers());
  RenderSettings settings;
  EXPECT_EQ(gpu_stage.drawnCloth(settings), cpu_stage.drawnCloth(settings));

  Stage& fallen_stage = fallen();
  auto& gpu = static_cast<GpuSolver&>(*fallen_stage.solver);
  fallen_stage.draw(settings);
  const SurfacePass& surface = fallen_stage.renderer->surface();
  const auto positions = gpu.positionBuffer().download<glm::vec4>(std::size_t(gpu.topology().pointCount()));
  std::vector<glm::vec4> normals, tangents, centres;
  computeSurface(surface.layout(), positions, normals, tangents, centres);
  const auto gpu_normals = surface.downloadNormals(), gpu_tangents = surface.downloadTangents();
  const auto gpu_centres = surface.downloadCentres();
  ASSERT_EQ(gpu_normals.size(), normals.size());
  ASSERT_EQ(gpu_centres.size(), centres.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    ASSERT_GT(glm::dot(glm::vec3(normals[i]), glm::vec3(gpu_normals[i])), 0.999f) << "normal of vertex " << i;
    ASSERT_GT(glm::dot(glm::vec3(tangents[i]), glm::vec3(gpu_tangents[i])), 0.999f) << "tangent of vertex " << i;
    ASSERT_EQ(tangents[i].w, gpu_tangents[i].w) << "bitangent sign of vertex " << i;
  }
  for (std::size_t q = 0; q < centres.size(); ++q)
    ASSERT_LT(glm::distance(glm::vec3(centres[q]), glm::vec3(gpu_centres[q])), 1e-5f) << "centre of quad " << q;
}

// The default camera's follow measures the cloth on the GPU (render/reach_probe.hpp): the pass finds what
// reachOf finds in a read-back of the same positions, keeps the measure before for a reader a frame late,
// and measures nothing of a cloth whose blow-up flags are raised (the renderer hides it).
TEST_F(RenderImageTest, ReachProbeMeasuresWhatTheCpuFindsInTheSolversBuffer) {
  Stage& stage = fallen();
  auto& gpu = static_cast<GpuSolver&>(*stage.solver);
  const ReachFrame frame = ReachFrame::of({0.1f, 0.2f, -0.3f}, 4.0f / 3.0f), wide = ReachFrame::of({}, 2.0f);
  const std::array<float, ViewReach::kValues> expected = reachOf(gpu.readPositions(), frame).values();
  ReachProbe probe(gpu);
  EXPECT_TRUE(probe.latest().empty()) << "nothing measured yet";
  probe.measure(frame);
  probe.measure(wide);
  const ViewReach previous = probe.previous(), latest = probe.latest();
  EXPECT_EQ(previous.t_x, frame.t_x);
  EXPECT_EQ(latest.t_x, wide.t_x);
  for (int k = 0; k < ViewReach::kValues; ++k)
    EXPECT_NEAR(previous.values()[k], expected[k], 1e-5f * (1.0f + std::abs(expected[k]))) << "value " << k;
  EXPECT_EQ(latest.box.min, previous.box.min) << "the box does not depend on the view";
  EXPECT_GT(latest.right, -1e29f);

  GpuSolver fresh(sphereScene());
  std::vector<glm::dvec3> x = fresh.topology().initial_positions;
  x[7].y = 2e5;
  fresh.uploadState(x, std::vector<glm::dvec3>(x.size(), glm::dvec3(0)), 0);
  fresh.checkHealth();
  ReachProbe blown(fresh);
  blown.measure(frame);
  EXPECT_TRUE(blown.latest().empty()) << "a blown-up cloth is not measured";
}

}  // namespace
}  // namespace drape
