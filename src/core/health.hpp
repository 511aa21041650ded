// The blow-up check every long run applies after each frame, for any solver: the viewer pauses on it,
// `drape simulate` exits 4 on it, bench marks a run with it. The CPU solvers scan their state with
// scanHealth; the GPU solver runs the same tests in a kernel after the frame's last pass
// (glsl/sim/health.comp) and reads back only the flags.
#pragma once

#include "core/scene.hpp"
#include "core/topology.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace drape {

// m: a coordinate beyond this, on any axis, is a runaway point (no scene comes near: the cloths are metres).
inline constexpr double kSaneBound = 1e5;
// A spring longer than (1 + this) times its rest length is a blow-up: the stretch limit holds springs
// near 10% (docs/design.md section 2); only a diverging run gets near 11 times the rest length.
inline constexpr double kBlowUpStrain = 10.0;

struct HealthLimits {
  double sane_bound = kSaneBound;
  double max_strain = kBlowUpStrain;
};

// What a health check found. The flag values are the GPU's (glsl/shared/layout.h, kHealth*).
struct Health {
  static constexpr unsigned kNonFinite = 1u;      // a position or displacement is NaN or infinite
  static constexpr unsigned kOutOfBounds = 2u;    // a coordinate beyond HealthLimits::sane_bound
  static constexpr unsigned kOverstretched = 4u;  // an enabled spring beyond (1 + max_strain) x rest
  unsigned flags = 0;
  long long first_point = -1;  // smallest index of a point that raised a flag (a spring raises both ends)
  long long substeps = -1;     // Solver::substeps() of the state checked (-1: not said)
  bool ok() const { return flags == 0; }
  std::string describe() const;  // empty while ok, else one line naming every flag and the point
  // Adds what another part of the same scan found (scanHealthPart): the answer of the scan in one piece.
  void merge(const Health& part);
};

// Non-finite x or v, |x| beyond the bound, enabled springs of `topo` stretched beyond the limit.
// Only the flags and the first point are kept, so that a CPU scan and the GPU kernel can be compared.
Health scanHealth(const Topology& topo, const ClothSpec& cloth, const std::vector<glm::dvec3>& x,
                  const std::vector<glm::dvec3>& v, const HealthLimits& limits = {});
// scanHealth's tests of points [p0, p1) and springs [s0, s1), for a caller that splits the scan (threads)
// and merges the parts. x and v in double or in float (each coordinate taken to double first, as a
// float solver's readPositions does).
template <class P>
Health scanHealthPart(const Topology& topo, const ClothSpec& cloth, const std::vector<P>& x, const std::vector<P>& v,
                      const HealthLimits& limits, std::size_t p0, std::size_t p1, std::size_t s0, std::size_t s1);

// A float state's quick look before that scan: where it says healthy, scanHealthPart over the same points and
// springs finds nothing (where it does not, the scan decides). Each enabled spring's squared length is taken in
// float against its squared limit less 2^-20 of it, which float rounding stays well inside: a cloth far from
// blowing up is passed in float, without a conversion to double a coordinate.
// The springs are kept as runs: consecutive springs whose ends step by one point, at one offset from a to b (a
// grid's springs of one direction along a row), read without an index a spring (the three index arrays were most
// of the look's memory traffic at 256 x 256). A run's limit is the least of its springs', which are within
// kRunSpread of each other (a vertical cloth's jitter spreads its rest lengths by a fraction of a percent).
struct QuickHealth {
  struct Run {
    std::uint32_t first, count;  // springs [first, first + count) of the topology, all enabled
    std::uint32_t a;             // spring first's end a; spring first + k joins a + k and a + k + step
    std::int32_t step;
    float limit2;
  };
  static constexpr double kRunSpread = 0x1p-5;
  std::vector<Run> runs;  // ascending by first
  float bound = 0;        // a float at most HealthLimits::sane_bound
  bool usable = false;    // false where a spring's limit is too small for the margin (it would underflow)
};
QuickHealth quickHealth(const Topology& topo, const ClothSpec& cloth, const HealthLimits& limits = {});
// A spring's limit in the quick look: a float |d|^2 at most this is within (1 + max_strain) x rest, its rounding
// either way inside the margin of 2^-20. Where most^2 is under 2^-60 (subnormal squares) the quick look is not usable.
float quickLimit2(double rest, const HealthLimits& limits);
bool quickHealthy(const QuickHealth& q, const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v,
                  std::size_t p0, std::size_t p1, std::size_t s0, std::size_t s1);

}  // namespace drape
