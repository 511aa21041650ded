// Self-collision candidates kept across substeps: a neighbour list with a skin (Verlet 1967). Every
// pair closer than range + margin when the list is built is listed; the list stays valid while the
// points' displacements since the build all fit in a box whose diagonal is under the margin (needsBuild()),
// because no pair then approaches by the margin and every pair within range is still listed. Points move
// ~1 mm a substep at CS184's speeds, mostly together, so a list of a few millimetres of skin serves
// several substeps instead of rebuilding the hash grid and reading 27 cells every substep.
//
// On a grid cloth the pairs just beyond the contact distance at rest are a ring around every point, at the
// same grid offsets everywhere (the stencil): about 40 a point at 256 x 256 with CS184's thickness, which a
// list would hold however it was built, because nothing but the cloth's compression brings them in. They
// are not listed but tested every substep by offset (cheap: no lookups, and rows of points side by side),
// and the list holds the rest; a list build passes over them and the held pairs by their offset, without
// reading their positions.
//
// The sum of a point's corrections must not depend on when the list was rebuilt, or on the GPU on
// thread timing: its terms are added in the order a 27-cell query of a grid of cell size `range` visits
// them (cells in z, y, x order around the point's cell, ascending index within a cell), so the result is
// the same whatever list it comes from. forEachOrderedPair yields them so (the tests' reference); the CPU
// solver finds each pair once and sorts each point's terms into that order (CpuSolver::sumPairTerms).
#pragma once

#include "cpu/aligned.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/hash_grid.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <exception>
#include <limits>
#include <utility>
#include <vector>

namespace drape {

// Per point, the stencil offsets whose partners are in range (CollisionPairs::stencilBit)
using StencilMask = std::uint64_t;

template <class T>
class CollisionPairs {
 public:
  using vec3 = glm::vec<3, T>;

  // range = 2 * thickness; margin >= 0 (0 rebuilds every substep).
  void configure(T range, T margin);
  // The cloth's rest positions: a pair closer than `range` there is held by the springs
  // (physics::heldAtRest) and never listed. Empty (the default): every pair is a candidate.
  void setRest(std::vector<vec3> rest);
  void invalidate() { built_ = false; }

  // The largest box of grid offsets a stencil is made for (a cloth whose contact distance spans more
  // points than this gets none: its pairs are all listed).
  static constexpr int kMaxStencilBox = 40;
  // A grid cloth of w x h points (point (u, v) is index v * w + u), after setRest: the grid offsets whose pairs
  // may lie within range + margin at rest and are not all held form the stencil (makeStencil), tested every
  // substep and never listed.
  void setGrid(int w, int h);
  // Float: the instruction set's scanPairs for builds (default: one candidate at a time). The same lists.
  void setKernels(const GridKernels* kernels) {
    kernels_ = kernels;
    grid_.setKernels(kernels);
  }
  // How a build on dense buckets goes through the points (findPairs): by cell (the default) or point by point,
  // which hashed buckets always do; the same lists (tests compare them).
  enum class BuildOrder { ByCell, ByPoint };
  void setBuildOrder(BuildOrder order) { build_order_ = order; }
  // Float grid with the kernels: the positions as they are now in a grid path's padded arrays (GridPath), for the
  // checks and builds until the next call; nullptr: not given (the vec3s are read). The check then reads them
  // and the anchors' copy in that layout made at the last build that had them. The same answers.
  void setPaddedPositions(const GridShape* shape, const float* x, const float* y, const float* z) {
    padded_ = shape ? Padded{*shape, x, y, z} : Padded{};
  }

  // Makes the list valid for positions x (rebuilding if any point moved too far); returns whether it
  // rebuilt. threads: OpenMP threads for the per-point loops. Outside a team.
  bool update(const std::vector<vec3>& x, int threads);
  // update() in two steps, for a team (cpu/parallel.hpp): whether the lists must be rebuilt for x, then the
  // build; every thread of the team calls both and shares their work. Outside a team build() forks its own
  // threads for long loops and throws what fails; in a team it keeps it for takeFailure().
  bool needsBuild(const std::vector<vec3>& x);
  // needsBuild in two steps, for a team that has a serial step of its own to share: startCheck on one thread
  // (it allocates, and may throw), then finishCheck on every thread, which returns needsBuild's answer.
  // stamp: the substep's number, where the check may first test the box of every displacement (the GPU's test, one
  // reduction), whose diagonal within the margin rules out every two tiles' (CS184's 50 x 50 files: 68-100% of the
  // checks): in a team whose check is split, from the parts each thread boxed (boxDisplacements) before it.
  void startCheck(const std::vector<vec3>& x, long long stamp = -1);
  bool finishCheck(const std::vector<vec3>& x);
  // Part `part` of that box: the displacements of rows [y0, y1) of a float grid's padded positions, for the check of
  // substep `stamp`; in a team, each thread its own rows before the barrier after startCheck. Nothing where the last
  // build kept no padded anchors.
  void boxDisplacements(int part, long long stamp, const GridShape& shape, const float* x, const float* y,
                        const float* z, int y0, int y1);
  static constexpr int kDisplacementParts = 64;  // a larger team skips the box
  void build(const std::vector<vec3>& x, int threads);
  bool splitCheck() const;  // whether finishCheck splits the check between a team's threads
  // What a build in a team failed with (out of memory), once the team is done with it; cleared by taking it.
  std::exception_ptr takeFailure() { return std::exchange(failure_, nullptr); }

  // Listed candidates of point i, ascending: every j off the stencil with |x_i - x_j| < range + margin at the
  // last build. Made from the entries at the first call after a build (the solver needs only those):
  // for tests and diagnostics, not to be called from two threads at once.
  const std::uint32_t* begin(std::size_t i) const { return bothEnds().list.data() + bothEnds().start[i]; }
  const std::uint32_t* end(std::size_t i) const { return bothEnds().list.data() + bothEnds().start[i + 1]; }
  std::size_t pairCount() const {  // each pair counted from both ends
    return near_.start.empty() ? 0 : 2 * std::size_t(near_.start.back() + far_.start.back());
  }
  // The same pairs from their lower end only, every listed j > i of point i in no particular order (for a sum that
  // visits each pair once and sorts its terms itself), in two parts laid out alike: those closer at the build than
  // the range and half the skin (near), and the rest (far), which no pair in range can be among until two points have
  // moved apart or together by half the skin since the build: for most of a list's life only the near part is tested
  // (farNeeded).
  struct EntryPart {
    // start: n + 1 offsets by owner (point i's entries are [start[i], start[i + 1])); entry k pairs owner[k] with
    // partner[k]; owner and partner hold at least start[n] entries
    std::vector<std::uint32_t> start, owner, partner;
  };
  const EntryPart& nearEntries() const { return near_; }
  const EntryPart& farEntries() const { return far_; }
  // Whether a far entry can be in range now: the points may have moved apart or together since the build by the
  // diagonal of the box around every displacement (the check's tiles), which with round-off reaches half the
  // skin. just_built: the lists were built this substep. Valid after finishCheck, until the points move again.
  bool farNeeded(bool just_built) const;

  // The stencil, for the last update's range and margin: grid offsets (du, dv) in ascending dv * w + du, so
  // that a point's partners ascend; empty off a grid.
  struct Offset {
    int du, dv;
    std::int64_t step;  // dv * w + du: the partner's index less the point's
  };
  const std::vector<Offset>& stencil() const { return stencil_; }
  const int* stencilDu() const { return du_.data(); }  // the stencil's du and dv as arrays, for the kernels
  const int* stencilDv() const { return dv_.data(); }
  // Per stencil offset, 1 where some of its pairs are held at rest (a vertical cloth's jitter): its pairs are
  // tested for that first.
  const std::uint8_t* stencilMixed() const { return mixed_.data(); }
  int gridWidth() const { return w_; }
  int gridHeight() const { return h_; }
  // Which of point i's stencil partners are within `range` and not held (a NaN distance counts): bit
  // stencilBit(k) for offset k (a float grid path lists the pairs instead: GridKernels::stencilPairs). A partner
  // whose bit is clear adds no term to the point's sum.
  StencilMask stencilMask(const std::vector<vec3>& x, std::size_t i) const;
  // Offset k's bit in a stencil mask; every offset from 63 on shares the last (the set is looked at whole).
  // 64 bits: at 256 x 256 with CS184's thickness the stencil has 40 offsets, and a shared bit sent nine
  // partners to be tested where one was in range.
  static StencilMask stencilBit(int k) { return StencilMask(1) << (k < 63 ? k : 63); }

  // Calls g(j) for every candidate of point i, ascending: its list and its stencil partners, merged; of the
  // stencil, only the offsets whose bits `mask` has (stencilMask), as the others add no term.
  template <class G>
  void forEachCandidate(std::size_t i, StencilMask mask, G&& g) const {
    const std::uint32_t *a = begin(i), *e = end(i);
    if (!stencil_.empty() && mask != 0) {
      const int u = int(i % std::size_t(w_)), v = int(i / std::size_t(w_));
      // The set bits in ascending order are the offsets in ascending step: the merge stays ascending.
      for (StencilMask m = mask; m != 0; m &= m - 1) {
        const std::size_t bit = std::size_t(std::countr_zero(m));
        const std::size_t last = std::min(bit < 63 ? bit + 1 : stencil_.size(), stencil_.size());
        for (std::size_t k = bit; k < last; ++k) {
          const Offset& o = stencil_[k];
          if (!onGrid(u + o.du, v + o.dv)) continue;
          const auto j = std::uint32_t(std::int64_t(i) + o.step);
          for (; a != e && *a < j; ++a)
            g(*a);
          if (!mixed_[k] || !physics::heldAtRest(rest_[i], rest_[j], range_)) g(j);
        }
      }
    }
    for (; a != e; ++a)
      g(*a);
  }
  // Calls g(j) for point i's stencil partners j > i whose bits `mask` has (stencilMask) and that the springs
  // do not hold, in no particular order: each stencil pair once, from its lower end.
  template <class G>
  void forEachForwardPartner(std::size_t i, StencilMask mask, G&& g) const {
    const int u = int(i % std::size_t(w_)), v = int(i / std::size_t(w_));
    // The set bits of the forward offsets only: the last bit stands for every offset from 63 on.
    for (StencilMask m = mask & forward_bits_; m != 0; m &= m - 1) {
      const std::size_t bit = std::size_t(std::countr_zero(m));
      const std::size_t first = std::max(bit, stencil_.size() / 2), last = bit < 63 ? bit + 1 : stencil_.size();
      for (std::size_t k = first; k < last; ++k) {
        const Offset& o = stencil_[k];
        if (!onGrid(u + o.du, v + o.dv)) continue;
        const auto j = std::uint32_t(std::int64_t(i) + o.step);
        if (!mixed_[k] || !physics::heldAtRest(rest_[i], rest_[j], range_)) g(j);
      }
    }
  }
  template <class G>
  void forEachCandidate(std::size_t i, G&& g) const {
    forEachCandidate(i, ~StencilMask(0), g);
  }
  // The stencil's squares for GridPath::stencilPairs, on a float grid whose check boxes them (GridStencilTiles): at
  // a build's substep (just_built) every pair is tested and the least distance of each square's pairs at each offset
  // recorded; at the substeps after it, a square's pairs at an offset are passed over where that least distance
  // exceeds the range by more than its points can have moved against their partners since (the boxes of the
  // squares around it, as this substep's check made them), with room for round-off: those pairs are out of range,
  // and the pairs found are the same. False where they do not apply (no squares, no record since the build). Every
  // thread of a team calls it.
  bool stencilTiles(bool just_built, GridStencilTiles& out);
  // After a record split between a team's threads, thread `from`'s first row of squares (its first row of points y0
  // not a square's first) merged into the record, by the thread before it once the team has passed a barrier. Each
  // thread's rows must then span a square's edge, so that only two threads meet in a row of squares.
  void mergeSharedRecord(int from, long long y0);
  void setStencilSquares(bool on) { squares_ = on; }
  // Whether the stencil's pairs may be passed over by its squares (stencilTiles), which read this substep's tile
  // boxes
  bool stencilReadsCheck() const { return squares_ && forwardOffsets() >= kSquaresMinOffsets; }
  // From this many forward offsets the squares pay. A vector of points whose squares pass over some of its offsets
  // and not others runs a loop of as many tests as its mask has bits, and its end is mispredicted: on CS184's
  // 50 x 50 files (2 to 4 forward offsets, half of them passed over) that cost more than the tests passed over
  // (pinned2 and selfCollision 4% slower on one thread, with as many instructions); pinned2 at 256^2 has 20.
  static constexpr std::size_t kSquaresMinOffsets = 8;
  // Whether the last substep's stencil passed over what its squares ruled out, and the share of the squares' offsets
  // it passed over (0 where it did not)
  bool squaresUsed() const { return squares_used_; }
  double squaresRuledOut() const;
  // The forward offsets (bit k: the stencil's offset half + k) square t's points tested at the last substep that did
  // not build, by the first thread of a team (all of them on one thread)
  std::uint64_t squareOffsetsTested(std::size_t t) const { return t < stencil_active_.size() ? stencil_active_[t] : 0; }
  long long rebuilds() const { return rebuilds_; }
  // The checks whose tiles' boxes called for a build that a closer look (tilesHold) spared
  long long closerLooksKept() const { return kept_ + (looked_.set && !moved_.set ? 1 : 0); }
  // The checks the box of every displacement cleared alone (startCheck), its tiles not boxed
  long long checksClearedWhole() const { return cleared_whole_; }
  long long entriesBuilt() const { return entries_built_; }  // pairCount summed over the builds
  T range() const { return range_; }
  T margin() const { return margin_; }

  // Largest distance any point may move from its build position before the list is rebuilt: half the
  // margin, less a few ulps of the largest coordinate so that round-off in the distances cannot
  // break the triangle inequality the proof uses.
  static T safeTravel(T margin, T extent);

 private:
  void boxTiles(const std::vector<vec3>& x, bool split);  // needsBuild's two steps: a team may split each
  void compareTiles(const std::vector<vec3>& x, bool split);
  // A grid's `count` pairs of tiles (found: a, c, each pair's two; a == c for a tile alone) that compareTiles' boxes
  // did not clear, cleared by smaller boxes: squares of about edge_ / kSubSquares points, then the points of two
  // squares that are not clear
  bool tilesHold(const std::vector<vec3>& x, const std::uint32_t* found, int count, T limit, T apart) const;
  static constexpr int kSubSquares = 4;
  // At most kLookedAt pairs, while the tiles they name hold at most 1/kLookShare of the points (or are two): of at
  // most 16 x 16 tiles, kLookedTiles
  static constexpr int kLookedAt = 64, kLookShare = 8;
  static constexpr std::size_t kLookedTiles = std::max(2, kMaxCompareTiles / kLookShare);
  struct alignas(64) LookedAt {  // compareTiles' pairs of tiles (a, c) to look at closely, on lines of their own
    std::array<std::uint32_t, 2 * kLookedAt> pairs;
    int count = 0;
  };
  std::vector<LookedAt> looked_at_;  // per thread of a team
  void makeTiles(std::size_t n);
  // A grid's squares of tiles (edge_ > 0): how many across and down
  int tilesAcross() const { return (w_ + edge_ - 1) / edge_; }
  int tilesDown() const { return (h_ + edge_ - 1) / edge_; }
  // The stencil's forward offsets (its second half), each pair's from its lower point
  std::size_t forwardOffsets() const { return stencil_.size() - stencil_.size() / 2; }
  // A row of squares' record (stencilTiles): a least distance per square and forward offset
  std::ptrdiff_t recordRow() const { return std::ptrdiff_t(tilesAcross()) * std::ptrdiff_t(forwardOffsets()); }
  // The row of squares a thread whose rows start at y0 shares with the thread before it (y0 not a square's first
  // row), or -1
  int sharedRow(long long y0) const { return edge_ > 0 && y0 % edge_ != 0 ? int(y0 / edge_) : -1; }
  void makeStencil();
  struct ScanArgs {  // GridKernels' PairScanArgs in T
    const T *x = nullptr, *y = nullptr, *z = nullptr, *u = nullptr, *v = nullptr;
    T px = 0, py = 0, pz = 0, pu = 0, pv = 0, reach2 = 0, a2 = 0, b2 = 0, near_below = 0, near2 = 0;
  };
  int scanSlots(const ScanArgs& a, std::uint32_t first, std::uint32_t last, std::uint32_t* out) const;
  bool onGrid(int u, int v) const { return u >= 0 && u < w_ && v >= 0 && v < h_; }
  // What a build does with pair {i, j} by its grid offset: kList (test it), or pass over it, held at rest or on
  // the stencil. Off the box of offsets the table covers, kList.
  enum OffsetKind : std::uint8_t { kList, kHeld, kStencil };

  // A pair as the build found it: its lower end, and its upper end with kFarBit set where it is a far entry
  using Pair = FiledPair;
  static constexpr std::uint32_t kFarBit = kFarSlot;  // as scanCell marks a far candidate's slot
  HashGrid<T> grid_;
  // The pairs thread t found whose lower ends are in the points [assemble_bounds_[d], assemble_bounds_[d + 1]), which
  // assembleLists' share d places: found_[t * assemblers() + d]. Kept to spare the allocations; on lines of their
  // own, as every pair found moves its vector's end.
  using Found = Lined<std::vector<Pair>>;
  std::vector<Found> found_;
  std::vector<std::uint32_t> assemble_bounds_;  // a share's bounds, from 0 to the point count: a team's size + 1
  std::size_t assemblers() const { return assemble_bounds_.size() - 1; }
  // In a team, thread t searches from the points (or the grid's slots) [search_bounds_[t], search_bounds_[t + 1]):
  // contiguous shares moved towards equal times (balanceShares) by search_seconds_, the last build's seconds, and
  // search_per_point_, each thread's seconds a point smoothed over builds
  std::vector<long long> search_bounds_;
  std::vector<double> search_seconds_, search_per_point_;
  struct BothEnds {
    bool made = false;
    std::vector<std::uint32_t> start, list;
  };
  const BothEnds& bothEnds() const;
  mutable BothEnds both_ends_;
  std::vector<std::uint32_t> fill_;  // assembleLists' next near entry of each point, then its next far one
  EntryPart near_, far_;
  T near_reach_ = 0;          // the near entries' reach at the build: range + margin / 2
  T extent_ = 0;              // the largest coordinate at the build, and the margin
  std::vector<vec3> anchor_;  // positions at the last build
  struct Padded {
    GridShape shape{};
    const float *x = nullptr, *y = nullptr, *z = nullptr;
  };
  Padded padded_;                          // setPaddedPositions
  PaddedFloats padded_anchor_[3];          // anchor_ in padded_'s layout, where the last build had it (else empty)
  std::vector<T> part_extent_;             // finishBuild's largest coordinate, per thread of the team
  std::vector<std::uint32_t> part_pairs_;  // assembleLists' near entries per thread of the team, then its far ones
  // needsBuild()'s tiles, as runs of consecutive points, and per tile the box of its displacements since the build
  // and the box of its points
  static constexpr int kTileEdge = 8, kTilesAcross = 16;
  static_assert(kTilesAcross * kTilesAcross <= kMaxCompareTiles);
  struct Run {
    std::uint32_t begin, end, tile;  // points [begin, end) of one tile
  };
  std::vector<Run> runs_;
  std::size_t tiled_ = std::size_t(-1);  // the point count runs_ was made for
  int edge_ = 0;                         // a grid's tiles: squares of edge_ points (0: runs of the index)
  std::size_t tile_count_ = 0;
  struct TileBox {
    vec3 dlo, dhi, lo, hi;  // the box of the displacements since the anchors, and the box of the positions
    static TileBox empty() {
      constexpr T kInf = std::numeric_limits<T>::infinity();
      return {vec3(kInf), vec3(-kInf), vec3(kInf), vec3(-kInf)};
    }
    void add(vec3 p, vec3 d) { add(TileBox{d, d, p, p}); }
    void add(const TileBox& o) {
      dlo = glm::min(dlo, o.dlo);
      dhi = glm::max(dhi, o.dhi);
      lo = glm::min(lo, o.lo);
      hi = glm::max(hi, o.hi);
    }
    // compareTiles' test: true where two boxes hold no pair within range that has moved apart by `limit`, being
    // `apart` or farther apart, or their displacements fitting a box of diagonal `limit`
    static bool clear(const TileBox& p, const TileBox& q, T limit, T apart) {
      const vec3 gap = glm::max(vec3(0), glm::max(q.lo - p.hi, p.lo - q.hi));
      if (glm::dot(gap, gap) >= apart * apart) return true;
      const vec3 box = glm::max(p.dhi, q.dhi) - glm::min(p.dlo, q.dlo);
      return glm::dot(box, box) <= limit * limit;
    }
  };
  std::vector<TileBox> boxes_;
  // boxDisplacements' parts, on lines of their own, and the check's stamp
  struct alignas(64) DisplacementPart {
    float box[6] = {};  // min x, y, z, max x, y, z
    bool finite = false;
    long long stamp = -1;
  };
  std::array<DisplacementPart, kDisplacementParts> displacement_parts_{};
  long long check_stamp_ = -1;
  long long cleared_whole_ = 0;  // checksClearedWhole, counted by one thread
  // The union of parts [0, parts) made for this check, into lo and hi; false where one is missing or not finite
  bool displacementBox(int parts, vec3& lo, vec3& hi) const;
  bool displacementsHold(int parts) const;        // that box's diagonal within the check's limit
  static constexpr std::size_t kSplitTiles = 32;  // from this many tiles a team splits needsBuild's work
  // stencilTiles': per square and forward offset the least squared distance at the build (recorded at the build of
  // count stencil_recorded_); per thread of the team and square the offsets to test, and the rows of squares
  // [first, second) the thread prepared them for last. A row of squares may be split between two threads (the
  // stencil's shares are whole rows of points): each prepares its own copy of its offsets, and at a record the later
  // one records it apart (shared_min2_).
  std::vector<float> stencil_min2_;
  std::vector<float> shared_min2_;  // per thread of the team, a row of squares' record (GridStencilTiles::shared_min2)
  std::vector<std::uint64_t> stencil_active_;
  std::vector<std::pair<int, int>> active_rows_;
  long long stencil_recorded_ = -1;
  bool squares_ = true;
  bool squares_used_ = false;  // the last substep's stencil passed over what the squares ruled out
  void activeOffsets(long long first, long long last);
  std::vector<vec3> rest_;
  int w_ = 0, h_ = 0;               // the grid, or 0 x 0
  std::vector<std::uint32_t> uv_;   // each point's grid column | row << 16 (words: GridKernels::filePairs gathers them)
  std::vector<std::int32_t> kind_;  // OffsetKind per offset of the box [-box_, box_]^2, row by row
  static int columnOf(std::uint32_t uv) { return int(uv & 0xffff); }  // of a uv_ word
  static int rowOf(std::uint32_t uv) { return int(uv >> 16); }
  void prepareBuild(const std::vector<vec3>& x, int threads);
  void findPairs(const std::vector<vec3>& x, int thread, long long first, long long last);
  void findPairsByCell(int thread, long long first, long long last);
  int scanCellSlots(const ScanArgs& a, std::uint32_t p0, std::uint32_t p1, const CellRange* ranges, int count,
                    std::uint32_t* points, std::uint32_t* slots) const;
  BuildOrder build_order_ = BuildOrder::ByCell;
  void setPoint(ScanArgs& scan, const std::vector<vec3>& x, std::size_t i) const;
  // The list's tables in locals, for the loops that file a build's pairs (collision_pairs_build.cpp)
  struct Filer;
  Filer filer(Found* mine) const;
  // The part of the candidate at slot s of the grid's order for p: kFarBit where |p - it|^2 (as glm::dot sums it) is
  // not under the near entries' reach, else 0 (a NaN distance is near). The scalar twin of scanCell's kFarSlot.
  std::uint32_t farMark(vec3 p, std::uint32_t s) const {
    const T dx = p.x - sx_[s], dy = p.y - sy_[s], dz = p.z - sz_[s];
    return dx * dx + dy * dy + dz * dz >= near_reach_ * near_reach_ ? kFarBit : 0;
  }
  // findPairsByCell's pairs of slots, per thread, as scanCell writes them: a batch of cells' at a time
  std::vector<std::vector<std::uint32_t>> cell_points_, cell_slots_;
  void fileFound(const Filer& file, const std::uint32_t* points, const std::uint32_t* slots, std::size_t count) const;
  void sizeLists(std::size_t n);  // serial: the lists sized for the pairs found
  void assembleLists(std::size_t n);
  void assembleBounds(std::size_t n, std::size_t shares);  // serial: assemble_bounds_
  void finishBuild(const std::vector<vec3>& x);
  template <class F>
  void guarded(F&& f);
  void rethrowOutsideTeam();
  ScanArgs scan_{};         // the build's, for every thread
  bool by_offset_ = false;  // the build passes over pairs by their grid offset
  struct Flag {             // an atomic flag that copies with the lists (a CpuSolver is copied in the tests)
    std::atomic<bool> set{false};
    Flag() = default;
    Flag(const Flag& o) : set(o.set.load()) {}
    Flag& operator=(const Flag& o) {
      set = o.set.load();
      return *this;
    }
  };
  Flag out_of_memory_;
  Flag moved_;          // needsBuild's answer, shared by a team
  Flag looked_;         // this check's closer look cleared the pairs of tiles its boxes did not
  long long kept_ = 0;  // closerLooksKept before this check
  bool split_ = false;  // this check is split between a team's threads (written by startCheck only)
  std::exception_ptr failure_;
  std::vector<T> sx_, sy_, sz_, su_, sv_;  // build's scratch: position, column and row of grid_.sorted()[s]
  T a2_ = 0, b2_ = 0, near_below_ = -1;    // ScanArgs of the stencil's grid
  const GridKernels* kernels_ = nullptr;
  int box_ = -1;
  std::vector<Offset> stencil_;
  StencilMask forward_bits_ = 0;  // the stencil bits of its second half, the offsets of positive step
  std::vector<int> du_, dv_;
  std::vector<std::uint8_t> mixed_;             // per stencil offset: some of its pairs are held at rest, some not
  T stencil_range_ = -1, stencil_margin_ = -1;  // what stencil_ was made for
  T range_ = 0, margin_ = 0;
  T travel_ = 0;  // safeTravel at the last build
  bool built_ = false;
  long long rebuilds_ = 0;
  long long entries_built_ = 0;
};

// Where j lies around i in the 27-cell query of a grid of cell size `range` (0..26, z then y then x),
// or -1 if the 27 cells do not hold it. The order in which the self-collision sum visits its terms.
inline int cellOrder(glm::ivec3 cell_i, glm::ivec3 cell_j) {
  const glm::ivec3 d = cell_j - cell_i;
  if (d.x < -1 || d.x > 1 || d.y < -1 || d.y > 1 || d.z < -1 || d.z > 1) return -1;
  return (d.z + 1) * 9 + (d.y + 1) * 3 + (d.x + 1);
}

// Calls f(c) with the correction of every pair {i, j} in range, in cellOrder and then ascending j: the
// order of a 27-cell query of a grid of cell size 2*thickness, as the sum had before the lists. One sweep
// over the short candidate list computes each term once and inserts it by its cell order (stably, so one
// order's terms stay in list order, ascending j); cells are computed only for pairs in range, which most
// points have none of. A point with more terms than are held (a deep fold) sweeps once per order present.
// stencil_mask: the point's stencilMask (all bits: every stencil partner is looked at).
template <class T, class F>
void forEachOrderedPair(const CollisionPairs<T>& pairs, std::size_t i, const std::vector<glm::vec<3, T>>& x,
                        T thickness, T inv_range, F&& f, StencilMask stencil_mask = ~StencilMask(0)) {
  using vec3 = glm::vec<3, T>;
  constexpr int kHeld = 24;  // the folded selfCollision scene has at most 5 terms a point
  struct Term {
    int order;
    vec3 c;
  };
  Term held[kHeld];
  int count = 0;
  std::uint32_t present = 0;
  glm::ivec3 cell_i{};
  pairs.forEachCandidate(i, stencil_mask, [&](std::uint32_t j) {
    const vec3 c = physics::selfCollisionCorrection(x[i], x[j], thickness);
    if (c == vec3(0)) return;
    if (present == 0) cell_i = HashGrid<T>::cellOf(x[i], inv_range);
    const int order = cellOrder(cell_i, HashGrid<T>::cellOf(x[j], inv_range));
    if (order < 0) return;
    present |= 1u << order;
    if (count < kHeld) {
      int k = count;
      for (; k > 0 && held[k - 1].order > order; --k)
        held[k] = held[k - 1];
      held[k] = {order, c};
    }
    ++count;
  });
  if (count <= kHeld) {
    for (int k = 0; k < count; ++k)
      f(held[k].c);
    return;
  }
  while (present != 0) {
    const int order = std::countr_zero(present);
    present &= present - 1;
    pairs.forEachCandidate(i, stencil_mask, [&](std::uint32_t j) {
      const vec3 c = physics::selfCollisionCorrection(x[i], x[j], thickness);
      if (c != vec3(0) && cellOrder(cell_i, HashGrid<T>::cellOf(x[j], inv_range)) == order) f(c);
    });
  }
}

// Pairs of points closer than `range` in the rest shape `rest`: the pairs self-collision skips
// (heldAtRest). count: each pair once; closest: the smallest such distance (0 if none).
struct HeldPairs {
  std::size_t count = 0;
  double closest = 0;
};
HeldPairs heldPairsAtRest(const std::vector<glm::dvec3>& rest, double range);

}  // namespace drape
