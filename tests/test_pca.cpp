// Principal frames: right-handed and orthonormal on every input, defined fallbacks, stable far from the origin.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "fcl_rs/bv/pca.h"
#include "fcl_rs/mesh/shapes.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

template <typename S>
class PcaTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(PcaTest, test::Scalars);

template <typename S>
PrincipalFrame<S> frameOf(const std::vector<fcl::Vector3<S>>& pts)
{
  return principalFrame<S>(int(pts.size()), [&](int i) { return pts[std::size_t(i)]; });
}

template <typename S>
void expectRotation(const fcl::Matrix3<S>& R)
{
  const S tol = 8 * std::numeric_limits<S>::epsilon();
  EXPECT_LT((R.transpose() * R - fcl::Matrix3<S>::Identity()).cwiseAbs().maxCoeff(), tol) << R;
  EXPECT_NEAR(R.determinant(), S(1), tol) << R;
  EXPECT_TRUE(R.allFinite());
}

template <typename S>
std::vector<fcl::Vector3<S>> moved(std::vector<fcl::Vector3<S>> pts, const fcl::Transform3<S>& tf)
{
  for (auto& p : pts) p = tf * p;
  return pts;
}

TYPED_TEST(PcaTest, DistinctEigenvaluesGivePrincipalAxes)
{
  using S = TypeParam;
  auto rng = test::seededRng("DistinctEigenvalues");
  const auto box = makeBox<S>(6, 3, 1).vertices;
  for (int trial = 0; trial < 50; ++trial)
  {
    const fcl::Transform3<S> tf = test::randomPose<S>(rng, S(10));
    const auto f = frameOf(moved(box, tf));
    expectRotation(f.axis);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(std::abs(f.axis.col(i).dot(tf.linear().col(i))), S(1), S(1e-4)) << "axis " << i;
    EXPECT_LT((f.mean - tf.translation()).norm(), S(1e-4) * S(10));
  }
}

TYPED_TEST(PcaTest, EqualEigenvaluesFallBackToModelAxes)
{
  using S = TypeParam;
  auto rng = test::seededRng("EqualEigenvalues");
  const fcl::Matrix3<S> R = test::randomRotation<S>(rng);
  std::vector<fcl::Vector3<S>> octahedron, cube;
  for (int i = 0; i < 3; ++i)
    for (S s : {S(-1), S(1)}) octahedron.push_back(R * (s * fcl::Vector3<S>::Unit(i)));
  for (const auto& v : makeBox<S>(2, 2, 2).vertices) cube.push_back(R * v);
  for (const auto* pts : {&octahedron, &cube})
  {
    const auto f = frameOf(*pts);
    expectRotation(f.axis);
    // Isotropic covariance: the eigenvectors are rounding noise, so the model axes are kept.
    EXPECT_TRUE(f.axis.isApprox(fcl::Matrix3<S>::Identity(), S(1e-6))) << f.axis;
  }
  const auto single = frameOf(std::vector<fcl::Vector3<S>>(5, fcl::Vector3<S>(1, 2, 3)));
  expectRotation(single.axis);
  EXPECT_TRUE(single.axis.isApprox(fcl::Matrix3<S>::Identity()));
  EXPECT_TRUE(single.mean.isApprox(fcl::Vector3<S>(1, 2, 3)));
}

TYPED_TEST(PcaTest, TwoEqualEigenvaluesKeepTheDistinctAxis)
{
  using S = TypeParam;
  auto rng = test::seededRng("TwoEqualEigenvalues");
  for (int trial = 0; trial < 20; ++trial)
  {
    const fcl::Transform3<S> tf = test::randomPose<S>(rng, S(5));
    // A needle: collinear points; the line is u0.
    std::vector<fcl::Vector3<S>> needle;
    for (int i = 0; i < 7; ++i) needle.push_back(tf * fcl::Vector3<S>(S(i), 0, 0));
    const auto fn = frameOf(needle);
    expectRotation(fn.axis);
    EXPECT_NEAR(std::abs(fn.axis.col(0).dot(tf.linear().col(0))), S(1), S(1e-5));
    // A square plate: flat with two equal in-plane variances; the normal is u2.
    const auto plate = frameOf(moved(makeBox<S>(2, 2, 0).vertices, tf));
    expectRotation(plate.axis);
    EXPECT_NEAR(std::abs(plate.axis.col(2).dot(tf.linear().col(2))), S(1), S(1e-5));
  }
}

TYPED_TEST(PcaTest, FarFromTheOriginTheAxesSurvive)
{
  using S = TypeParam;
  auto rng = test::seededRng("FarFromTheOrigin");
  // The flat 1 x 0.5 x 0.001 patch where FCL's one-pass covariance turns the normal by 75 degrees at 1e7.
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<fcl::Vector3<S>> patch;
  for (int i = 0; i < 200; ++i) patch.push_back(fcl::Vector3<S>(S(u(rng)), S(u(rng) / 2), S(u(rng) / 1000)));
  for (double offset : {1e3, 1e6, 1e7})
  {
    fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
    tf.linear() = test::randomRotation<S>(rng);
    tf.translation() = fcl::Vector3<S>(S(offset), S(-offset), S(offset / 2));
    const auto pts = moved(patch, tf);
    const auto f = frameOf(pts);
    expectRotation(f.axis);
    // The stored points themselves carry an error of ulp(offset); the normal is only as good as that.
    const double point_error = double(std::numeric_limits<S>::epsilon()) * offset;
    if (point_error < 1e-5) {
      EXPECT_NEAR(std::abs(f.axis.col(2).dot(tf.linear().col(2))), S(1), S(1e-3)) << "offset " << offset;
    }
  }
}

TYPED_TEST(PcaTest, NonFiniteInputIsAnError)
{
  using S = TypeParam;
  std::vector<fcl::Vector3<S>> pts = {fcl::Vector3<S>(0, 0, 0), fcl::Vector3<S>(1, 0, 0)};
  pts.push_back(fcl::Vector3<S>(std::numeric_limits<S>::quiet_NaN(), 0, 0));
  EXPECT_THROW(frameOf(pts), std::domain_error);
  pts.back() = fcl::Vector3<S>(0, std::numeric_limits<S>::infinity(), 0);
  EXPECT_THROW(frameOf(pts), std::domain_error);
  EXPECT_THROW(frameOf(std::vector<fcl::Vector3<S>>{}), std::invalid_argument);
}

}  // namespace
}  // namespace fcl_rs
