// libFuzzer target (clang only; `tools/test --fuzz` builds and runs it): arbitrary bytes through the scene
// loader, then a few substeps of the CPU float solver on whatever the loader accepts. Built with ASan and
// UBSan (no recovery), so a memory error, UB, an exception other than SceneError, or a broken loader
// promise (checked below) is a crash that libFuzzer reports with the input that caused it.
#include "core/scene.hpp"
#include "cpu/cpu_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

// Small enough that an input runs in about a millisecond; the fuzzed parameters are kept, only the grid
// and the per-substep pass counts are capped.
constexpr int kMaxSide = 12;
constexpr int kMaxStretchPasses = 4;
constexpr std::size_t kMaxColliders = 8;
constexpr int kSubsteps = 3;

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "scene_fuzzer: loader accepted a scene that breaks its contract: %s\n", what);
  std::abort();
}

// What parseScene promises about every scene it returns (scene.hpp, scenes/README.md).
void checkContract(const drape::Scene& s) {
  const drape::ClothSpec& c = s.cloth;
  check(c.width > 0 && std::isfinite(c.width) && c.height > 0 && std::isfinite(c.height), "width/height > 0");
  check(c.num_width_points >= 2 && c.num_height_points >= 2, "at least 2 x 2 points");
  check(static_cast<long long>(c.num_width_points) * c.num_height_points <= drape::kMaxClothPoints, "grid cap");
  check(c.thickness > 0 && std::isfinite(c.thickness), "thickness > 0");
  check(c.damping >= 0 && c.damping <= 100, "damping in [0, 100]");
  check(c.density > 0 && c.ks > 0, "density, ks > 0");
  for (const glm::ivec2& p : c.pinned)
    check(p.x >= 0 && p.x < c.num_width_points && p.y >= 0 && p.y < c.num_height_points, "pins inside the grid");
  for (const drape::SphereSpec& sphere : s.spheres)
    check(sphere.radius > 0 && sphere.friction >= 0 && sphere.friction <= 1, "sphere radius, friction");
  for (const drape::PlaneSpec& plane : s.planes)
    check(std::fabs(glm::length(plane.normal) - 1.0) < 1e-9, "plane normal is unit");
  check(s.sim.frames_per_sec > 0 && s.sim.steps_per_frame >= 1 && s.sim.stretch_passes >= 0, "sim counts");
  check(s.sim.stretch_limit >= 1.0, "stretch_limit >= 1");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  drape::Scene scene;
  try {
    scene = drape::parseScene(text, "fuzz.json");
  } catch (const drape::SceneError&) {
    return 0;  // rejected with its one-line message: what most inputs get
  }
  checkContract(scene);

  drape::ClothSpec& cloth = scene.cloth;
  cloth.num_width_points = std::min(cloth.num_width_points, kMaxSide);
  cloth.num_height_points = std::min(cloth.num_height_points, kMaxSide);
  std::erase_if(cloth.pinned,
                [&](const glm::ivec2& p) { return p.x >= cloth.num_width_points || p.y >= cloth.num_height_points; });
  if (scene.spheres.size() > kMaxColliders) scene.spheres.resize(kMaxColliders);
  if (scene.planes.size() > kMaxColliders) scene.planes.resize(kMaxColliders);
  scene.sim.stretch_passes = std::min(scene.sim.stretch_passes, kMaxStretchPasses);

  drape::CpuSolver<float> solver(scene);
  for (int i = 0; i < kSubsteps; ++i)
    solver.step();
  (void)solver.readPositions();
  return 0;
}
