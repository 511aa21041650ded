// Wind noise on hostile inputs: positions that blew up and scenes whose noise_scale is tiny put huge or
// non-finite points into valueNoise, whose float -> int conversion of the lattice cell was undefined
// behaviour there (UBSan: float-cast-overflow).
#include "cpu/physics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace drape {
namespace {

template <class T>
class ValueNoise : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ValueNoise, Precisions);

TYPED_TEST(ValueNoise, IsZeroForNonFiniteAndHugePoints) {
  using T = TypeParam;
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  const T huge[] = {inf, -inf, nan, T(1e30), T(-1e30), T(3e9), T(-3e9), T(1 << 30), std::numeric_limits<T>::max()};
  for (T v : huge) {
    for (int axis = 0; axis < 3; ++axis) {
      glm::vec<3, T> p(T(0.3), T(0.6), T(0.9));
      p[axis] = v;
      EXPECT_EQ(physics::valueNoise(p), T(0)) << "axis " << axis << " = " << v;
    }
  }
}

TYPED_TEST(ValueNoise, IsUnchangedInsideTheLimit) {
  using T = TypeParam;
  // Deterministic, in [-1, 1], not constant, and continuous across a lattice cell.
  const T a = physics::valueNoise(glm::vec<3, T>(T(0.3), T(-2.6), T(5.9)));
  const T b = physics::valueNoise(glm::vec<3, T>(T(1e6) + T(0.5), T(-7e5), T(3.25)));
  EXPECT_EQ(a, physics::valueNoise(glm::vec<3, T>(T(0.3), T(-2.6), T(5.9))));
  EXPECT_NE(a, b);
  for (T v : {a, b}) {
    EXPECT_GE(v, T(-1));
    EXPECT_LE(v, T(1));
  }
  const T left = physics::valueNoise(glm::vec<3, T>(T(2) - T(1e-4), T(0.5), T(0.5)));
  const T right = physics::valueNoise(glm::vec<3, T>(T(2), T(0.5), T(0.5)));
  EXPECT_NEAR(left, right, T(1e-3));
  // Just inside the limit the cell still fits an int.
  EXPECT_TRUE(std::isfinite(physics::valueNoise(glm::vec<3, T>(T(-(1 << 29)), T(0), T(0)))));
}

TYPED_TEST(ValueNoise, WindStaysFiniteForATinyNoiseScale) {
  using T = TypeParam;
  // noise_scale at the loader's lower bound: x / noise_scale is ~1e38, far beyond the noise's limit.
  const glm::vec<3, T> v = physics::windVelocity(glm::vec<3, T>(T(0.5), T(1), T(0.25)), T(1),
                                                 glm::vec<3, T>(T(2), 0, 0), T(0.5), T(1.2e-38), T(1));
  const glm::vec<3, T> steady(T(2), T(0), T(0));
  EXPECT_TRUE(v == steady) << "the steady wind without noise: " << v.x << " " << v.y << " " << v.z;
}

}  // namespace
}  // namespace drape
