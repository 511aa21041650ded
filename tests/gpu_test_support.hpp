// Shared by the GPU solver's GL tests: standard scenes, CPU float states to start passes from, and
// deviations measured in float ulps of the values involved.
#pragma once

#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "cpu/cpu_solver.hpp"
#include "gl/context.hpp"
#include "test_paths.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace drape::gpu_test {

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
