// Lanes (fcl_rs/bv/lanes.h): the lane moves the boxed test is built from, against the values they stand for.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "fcl_rs/bv/lanes.h"
#include "fcl_rs/bv/rs.h"
#include "test_util.h"

namespace {

using fcl_rs::detail::Lanes;
using fcl_rs::test::seededRng;

Lanes randomLanes(std::mt19937_64& rng)
{
  std::uniform_real_distribution<float> u(-10.0f, 10.0f);
  return Lanes(u(rng), u(rng), u(rng), u(rng));
}

TEST(Lanes, ShuffleAndTransposeMoveEveryLaneWhereTheyShould)
{
  auto rng = seededRng("LanesShuffleTranspose");
  for (int trial = 0; trial < 100; ++trial)
  {
    const Lanes x = randomLanes(rng), y = randomLanes(rng), z = randomLanes(rng);
    const Lanes s = fcl_rs::detail::shuffle<2, 0, 3, 1>(x);
    EXPECT_TRUE((s == Lanes(x[2], x[0], x[3], x[1])).all()) << s.transpose();
    Lanes columns[3];
    fcl_rs::detail::transpose3(x, y, z, columns);
    for (int i = 0; i < 3; ++i)
      EXPECT_TRUE((columns[i] == Lanes(x[i], y[i], z[i], 0.0f)).all()) << "column " << i << ": " << columns[i].transpose();
  }
}

TEST(Lanes, DiagonalLanesAreTheScaledDiagonalSlabProjections)
{
  auto rng = seededRng("LanesDiagonals");
  for (int trial = 0; trial < 100; ++trial)
  {
    const Lanes v = randomLanes(rng);  // the fourth lane must not leak into any diagonal
    Lanes first, second;
    fcl_rs::detail::diagonalLanes(v, first, second);
    const Eigen::Vector3d y(v[0], v[1], v[2]);
    for (int k = 3; k < fcl_rs::kNumSlabs; ++k)
    {
      // sqrt(2) times the projection on the unit direction of slab k.
      const double expected = std::sqrt(2.0) * fcl_rs::detail::slabDirection<double>(k).dot(y);
      const float got = k < 7 ? first[k - 3] : second[k - 7];
      EXPECT_NEAR(got, expected, 1e-5 * (1 + std::abs(expected))) << "slab " << k;
    }
    EXPECT_EQ(second[2], 0.0f);
    EXPECT_EQ(second[3], 0.0f);
  }
}

}  // namespace
