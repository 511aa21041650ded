// Shared by the GPU solver's GL tests: standard scenes, CPU float states to start passes from, and
// deviations measured in float ulps of the values involved.
#pragma once

#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "cpu/cpu_solver.hpp"
#include "gl/context.hpp"
#include "gpu/gpu_options.hpp"
#include "test_paths.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace drape::gpu_test {

// The general path, the one these tests describe: GpuPath::Auto takes it on llvmpipe but the one-dispatch or
// tiled path on a GPU (gpu/path_choice.hpp), with other pass lists and buffers. The automatic choice has tests
// of its own (gpu_plan_test.cpp for both kinds of device, GpuSolverTest for the device at hand).
inline GpuSolverOptions general(GpuSolverOptions options = {}) {
  if (options.path == GpuPath::Auto) options.path = GpuPath::General;
  return options;
}

inline Scene standardScene(const std::string& file) {
  return loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + file);
}

// The nearest float coordinates, as a solver working in float stores them. Through a volatile:
// GCC 12.2 at -O2 (SLP vectorizer) compiles {double(float(a)), double(float(b))} to a plain copy of
// a and b, dropping the rounding; glm::dvec3(glm::vec3(p)) is hit the same way.
inline double asFloat(double v) {
  volatile float f = float(v);
  return double(f);
}
inline glm::dvec3 asFloat(const glm::dvec3& p) {
  return {asFloat(p.x), asFloat(p.y), asFloat(p.z)};
}

// Whether the GPU must reproduce CpuSolver<float> bit for bit. Mesa's llvmpipe does: it compiles GLSL
// for the same CPU, rounds every operation to nearest like the C++ code, and `precise` (glsl/sim)
// keeps it from fusing or reassociating, so every pass and every run measures a difference of 0 and
// the tests ask for exactly that. Other drivers may divide and take square roots within GLSL's
// looser bounds (2.5 ulp for a/b): there the ulp bounds of each test apply.
inline bool bitIdenticalDevice(const gl::ContextInfo& info) {
  return info.renderer.find("llvmpipe") != std::string::npos;
}

// Spacing between adjacent float values at magnitude m.
inline double floatUlp(double m) {
  const float f = float(std::abs(m));
  return double(std::nextafter(f, std::numeric_limits<float>::infinity()) - f);
}

inline double maxAbs(const std::vector<glm::dvec3>& a) {
  double m = 0;
  for (const glm::dvec3& p : a)
    m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return m;
}

// Largest per-component difference.
inline double maxComponentDifference(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const glm::dvec3 d = glm::abs(a[i] - b[i]);
    m = std::max({m, d.x, d.y, d.z});
  }
  return m;
}

// Number of points whose value differs between two states (did a pass do anything?).
inline int changedPoints(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  int n = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    n += a[i] != b[i];
  return n;
}

// Whether the GPU must reproduce CpuSolver<float> bit for bit (above), unless DRAPE_TEST_AS_GPU=1 asks the
// tests to take llvmpipe for a device that is not: that runs the bounds below (the rounding twins) here too.
inline bool exactDevice(const gl::ContextInfo& info) {
  const char* as_gpu = std::getenv("DRAPE_TEST_AS_GPU");
  return bitIdenticalDevice(info) && !(as_gpu && std::string(as_gpu) == "1");
}

// Every free coordinate of `x` moved by one ulp up, one down or left, by a hash of (point, coordinate, seed).
inline std::vector<glm::dvec3> nudgedByUlps(const std::vector<glm::dvec3>& x, const Topology& topo,
                                            std::uint32_t seed) {
  std::vector<glm::dvec3> out = x;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (topo.pinned[i]) continue;
    for (int c = 0; c < 3; ++c) {
      std::uint32_t h = std::uint32_t(i) * 2654435761u ^ std::uint32_t(c) * 40503u ^ seed * 2246822519u;
      h ^= h >> 13;
      h *= 0x5bd1e995u;
      h ^= h >> 15;
      if ((h & 3u) == 0u) continue;
      const float f = float(x[i][c]);
      out[i][c] = double(std::nextafter(
          f, (h & 1u) ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity()));
    }
  }
  return out;
}

// On a device that is not bit-identical, how far rounding alone carries a run. A GPU's passes round a few
// operations differently (GLSL allows 2.5 ulps for a/b; each pass stays within 4 ulps of the CPU's,
// tests/gpu_passes_gl_test.cpp), and contact makes the motion discontinuous in the state: a point one ulp
// inside a sphere is moved by the friction and one ulp outside is not (CS184's model), a tether switched on
// snaps a stretched cloth. Measured on the CPU float solver (pinned4 at 5000 N/m, tethers switched on after 15
// frames, every coordinate nudged by an ulp once a frame): 1e-6 m apart before the switch, 5.2 mm one frame
// after; sphere.json 8.7e-7 m before the cloth lands, 12 mm ten frames after. The twin is that run: the
// CPU float solver with every free coordinate nudged by up to an ulp after each substep. A GPU run may part
// from the CPU run kTwinFactor times as far as the twin does (its rounding differs in every pass, the
// twin's once a substep), and always by the per-substep ulp bound the test had before.
constexpr double kTwinFactor = 4.0;

class RoundingTwin {
 public:
  explicit RoundingTwin(const Scene& scene) : twin_(scene) {}
  void setParams(const ClothSpec& cloth, const SimParams& sim) { twin_.setParams(cloth, sim); }
  void stepFrame() {
    for (int s = 0; s < twin_.scene().sim.steps_per_frame; ++s) {
      twin_.step();
      twin_.setState(nudgedByUlps(twin_.readPositions(), twin_.topology(), ++substeps_), twin_.readDisplacements());
    }
  }
  // The bound for a GPU run against `cpu` (the un-nudged run, at the same frame), relative to `size`.
  double bound(const std::vector<glm::dvec3>& cpu, double size, double ulp_bound) {
    return std::max(ulp_bound, kTwinFactor * maxDeviation(twin_.readPositions(), cpu) / size);
  }

 private:
  CpuSolver<float> twin_;
  std::uint32_t substeps_ = 0;
};

// One substep's sensitivity to rounding: how far `step` (a whole substep, or passes) carries the CPU from
// `x, v` nudged by an ulp, over `seeds` nudges, at most. Where the substep has a contact decision to flip, this
// is what a GPU's last-bit differences may become by its end.
template <class Step>
double substepSensitivity(const CpuSolver<float>& cpu, const std::vector<glm::dvec3>& x,
                          const std::vector<glm::dvec3>& v, Step step, int seeds = 4) {
  CpuSolver<float> plain = cpu;
  plain.setState(x, v);
  step(plain);
  const std::vector<glm::dvec3> reference = plain.readPositions();
  double most = 0;
  for (int k = 1; k <= seeds; ++k) {
    CpuSolver<float> nudged = cpu;
    nudged.setState(nudgedByUlps(x, cpu.topology(), std::uint32_t(k)), v);
    step(nudged);
    most = std::max(most, maxComponentDifference(nudged.readPositions(), reference));
  }
  return most;
}

// Steps `cpu` substep by substep, at most three frames, until the collision pass of the next substep has
// work after `before_collide` (the passes before it, run on a copy): a falling cloth crosses a floor within
// one substep only now and then, and a pass compared where it does nothing proves nothing.
template <class BeforeCollide>
void stepUntilCollisionsHaveWork(CpuSolver<float>& cpu, BeforeCollide before_collide) {
  const Scene& scene = cpu.scene();
  if (scene.spheres.empty() && scene.planes.empty() && scene.meshes.empty()) return;
  for (int s = 0; s < 3 * scene.sim.steps_per_frame; ++s) {
    CpuSolver<float> probe = cpu;
    before_collide(probe);
    const std::vector<glm::dvec3> before = probe.readPositions();
    probe.collide();
    if (changedPoints(before, probe.readPositions()) > 0) return;
    cpu.step();
  }
}

}  // namespace drape::gpu_test
