// CPU reference solver: the passes of DESIGN section 2, in that order, with the same Jacobi semantics
// as the GPU, templated on float (to compare with the GPU) and double (the accuracy reference).
#pragma once

#include "core/solver.hpp"
#include "cpu/hash_grid.hpp"
#include "cpu/physics.hpp"

#include <chrono>
#include <vector>

namespace drape {

// How Verlet keeps the previous position: the displacement v = x - x_prev (default, precise) or
// x_prev itself (CS184's form, kept to measure the round-off it costs).
enum class VerletForm { Displacement, PreviousPosition };

template <class T>
class CpuSolver final : public Solver {
 public:
  using vec3 = glm::vec<3, T>;

  explicit CpuSolver(Scene scene, VerletForm form = VerletForm::Displacement);

  std::string name() const override;
  const Scene& scene() const override { return scene_; }
  const Topology& topology() const override { return topo_; }

  // step() is this list of passes; each is public so tests can run and compare them one by one.
  void step() override;
  void accumulateForces();  // gravity + springs + wind -> forces_
  void integrate();         // Verlet, pinned points stay
  void selfCollide();       // hash grid, Jacobi, averaged, / steps_per_frame
  void collide();           // each sphere, then each plane
  void limitStretch();      // Provot, sim.stretch_passes Jacobi passes

  void reset() override;
  void setParams(const ClothSpec& cloth, const SimParams& sim) override;
  std::vector<glm::dvec3> readPositions() override;
  std::vector<glm::dvec3> readDisplacements() override;
  long long substeps() const override { return substeps_; }
  std::vector<std::string> passes() const override;
  std::vector<PassTiming> timings() const override;
  void resetTimings() override;

  // Direct state access for tests and tools.
  const std::vector<vec3>& positions() const { return x_; }
  const std::vector<vec3>& displacements() const { return v_; }
  const std::vector<vec3>& forces() const { return f_; }
  void setState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v);
  T mass() const { return mass_; }

 private:
  struct Stiffness {
    T k[kSpringTypeCount];
  };
  void refreshDerived();
  void applyCorrections();  // x += c, and v += c so that x_prev stays put
  vec3 pointNormal(int i) const;
  bool needsPass(int pass) const;
  template <class F>
  void timed(int pass, F&& f);

  Scene scene_;
  Topology topo_;
  VerletForm form_;
  std::vector<vec3> x_, v_, f_, correction_;
  std::vector<T> rest_;  // per adjacency entry, in T
  HashGrid<T> grid_;
  T mass_ = 0, dt_ = 0, keep_ = 1;
  Stiffness stiffness_{};
  long long substeps_ = 0;
  std::vector<PassTiming> timings_;
};

extern template class CpuSolver<float>;
extern template class CpuSolver<double>;

}  // namespace drape
