// The pair kernel (fcl_rs/bv/pair_kernel.h): the boxed test against its definition, the pair frame within its
// rounding bound, and the leaf-triangle filters.
#include <cmath>
#include <iostream>
#include <limits>

#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

using test::randomCloud;
using test::randomPose;
using test::seededRng;

// Exact references for the pair kernel's rounding.
using L = long double;
using VL = Eigen::Matrix<L, 3, 1>;
using ML = Eigen::Matrix<L, 3, 3>;

template <typename S>
class PairKernelTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(PairKernelTest, test::Scalars);

// The boxed test is each volume's nine slabs against the other's principal box: recomputed here from the eight
// box corners mapped exactly (long double, exact inverses of the stored frames), every pair apart along some
// slab by more than twice its rounding bound is rejected, and every pair the boxes do not separate is kept.
TYPED_TEST(PairKernelTest, BoxedTestIsTheSlabsAgainstTheOtherBox)
{
  using S = TypeParam;
  auto rng = seededRng("BoxedTestIsTheSlabsAgainstTheOtherBox");
  int apart = 0, kept = 0, apart_on_diagonal = 0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    const auto a = randomCloud<S>(rng, trial, 8), b = randomCloud<S>(rng, trial + 1, 8);
    const RS<S> ra = fitPoints<S>(a.data(), int(a.size())), rb = fitPoints<S>(b.data(), int(b.size()));
    const fcl::Transform3<S> tf = randomPose<S>(rng, S(3));
    const ML R = tf.linear().template cast<L>();
    const VL T = tf.translation().template cast<L>();
    // x1 = to1 * y2 + from1: b2's frame into b1's; the inverse map takes b1's frame into b2's.
    const ML A1 = ra.axis.template cast<L>(), A2 = rb.axis.template cast<L>();
    const ML to1 = A1.transpose() * R * A2.inverse().transpose();
    const VL from1 = A1.transpose() * (R * rb.origin.template cast<L>() + T - ra.origin.template cast<L>());
    const ML to2 = A2.transpose() * R.inverse() * A1.inverse().transpose();
    const VL from2 = A2.transpose() * (R.inverse() * (ra.origin.template cast<L>() - T) - rb.origin.template cast<L>());
    // Largest gap between a face slab (a diagonal slab) of `slabs` and the box of `other` mapped by (to, from).
    L face_gap = -std::numeric_limits<L>::max(), diagonal_gap = face_gap;
    const auto slabsAgainstBox = [&](const RS<S>& slabs, const RS<S>& other, const ML& to, const VL& from) {
      for (int k = 0; k < kNumSlabs; ++k)
      {
        const VL dir = detail::slabDirection<double>(k).template cast<L>();
        L low = std::numeric_limits<L>::max(), high = -std::numeric_limits<L>::max();
        for (int corner = 0; corner < 8; ++corner)
        {
          VL y;
          for (int i = 0; i < 3; ++i) y[i] = (corner >> i & 1) ? L(other.hi[i]) : L(other.lo[i]);
          const L v = dir.dot(to * y + from);
          low = std::min(low, v);
          high = std::max(high, v);
        }
        L& gap = k < 3 ? face_gap : diagonal_gap;
        gap = std::max(gap, std::max(low - L(slabs.hi[k]), L(slabs.lo[k]) - high));
      }
    };
    slabsAgainstBox(ra, rb, to1, from1);
    slabsAgainstBox(rb, ra, to2, from2);
    const fcl::Matrix3<S> rotation = tf.linear();
    const fcl::Vector3<S> translation = tf.translation();
    // The boxed test computes in the storage precision: its bound (storedPairRoundingBound) on PairFrame's values.
    const detail::MovedFrame<S> moved(rotation, translation, rb);
    const detail::PairFrame<S> f(moved, ra);
    const S tol = detail::storedPairRoundingBound<S>(
        moved.offsets + ra.origin.template lpNorm<1>(), f.box1.reach() + moved.reach,
        (f.centre2 - f.box1.c).template lpNorm<1>(), (moved.centre - ra.origin).template lpNorm<1>());
    const bool boxed = overlap(rotation, translation, ra, rb, OverlapTest::kBoxed);
    const L gap = std::max(face_gap, diagonal_gap);
    if (gap <= 0)
    {
      EXPECT_TRUE(boxed) << "trial " << trial << " gap " << double(gap);
      ++kept;
    }
    else if (gap > 2 * L(tol))
    {
      EXPECT_FALSE(boxed) << "trial " << trial << " gap " << double(gap) << " tol " << double(tol);
      ++apart;
      apart_on_diagonal += face_gap <= 0;
    }
  }
  EXPECT_GT(kept, 200);
  EXPECT_GT(apart, 200);
  EXPECT_GT(apart_on_diagonal, 20);  // some pairs only the diagonals separate
  std::cout << "kept " << kept << ", apart " << apart << " (" << apart_on_diagonal << " by diagonals only)\n";
}

// The pair kernel's one rounding bound covers the change of frame: every vertex y2 of b2 (its frame) lands,
// through the computed M y2 + t, within tol of its exact image in b1's frame (long double, exact inverse of the
// stored frame), and so do the two box centres the boxed test compares, with both volumes and the transform
// far from the origin.
TYPED_TEST(PairKernelTest, PairFrameStaysWithinItsRoundingBound)
{
  using S = TypeParam;
  auto rng = seededRng("PairFrameStaysWithinItsRoundingBound");
  std::uniform_real_distribution<double> far(-1000, 1000);
  S worst = 0;  // largest error / tol
  for (int trial = 0; trial < 200; ++trial)
  {
    const fcl::Vector3<S> shift_a(S(far(rng)), S(far(rng)), S(far(rng))), shift_b(S(far(rng)), S(far(rng)), S(far(rng)));
    auto a = randomCloud<S>(rng, trial, 12), b = randomCloud<S>(rng, trial + 1, 12);
    for (auto& p : a) p += shift_a;
    for (auto& p : b) p += shift_b;
    const RS<S> ra = fitPoints<S>(a.data(), int(a.size())), rb = fitPoints<S>(b.data(), int(b.size()));
    const fcl::Transform3<S> tf = randomPose<S>(rng, S(1000));
    const detail::PairFrame<S> f(tf.linear(), tf.translation(), ra, rb);
    const ML R = tf.linear().template cast<L>(), A1 = ra.axis.template cast<L>();
    const ML A2_inverse_transpose = rb.axis.template cast<L>().inverse().transpose();
    const VL T = tf.translation().template cast<L>(), o1 = ra.origin.template cast<L>(), o2 = rb.origin.template cast<L>();
    for (const auto& y2 : rb.corners())
    {
      const VL x2 = A2_inverse_transpose * y2.template cast<L>() + o2;
      const VL exact = A1.transpose() * (R * x2 + T - o1);
      const fcl::Vector3<S> computed = f.M * y2 + f.t();
      const S error = S((computed.template cast<L>() - exact).cwiseAbs().maxCoeff());
      ASSERT_LE(error, f.tol) << "trial " << trial;
      worst = std::max(worst, error / f.tol);
    }
    // The boxed test's two box centres: b2's in b1's frame, and b1's in b2's frame (stored frame A2, exact
    // inverse of A1 and R).
    const VL c2 = A2_inverse_transpose * f.box2.c.template cast<L>() + o2;
    const VL centre2 = A1.transpose() * (R * c2 + T - o1);
    const VL c1 = A1.inverse().transpose() * f.box1.c.template cast<L>() + o1;
    const VL centre1 = rb.axis.template cast<L>().transpose() * (R.inverse() * (c1 - T) - o2);
    const S error2 = S((f.centre2.template cast<L>() - centre2).cwiseAbs().maxCoeff());
    const S error1 = S((f.centre1().template cast<L>() - centre1).cwiseAbs().maxCoeff());
    ASSERT_LE(error2, f.tol) << "trial " << trial;
    ASSERT_LE(error1, f.tol) << "trial " << trial;
    worst = std::max(worst, std::max(error1, error2) / f.tol);
  }
  std::cout << "largest frame error / rounding bound: " << worst << "\n";
}

// The traversal's test of a leaf's triangle against the other tree's node (detail::triangleOverlap, both ways
// round): a triangle with a vertex at a corner of the node's polytope (grazing) or through a point inside it is
// never culled, near the origin and 1e3 or 1e5 away; the same triangle moved out past a face by well over the
// rounding bound is.
TYPED_TEST(PairKernelTest, LeafTriangleTestKeepsTouchingTrianglesAndCullsDistantOnes)
{
  using S = TypeParam;
  auto rng = seededRng("LeafTriangleTestKeepsTouchingTriangles");
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  const S offsets[] = {0, 1000, 100000};
  for (int trial = 0; trial < 600; ++trial)
  {
    const S offset = offsets[trial % 3];
    auto cloud = randomCloud<S>(rng, trial, 3 + trial % 20);
    const fcl::Vector3<S> shift(S(u(rng) * offset), S(u(rng) * offset), S(u(rng) * offset));
    for (auto& p : cloud) p += shift;
    const RS<S> node = fitPoints<S>(cloud.data(), int(cloud.size()));
    const fcl::Transform3<S> tf = randomPose<S>(rng, offset + 1);
    const fcl::Matrix3<S> R = tf.linear();
    const fcl::Vector3<S> T = tf.translation();
    const bool node_in_model1 = trial % 2 == 0;  // else the triangle is model1's and the node model2's
    // A point of the node's polytope: a corner (the triangle grazes it) or a mix of corners.
    const auto corners = node.corners();
    fcl::Vector3<S> y = corners[std::size_t(trial) % 32];
    if (trial % 4 >= 2)
    {
      const S w = S(unit(rng));
      y = w * y + (1 - w) * corners[std::size_t(trial / 4) % 32];
    }
    const fcl::Vector3<S> x = node.toModel(y);
    const fcl::Vector3<S> at = node_in_model1 ? fcl::Vector3<S>(R.transpose() * (x - T)) : fcl::Vector3<S>(R * x + T);
    // The triangle in its own model's coordinates, through `at`: as a vertex, or on the first edge's middle.
    const S size = S(std::pow(10.0, 3 * unit(rng) - 2));
    const fcl::Vector3<S> e(S(u(rng)), S(u(rng)), S(u(rng))), f(S(u(rng)), S(u(rng)), S(u(rng)));
    fcl::Vector3<S> tri[3] = {at, at + size * e, at + size * f};
    if (trial % 3 == 1) tri[1] = at - size * e, tri[0] = at + size * e;
    const auto test = [&](const fcl::Vector3<S> t[3]) {
      const RS<S> leaf = fitPoints<S>(t, 3);
      return node_in_model1 ? detail::triangleOverlap(node, R, T, t, leaf, S(0))
                            : detail::triangleOverlap(t, leaf, detail::MovedFrame<S>(R, T, node), node);
    };
    ASSERT_TRUE(test(tri)) << "trial " << trial << " offset " << offset << " size " << size;

    // Moved out along the node's first axis until every vertex is past the slab by 1 % of the node's size and
    // far more than the rounding bound (pairRoundingBound of everything involved).
    const fcl::Vector3<S> axis_in_triangle = node_in_model1 ? fcl::Vector3<S>(R.transpose() * node.axes().col(0))
                                                            : fcl::Vector3<S>(R * node.axes().col(0));
    S lowest = std::numeric_limits<S>::max();
    for (const auto& v : tri) lowest = std::min(lowest, axis_in_triangle.dot(v));
    const S bound =
        detail::pairRoundingBound<S>(3 * (offset + size) + 3 * T.template lpNorm<1>(), node.magnitude() + size);
    const S beyond = axis_in_triangle.dot(at) - lowest + node.hi[0] - y[0] + S(0.01) * node.magnitude() + 100 * bound;
    fcl::Vector3<S> apart[3];
    for (int i = 0; i < 3; ++i) apart[i] = tri[i] + beyond * axis_in_triangle;
    EXPECT_FALSE(test(apart)) << "trial " << trial << " offset " << offset << " size " << size;
  }
}

}  // namespace
}  // namespace fcl_rs
