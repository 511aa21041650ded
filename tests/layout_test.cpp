// The GPU buffer structs (glsl/shared/layout.h) as C++ sees them must match what std430 makes of the
// same declaration in GLSL: every member offset, the struct size and the array stride. The expected
// numbers come from the std430 rules themselves (GL 4.5 core spec, 7.6.2.2), applied here member by
// member, not from the C++ compiler.
#include "gpu/layout.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

namespace drape::gpu {
namespace {

enum class Kind { Scalar, Vec2, Vec4 };  // the member types layout.h allows

struct Member {
  std::string name;
  Kind kind;
  std::size_t cxx_offset;  // offsetof in the C++ struct
};

std::size_t baseAlignment(Kind k) {
  return k == Kind::Scalar ? 4 : k == Kind::Vec2 ? 8 : 16;
}
std::size_t byteSize(Kind k) {
  return k == Kind::Scalar ? 4 : k == Kind::Vec2 ? 8 : 16;
}
std::size_t roundUp(std::size_t n, std::size_t a) {
  return (n + a - 1) / a * a;
}

// std430: each member at the next multiple of its base alignment; the struct aligned to its largest
// member alignment (no rounding up to 16 as std140 would), its size padded to that alignment, which is
// also the array stride.
void expectStd430(const char* type, const std::vector<Member>& members, std::size_t cxx_size) {
  std::size_t offset = 0, align = 0;
  for (const Member& m : members) {
    offset = roundUp(offset, baseAlignment(m.kind));
    EXPECT_EQ(m.cxx_offset, offset) << type << "::" << m.name;
    offset += byteSize(m.kind);
    align = std::max(align, baseAlignment(m.kind));
  }
  EXPECT_EQ(cxx_size, roundUp(offset, align)) << type << ": size (= array stride)";
}

#define MEMBER(type, name, kind)            \
  Member {                                  \
#name, Kind::kind, offsetof(type, name) \
  }

TEST(Layout, SimParamsIsStd430) {
  expectStd430("SimParams",
               {MEMBER(SimParams, stiffness, Vec4),
                MEMBER(SimParams, wind_velocity, Vec4),
                MEMBER(SimParams, weight, Vec4),
                MEMBER(SimParams, dt, Scalar),
                MEMBER(SimParams, dt2, Scalar),
                MEMBER(SimParams, keep, Scalar),
                MEMBER(SimParams, thickness, Scalar),
                MEMBER(SimParams, inv_cell_size, Scalar),
                MEMBER(SimParams, steps_per_frame, Scalar),
                MEMBER(SimParams, stretch_limit, Scalar),
                MEMBER(SimParams, noise_scale, Scalar),
                MEMBER(SimParams, noise_speed, Scalar),
                MEMBER(SimParams, sane_bound, Scalar),
                MEMBER(SimParams, point_count, Scalar),
                MEMBER(SimParams, bucket_mask, Scalar),
                MEMBER(SimParams, bucket_count, Scalar),
                MEMBER(SimParams, scan_blocks, Scalar),
                MEMBER(SimParams, inv_pair_cell, Scalar),
                MEMBER(SimParams, pair_reach, Scalar),
                MEMBER(SimParams, pair_reach2, Scalar),
                MEMBER(SimParams, pair_margin, Scalar),
                MEMBER(SimParams, blow_up_stretch, Scalar),
                MEMBER(SimParams, pad0, Scalar),
                MEMBER(SimParams, alpha_tilde, Vec4)},
               sizeof(SimParams));
  EXPECT_EQ(sizeof(SimParams), 144u);
}

TEST(Layout, ArrayElementsAreStd430) {
  expectStd430("ColouredSpring",
               {MEMBER(ColouredSpring, a, Scalar), MEMBER(ColouredSpring, b, Scalar),
                MEMBER(ColouredSpring, rest, Scalar), MEMBER(ColouredSpring, type, Scalar)},
               sizeof(ColouredSpring));
  expectStd430("ColourPartner", {MEMBER(ColourPartner, other, Scalar), MEMBER(ColourPartner, rest, Scalar)},
               sizeof(ColourPartner));
  EXPECT_EQ(sizeof(ColourPartner), 8u);
  expectStd430("Neighbor", {MEMBER(Neighbor, index_type, Scalar), MEMBER(Neighbor, rest, Scalar)}, sizeof(Neighbor));
  EXPECT_EQ(sizeof(Neighbor), 8u) << "8-byte stride: std430 does not pad scalar structs to 16";
  EXPECT_EQ(kNeighborIndexMask, (1u << kNeighborIndexBits) - 1);
  EXPECT_GE(std::uint64_t(kNeighborIndexMask) + 1, std::uint64_t(4096) * 4096) << "the largest cloth's indices";
  expectStd430("Collider", {MEMBER(Collider, a, Vec4), MEMBER(Collider, b, Vec4)}, sizeof(Collider));
  expectStd430("GridPoint",
               {MEMBER(GridPoint, cell_x, Scalar), MEMBER(GridPoint, cell_y, Scalar), MEMBER(GridPoint, cell_z, Scalar),
                MEMBER(GridPoint, bucket, Scalar), MEMBER(GridPoint, arrival, Scalar)},
               sizeof(GridPoint));
  expectStd430("GridEntry",
               {MEMBER(GridEntry, x, Scalar), MEMBER(GridEntry, y, Scalar), MEMBER(GridEntry, z, Scalar),
                MEMBER(GridEntry, index, Scalar)},
               sizeof(GridEntry));
  expectStd430("Health",
               {MEMBER(Health, flags, Scalar), MEMBER(Health, first_point, Scalar), MEMBER(Health, pad0, Scalar),
                MEMBER(Health, pad1, Scalar)},
               sizeof(Health));
  expectStd430(
      "PairState",
      {MEMBER(PairState, stale, Scalar), MEMBER(PairState, extent_bits, Scalar), MEMBER(PairState, travel2, Scalar),
       MEMBER(PairState, total, Scalar), MEMBER(PairState, capacity, Scalar), MEMBER(PairState, overflow, Scalar),
       MEMBER(PairState, builds, Scalar), MEMBER(PairState, pad0, Scalar)},
      sizeof(PairState));
  // Two arrays of kPairDispatchCount (x, y, z) commands; glDispatchComputeIndirect reads 3 tight uints.
  EXPECT_EQ(sizeof(PairDispatch::live), 3 * kPairDispatchCount * sizeof(uint));
  EXPECT_EQ(offsetof(PairDispatch, full), sizeof(PairDispatch::live));
  EXPECT_EQ(sizeof(PairDispatch), 2 * sizeof(PairDispatch::live));
  EXPECT_EQ(offsetof(PairControl, dispatch), sizeof(PairState)) << "std430: structs of scalars align to 4";
  expectStd430("PickResult",
               {MEMBER(PickResult, best_t_bits, Scalar), MEMBER(PickResult, index, Scalar),
                MEMBER(PickResult, pad0, Scalar), MEMBER(PickResult, pad1, Scalar)},
               sizeof(PickResult));
  expectStd430(
      "PointMass",
      {MEMBER(PointMass, weight, Vec4), MEMBER(PointMass, normal_a, Scalar), MEMBER(PointMass, normal_b, Scalar),
       MEMBER(PointMass, normal_c, Scalar), MEMBER(PointMass, normal_d, Scalar), MEMBER(PointMass, drag_area, Scalar),
       MEMBER(PointMass, pad0, Scalar), MEMBER(PointMass, pad1, Scalar), MEMBER(PointMass, pad2, Scalar)},
      sizeof(PointMass));
}

TEST(Layout, TetherIsTwoScalars) {
  expectStd430("Tether", {MEMBER(Tether, anchor, Scalar), MEMBER(Tether, rest, Scalar)}, sizeof(Tether));
  EXPECT_EQ(sizeof(Tether), 8u);
}

TEST(Layout, PerPointArraysHaveTheStridesTheKernelsAssume) {
  // vec4 positions/normals/tangents, vec2 uvs, uint indices: std430 strides 16, 8, 4. Displacements are
  // float[] with 3 a point, which glm::vec3 arrays match.
  EXPECT_EQ(sizeof(glm::vec4), 16u);
  EXPECT_EQ(sizeof(glm::vec3), 12u);
  EXPECT_EQ(alignof(glm::vec4), 4u) << "glm is not 16-aligned: the structs must place vec4s themselves";
  EXPECT_EQ(sizeof(glm::vec2), 8u);
  EXPECT_EQ(sizeof(uint), 4u);
}

TEST(Layout, BindingPointsAreDistinct) {
  const uint bindings[] = {kBindingParams,          kBindingPosIn,          kBindingDispIn,     kBindingPosOut,
                           kBindingDispOut,         kBindingOffsets,        kBindingNeighbors,  kBindingColliders,
                           kBindingGridPoints,      kBindingGridCounts,     kBindingGridStart,  kBindingGridBlocks,
                           kBindingGridScatter,     kBindingGridSorted,     kBindingHealth,     kBindingPick,
                           kBindingColouredSprings, kBindingPairControl,    kBindingPairAnchor, kBindingPairStart,
                           kBindingPairList,        kBindingPointMass,      kBindingXpbdLambda, kBindingColourPartners,
                           kBindingTethers,         kBindingColouredPoints, kBindingVbdInertia, kBindingRest,
                           kBindingFaceTable,       kBindingFaceFeatures};
  EXPECT_EQ(kBindingCount, std::size(bindings)) << "kBindingCount is one more than the largest binding point";
  std::vector<bool> used(64, false);
  for (uint b : bindings) {
    ASSERT_LT(b, 64u);
    EXPECT_FALSE(used[b]) << "binding " << b << " used twice";
    used[b] = true;
  }
}

TEST(Layout, ScanSizesAgree) {
  EXPECT_EQ(kScanBlock, kScanLocalSize * kScanItems);
  EXPECT_EQ(kScanLocalSize & (kScanLocalSize - 1), 0u) << "the Hillis-Steele scan doubles its offset";
}

}  // namespace
}  // namespace drape::gpu
