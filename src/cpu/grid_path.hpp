// The float solver's grid path: forces, the Gauss-Seidel stretch limit and XPBD's and VBD's sweeps of a grid cloth with
// the grid kernels (cpu/grid_kernels.hpp), the positions and displacements copied into a padded structure of arrays for
// the pass and back after it, or kept there from integrate to the next substep (CpuSolver::gridIntegrates). The bytes
// are the general path's (tests/grid_path_test.cpp); the mesh path and double keep the gathers over the adjacency and
// the colouring.
#pragma once

#include "core/scene.hpp"
#include "core/topology.hpp"
#include "cpu/aligned.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/parallel.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <utility>
#include <vector>

namespace drape {

class GridPath {
 public:
  // A grid cloth's topology (Topology::W > 0); rest lengths per spring, as the solver rounds them.
  GridPath(const Topology& topo, const std::vector<float>& rest, GridIsa isa);

  const GridKernels& kernels() const { return *kernels_; }
  void setMasses(const std::vector<float>& mass, const std::vector<float>& inv_mass);

  // Called by every thread of a team (or by one thread alone): each splits the rows and ends with a barrier.
  // enabled[t] and k[t] per spring type.
  // wait: false where the next pass reads only the forces of its own thread's rows (no barrier after them).
  // loaded: the padded arrays already hold x (the stretch limit's copy back was the last to move it), so it is not
  // copied in again.
  void forces(const std::vector<glm::vec3>& x, std::vector<glm::vec3>& f, glm::vec3 gravity, const float k[3],
              const bool enabled[3], bool wait = true, bool loaded = false);
  // Verlet in displacement form (GridKernels::integrateRows) on the padded arrays, which must hold x and v (the
  // substep before left them there): the new x and v written there, and the new x to *x_out where given (the solver's
  // x, which self-collision reads), each thread its own rows, no barrier after. The solver's v is not written: it is
  // behind the arrays until storePositions.
  void integrate(std::vector<glm::vec3>* x_out, const std::vector<glm::vec3>& f, float dt2, float keep);
  // Point i (in point order) moved by c in the padded arrays, its displacement with it: CpuSolver::displace in
  // displacement form, between integrate and the stretch limit's copy back.
  void displace(std::size_t i, glm::vec3 c) {
    const std::size_t k = padded_[i];
    x_[k] += c.x;
    y_[k] += c.y;
    z_[k] += c.z;
    vx_[k] += c.x;
    vy_[k] += c.y;
    vz_[k] += c.z;
  }
  // The padded arrays back into x and v, by one thread outside a team (CpuSolver::syncPositions).
  void storePositions(std::vector<glm::vec3>& x, std::vector<glm::vec3>& v) { copyOut(x, &v, false); }
  // x and v into the padded arrays, by one thread outside a team (a test's state)
  void loadState(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v) { copyIn(x, &v, false); }
  // The health check's quick look (GridKernels::healthyRows) on the padded arrays, which must hold x and v: the
  // springs' limits per direction from the cloth's enabled types (setHealthLimits, again where they change), the
  // coordinates' bound QuickHealth's.
  void setHealthLimits(const Topology& topo, const ClothSpec& cloth);
  bool healthy(float bound) const;
  // forces() on the padded arrays, which hold x and v (as for integrate), and integrate in the same sweep: each row
  // once no later row's forces read it, a thread's first and last two rows (which another thread's forces read)
  // after a barrier. No barrier after.
  void forcesAndIntegrate(std::vector<glm::vec3>* x_out, std::vector<glm::vec3>& f, glm::vec3 gravity, const float k[3],
                          const bool enabled[3], float dt2, float keep);
  // The positions x into the padded arrays, where self-collision's check and stencil read them (positions()).
  // Called by every thread of a team, or by one thread alone.
  void loadPositions(const std::vector<glm::vec3>& x);
  const GridShape& shape() const { return shape_; }
  const float* positions(int coordinate) const {
    return coordinate == 0 ? x_.data() : coordinate == 1 ? y_.data() : z_.data();
  }
  // Self-collision's stencil over the positions last loaded (loadPositions), from the points of rows [y0, y1):
  // the pairs in range and not held at rest, appended to lower and upper (GridKernels::stencilPairs; the vectors
  // only grown), their count returned. du, dv, mixed: the whole stencil, sorted by dv * W + du (its second half
  // mirrors its first). A thread of a team calls it for its own rows and writes nothing another thread reads
  // before the next barrier. tiles: where given, [y0, y1) is whole rows of squares (y1 may be the last row) and the
  // tests the list's last build rules out are passed over (GridStencilTiles).
  std::size_t stencilPairs(const int* du, const int* dv, const std::uint8_t* mixed, int count, float range2, int y0,
                           int y1, std::vector<std::uint32_t>& lower, std::vector<std::uint32_t>& upper,
                           const GridStencilTiles* tiles = nullptr);
  // `passes` Gauss-Seidel passes over the 12 colours in order; v nullptr when it is not a displacement. wait:
  // false where the next pass reads only its own thread's rows of x and v (no barrier after they are copied out).
  // copy_out false: the positions stay in the padded arrays for collideAndCopyOut. loaded: the arrays hold x and v
  // already (integrate), so they are not copied in.
  void limitStretch(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, float limit, int passes,
                    const bool enabled[3], bool wait = true, bool copy_out = true, bool loaded = false);
  // After limitStretch(..., copy_out = false): the spheres' and planes' collisions of every point on the padded
  // arrays (collideRows), then x and v back; each thread its own rows, no barrier between.
  void collideAndCopyOut(std::vector<glm::vec3>& x, std::vector<glm::vec3>& v, const CollideArgs& objects,
                         bool wait = true);
  // The same collisions on the padded arrays where they hold the points (after integrate), each thread its own
  // rows, no barrier after, nothing copied back.
  void collide(const CollideArgs& objects);
  // A team's rows of the colours (thread t: [rows[t], rows[t + 1])) on a cloth of kParallelItems points or more,
  // moved towards equal times after each sweep (smaller cloths: the even split); fixColourRows sets them and keeps
  // them, at any size (a test's uneven split).
  const std::vector<long long>& colourRows() const { return colour_rows_; }
  void fixColourRows(std::vector<long long> rows) {
    colour_rows_ = std::move(rows);
    colour_seconds_.assign(colour_rows_.size() - 1, 0);
    colour_per_row_.assign(colour_rows_.size() - 1, -1);
    colour_rows_fixed_ = true;
  }
  // XPBD's `sweeps` sweeps over the colours in order, with the compliances over dt^2 per spring type; the
  // multipliers start at 0 (one sweep never reads them).
  void xpbd(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, const float alpha_tilde[3], const bool enabled[3],
            int sweeps);
  // VBD's `sweeps` sweeps over the point colours in order (each colour's points ascending; no two share a
  // spring): each free point's Newton step, with the stiffnesses per spring type; the first sweep keeps the
  // prediction for the later ones.
  // The colours' points (PointColouring::points), each one's padded index, column and row worked out once:
  // two divisions a lane each sweep were a fifth of the kernel's time. Before vbd().
  void setVbdPoints(const std::vector<std::uint32_t>& points);
  void vbd(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, const float k[3], const bool enabled[3], float dt2,
           int sweeps, const std::vector<std::uint32_t>& colour_start);

 private:
  static constexpr int kStencilRows = 4;  // stencilPairs' rows a kernel call, without the squares
  static constexpr int kBand = 2;         // the most rows a spring ends below its start (kGridDirections' dy)
  using ColourKernel = void (*)(const GridStretchArgs&, int, int, int, int);
  GridSprings springs(const float k[3], const bool enabled[3]) const;
  GridForceArgs forceArgs(std::vector<glm::vec3>& f, glm::vec3 gravity, const float k[3], const bool enabled[3]) const;
  GridIntegrateArgs integrateArgs(std::vector<glm::vec3>* x_out, const std::vector<glm::vec3>& f, float dt2,
                                  float keep);
  GridStretchArgs colourArgs(bool displacements, const GridSprings& springs);
  // x (and v, where not nullptr) into the padded arrays and back, each thread its rows; every thread of a team calls
  // them. wait: a barrier after (false where the next step reads only its own thread's rows).
  void copyIn(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>* v, bool wait = true);
  void copyOut(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, bool wait = true);
  bool followsColourTimes() const;
  bool colourRows(bool follow, long long& y0, long long& y1);
  bool colourBands(bool follow) const;
  // x (and v) into the padded arrays, `passes` sweeps of `colour` over the colours in order, and back.
  void sweepColours(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, const GridStretchArgs& args, int passes,
                    ColourKernel colour, bool wait = true, bool copy_out = true, bool loaded = false);

  GridShape shape_;
  const GridKernels* kernels_;
  PaddedFloats x_, y_, z_, vx_, vy_, vz_, pinned_, mass_, inv_mass_;
  PaddedFloats rx_, ry_, rz_;  // rest positions, as the float solver rounds them
  PaddedFloats rest_[6];       // per direction, at each spring's start a
  PaddedFloats limit2_[6];     // per direction, at each spring's start: its quickLimit2 (empty: the type is off)
  PaddedFloats tx_, ty_, tz_;  // VBD of several sweeps: each point's prediction
  // VBD: the colours' points' padded indices, columns and rows (setVbdPoints)
  std::vector<std::int32_t> vbd_padded_;
  std::vector<float> vbd_column_, vbd_row_;
  PaddedFloats lambda_[6];                 // XPBD of several sweeps: per direction, each spring's multiplier
  std::vector<std::uint8_t> signed_rows_;  // per row, whether copyIn saw a -0 (GridStretchArgs::signed_rows)
  std::vector<std::uint32_t> padded_;      // per point, its index in the padded arrays (displace)
  // The colours' rows of each thread of a team (sweepColours), its seconds for them at the last sweep and its
  // seconds a row smoothed over sweeps (balanceShares)
  std::vector<long long> colour_rows_;
  std::vector<double> colour_seconds_, colour_per_row_;
  bool colour_rows_fixed_ = false;
  // Each thread's count of the colours whose rows next to its neighbours' it has done (colourBands)
  TeamProgress colour_progress_;
};

}  // namespace drape
