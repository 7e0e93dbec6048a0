// RS<S> as a bounding volume: containment, corners, support, merge, overlap, distance, volume, trees.
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <fcl/math/bv/OBB.h>
#include <gtest/gtest.h>
extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

using test::randomCloud;
using test::randomPose;
using test::randomRotation;
using test::seededRng;

/// Volume of the convex hull of pts (qhull), 0 when the points span less than 3 dimensions.
double hullVolume(const std::vector<Eigen::Vector3d>& pts)
{
  if (pts.size() < 4) return 0;
  std::vector<coordT> coords;
  for (const auto& p : pts) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, nullptr);
  char options[] = "qhull FA Qt Pp";
  const int failed = qh_new_qhull(qh, 3, int(pts.size()), coords.data(), False, options, nullptr, nullptr);
  const double volume = failed ? 0.0 : qh->totvol;
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  return volume;
}

/// Rounding of values derived from a volume of size scale, including the float storage of its slabs.
template <typename S>
S tolerance(S scale)
{
  return 512 * std::numeric_limits<S>::epsilon() * scale + 2 * detail::storageBound(scale);
}

template <typename S>
class RSTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(RSTest, test::Scalars);

TYPED_TEST(RSTest, DefaultIsEmptyAndGrowsFromPoints)
{
  using S = TypeParam;
  RS<S> bv;
  EXPECT_TRUE(bv.empty());
  EXPECT_FALSE(bv.overlap(bv));
  EXPECT_FALSE(bv.contain(fcl::Vector3<S>::Zero()));
  EXPECT_EQ(bv.volume(), S(0));
  const fcl::Vector3<S> p(1, 2, 3), q(-1, 0, 5);
  bv += p;
  EXPECT_FALSE(bv.empty());
  EXPECT_TRUE(bv.contain(p));
  EXPECT_FALSE(bv.contain(q));
  bv += q;
  EXPECT_TRUE(bv.contain(q));
  EXPECT_TRUE(bv.contain((p + q) / 2));
}

TYPED_TEST(RSTest, FitContainsEveryPointAndCornersBoundThePolytope)
{
  using S = TypeParam;
  auto rng = seededRng("FitContainsEveryPoint");
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 300; ++trial)
  {
    const auto pts = randomCloud<S>(rng, trial, 1 + trial % 40);
    const RS<S> bv = fitPoints<S>(pts.data(), int(pts.size()));
    const S scale = bv.magnitude() + bv.origin.template lpNorm<1>();
    // The frame is orthonormal and right-handed, up to its storage.
    const fcl::Matrix3<S> A = bv.axes();
    const S frame_eps = 16 * std::numeric_limits<typename RS<S>::Stored>::epsilon();
    EXPECT_LT((A.transpose() * A - fcl::Matrix3<S>::Identity()).norm(), frame_eps);
    EXPECT_NEAR(A.determinant(), S(1), frame_eps);
    for (const auto& p : pts) ASSERT_TRUE(bv.contain(p)) << "trial " << trial;

    const auto corners = bv.corners();
    for (int c = 0; c < 32; ++c)
    {
      // Every corner lies in all 18 halfspaces and on at least three of the planes.
      int on_planes = 0;
      for (int k = 0; k < kNumSlabs; ++k)
      {
        const S v = projectOnSlab(corners[c], k);
        EXPECT_GE(v, bv.lo[k] - tolerance(scale)) << "trial " << trial << " corner " << c << " slab " << k;
        EXPECT_LE(v, bv.hi[k] + tolerance(scale)) << "trial " << trial << " corner " << c << " slab " << k;
        on_planes += std::abs(v - bv.lo[k]) <= tolerance(scale);
        on_planes += std::abs(v - bv.hi[k]) <= tolerance(scale);
      }
      EXPECT_GE(on_planes, 3) << "trial " << trial << " corner " << c;
    }
    // The corners' hull contains every point: no direction finds a point beyond the corners, and
    // the octant trick (4 vertices) gives the same support as all 32 corners; extremeVertex is a corner
    // where that support is attained.
    for (int d = 0; d < 50; ++d)
    {
      const fcl::Vector3<S> dir = fcl::Vector3<S>(S(g(rng)), S(g(rng)), S(g(rng))).normalized();
      S all = -std::numeric_limits<S>::max();
      for (const auto& c : corners) all = std::max(all, dir.dot(c));
      EXPECT_NEAR(bv.support(dir), all, tolerance(scale));
      for (const auto& p : pts) ASSERT_LE(dir.dot(bv.toFrame(p)), bv.support(dir) + tolerance(scale));
      const fcl::Vector3<S> extreme = detail::extremeVertex(bv, dir);
      EXPECT_NEAR(dir.dot(extreme), all, tolerance(scale)) << "trial " << trial;
      S nearest_corner = std::numeric_limits<S>::max();
      for (const auto& c : corners) nearest_corner = std::min(nearest_corner, (c - extreme).norm());
      EXPECT_LE(nearest_corner, tolerance(scale)) << "trial " << trial;
    }
  }
}

TYPED_TEST(RSTest, BatchedGrowthIsPerPointGrowthPaddedOnce)
{
  // expandPoints (what fits use) pads by the largest point's rounding once; expandFrame pads per point.
  using S = TypeParam;
  auto rng = seededRng("BatchedGrowth");
  for (int trial = 0; trial < 100; ++trial)
  {
    const auto pts = randomCloud<S>(rng, trial, 1 + trial % 40);
    RS<S> batched(randomRotation<S>(rng), pts.front());
    RS<S> per_point = batched;
    batched.expandPoints(int(pts.size()), [&](int i) { return pts[std::size_t(i)]; });
    S largest = 0;
    for (const auto& p : pts)
    {
      per_point.expandFrame(per_point.toFrame(p), 0);
      largest = std::max(largest, per_point.toFrame(p).template lpNorm<1>());
    }
    per_point.updateBoxExcess();
    // Plus the outward rounding to the stored slabs (two float ulps), once per side.
    const S pad = 8 * std::numeric_limits<S>::epsilon() * largest +
                  4 * std::numeric_limits<typename RS<S>::Stored>::epsilon() * per_point.magnitude();
    for (int k = 0; k < kNumSlabs; ++k)
    {
      EXPECT_LE(batched.lo[k], per_point.lo[k]) << "trial " << trial << " slab " << k;
      EXPECT_GE(batched.hi[k], per_point.hi[k]) << "trial " << trial << " slab " << k;
      EXPECT_LE(per_point.lo[k] - batched.lo[k], pad) << "trial " << trial << " slab " << k;
      EXPECT_LE(batched.hi[k] - per_point.hi[k], pad) << "trial " << trial << " slab " << k;
    }
    EXPECT_NEAR(batched.box_excess, per_point.box_excess, 4 * pad + tolerance(per_point.magnitude()));
    for (const auto& p : pts) ASSERT_TRUE(batched.contain(p)) << "trial " << trial;
  }
}

TYPED_TEST(RSTest, MergeContainsBothInputs)
{
  using S = TypeParam;
  auto rng = seededRng("MergeContainsBothInputs");
  for (int trial = 0; trial < 200; ++trial)
  {
    const auto a = randomCloud<S>(rng, trial, 5 + trial % 20);
    const auto b = randomCloud<S>(rng, trial + 2, 5 + trial % 13);
    const RS<S> ra = fitPoints<S>(a.data(), int(a.size())), rb = fitPoints<S>(b.data(), int(b.size()));
    const RS<S> merged = ra + rb;
    for (const auto& p : a) ASSERT_TRUE(merged.contain(p)) << "trial " << trial;
    for (const auto& p : b) ASSERT_TRUE(merged.contain(p)) << "trial " << trial;
    for (const auto& c : ra.corners()) ASSERT_TRUE(merged.contain(ra.toModel(c))) << "trial " << trial;
    for (const auto& c : rb.corners()) ASSERT_TRUE(merged.contain(rb.toModel(c))) << "trial " << trial;
    EXPECT_TRUE((ra + RS<S>()).contain(a.front()));
    EXPECT_TRUE((RS<S>() + rb).contain(b.front()));
  }
}

// Volumes far smaller than their distance from the model origin: merging must not round at the origin's
// magnitude (fuzz_rs found a float merge 254 from the origin that missed a point of a 3e-4 volume).
TYPED_TEST(RSTest, MergeFarFromTheOriginContainsBothInputs)
{
  using S = TypeParam;
  auto rng = seededRng("MergeFarFromTheOriginContainsBothInputs");
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 400; ++trial)
  {
    const double offset = std::ldexp(1.0, trial % 12), size = 1e-4 * offset * std::ldexp(1.0, -(trial % 5));
    const Eigen::Vector3d base = offset * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    auto cloud = [&](int n) {
      std::vector<fcl::Vector3<S>> pts;
      for (int i = 0; i < n; ++i) pts.push_back((base + size * Eigen::Vector3d(u(rng), u(rng), u(rng))).cast<S>());
      return pts;
    };
    const auto a = cloud(3 + trial % 9), b = cloud(2 + trial % 7);
    const RS<S> merged = fitPoints<S>(a.data(), int(a.size())) + fitPoints<S>(b.data(), int(b.size()));
    for (const auto& p : a) ASSERT_TRUE(merged.contain(p)) << "trial " << trial << " offset " << offset;
    for (const auto& p : b) ASSERT_TRUE(merged.contain(p)) << "trial " << trial << " offset " << offset;
  }
}

// Slabs are stored in float whatever S is, rounded outward: every fitted point lies inside the stored slabs
// with no tolerance at all, far from the model origin and at tiny scales. Rounding to nearest cuts an extreme
// point off about every other slab end (the fit's own padding is a few double ulps, a float ulp is 2^29 of them).
TYPED_TEST(RSTest, StoredSlabsRoundOutwardAndContainEveryFittedPoint)
{
  using S = TypeParam;
  using Stored = typename RS<S>::Stored;
  const Stored infinity = std::numeric_limits<Stored>::infinity();
  for (const double v : {0.1, -0.1, 1.0 / 3, 1e-40, -1e-40, 1e-50, -1e-50, 0.0, 1e39, -1e39, 1e300, -1e300})
  {
    if (!(std::abs(v) <= double(std::numeric_limits<S>::max()))) continue;
    const S value = S(v);
    const Stored below = RS<S>::slabBelow(value), above = RS<S>::slabAbove(value);
    EXPECT_LE(S(below), value) << v;
    EXPECT_GE(S(above), value) << v;
    // Within two ulps, not just anywhere below or above.
    EXPECT_GT(S(std::nextafter(std::nextafter(below, infinity), infinity)), value) << v;
    EXPECT_LT(S(std::nextafter(std::nextafter(above, -infinity), -infinity)), value) << v;
  }

  auto rng = seededRng("StoredSlabsRoundOutwardAndContainEveryFittedPoint");
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 300; ++trial)
  {
    const double offset = trial % 3 == 0 ? 0.0 : std::ldexp(1.0, 3 * (trial % 7)), size = std::pow(10.0, -(trial % 9));
    const Eigen::Vector3d base = offset * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    std::vector<fcl::Vector3<S>> pts;
    for (int i = 0; i < 3 + trial % 20; ++i)
      pts.push_back((base + size * Eigen::Vector3d(u(rng), u(rng), u(rng))).cast<S>());
    const RS<S> bv = fitPoints<S>(pts.data(), int(pts.size()));
    for (int k = 0; k < kNumSlabs; ++k)
    {
      S lowest = std::numeric_limits<S>::max(), highest = std::numeric_limits<S>::lowest();
      for (const auto& p : pts)
      {
        const S v = projectOnSlab(bv.toFrame(p), k);
        lowest = std::min(lowest, v);
        highest = std::max(highest, v);
      }
      ASSERT_LE(S(bv.lo[k]), lowest) << "trial " << trial << " slab " << k << " offset " << offset << " size " << size;
      ASSERT_GE(S(bv.hi[k]), highest) << "trial " << trial << " slab " << k << " offset " << offset << " size " << size;
      // And no looser than the fit's padding plus two float ulps per end.
      const S slack = 8 * std::numeric_limits<S>::epsilon() * (offset + 2 * size) +
                      4 * std::numeric_limits<Stored>::epsilon() * std::max(std::abs(lowest), std::abs(highest));
      EXPECT_LE(lowest - S(bv.lo[k]), slack) << "trial " << trial << " slab " << k;
      EXPECT_LE(S(bv.hi[k]) - highest, slack) << "trial " << trial << " slab " << k;
    }
  }
}

// Issue 13's memory target: a node of an RS<double> tree (frame and slabs stored in float, the origin in double)
// is at most 1.25 times FCL's OBB<double> node.
TEST(RSStorage, DoubleNodeIsAtMostAQuarterLargerThanOBBs)
{
  const std::size_t rs = sizeof(fcl::BVNode<RS<double>>), obb = sizeof(fcl::BVNode<fcl::OBB<double>>);
  std::cout << "BVNode<RS<double>>: " << rs << " bytes, BVNode<OBB<double>>: " << obb << " bytes\n";
  EXPECT_LE(4 * rs, 5 * obb);
}

TYPED_TEST(RSTest, OverlapIsSymmetricAndConservative)
{
  using S = TypeParam;
  auto rng = seededRng("OverlapIsSymmetricAndConservative");
  std::uniform_real_distribution<double> u(-1, 1);
  int overlapping = 0, separated = 0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    const auto a = randomCloud<S>(rng, trial, 8);
    auto b = randomCloud<S>(rng, trial + 1, 8);
    const fcl::Transform3<S> tf = randomPose<S>(rng, S(4));
    const RS<S> ra = fitPoints<S>(a.data(), int(a.size())), rb = fitPoints<S>(b.data(), int(b.size()));
    const fcl::Matrix3<S> R = tf.linear();
    const fcl::Vector3<S> T = tf.translation();
    // The two-sided and boxed variants are symmetric (the paper's one-sided test is not).
    for (auto test : {OverlapTest::kTwoSided, OverlapTest::kBoxed})
      EXPECT_EQ(overlap(R, T, ra, rb, test), overlap<S>(R.transpose(), -(R.transpose() * T), rb, ra, test))
          << "trial " << trial << " test " << int(test);
    const bool ab = overlap(R, T, ra, rb, OverlapTest::kTwoSided);
    (ab ? overlapping : separated)++;

    // Same coordinates: symmetric too.
    std::vector<fcl::Vector3<S>> moved;
    for (const auto& p : b) moved.push_back(tf * p);
    const RS<S> rm = fitPoints<S>(moved.data(), int(moved.size()));
    EXPECT_EQ(ra.overlap(rm), rm.overlap(ra)) << "trial " << trial;

    // Sharing one point means touching: never reported separate.
    const fcl::Vector3<S> shared = a[std::size_t(trial) % a.size()];
    b.push_back(tf.inverse(Eigen::Isometry) * shared);
    const RS<S> touching = fitPoints<S>(b.data(), int(b.size()));
    for (auto test : {OverlapTest::kTwoSided, OverlapTest::kOneSided, OverlapTest::kBoxed})
      EXPECT_TRUE(overlap(R, T, ra, touching, test)) << "trial " << trial << " test " << int(test);
    // Every variant is implied by the tightest one.
    if (ab)
    {
      EXPECT_TRUE(overlap(R, T, ra, rb, OverlapTest::kOneSided)) << "trial " << trial;
      EXPECT_TRUE(overlap(R, T, ra, rb, OverlapTest::kBoxed)) << "trial " << trial;
    }
  }
  EXPECT_GT(overlapping, 100);
  EXPECT_GT(separated, 100);
}

TYPED_TEST(RSTest, BoxExcessBoundsTheCornerCutsAndTheFilterIsExact)
{
  using S = TypeParam;
  auto rng = seededRng("BoxExcessBoundsTheCornerCutsAndTheFilterIsExact");
  std::normal_distribution<double> g;
  int separated_by_polytopes = 0;
  for (int trial = 0; trial < 1000; ++trial)
  {
    const auto a = randomCloud<S>(rng, trial, 8), b = randomCloud<S>(rng, trial + 1, 8);
    const RS<S> ra = fitPoints<S>(a.data(), int(a.size())), rb = fitPoints<S>(b.data(), int(b.size()));
    // Kept current by fit, merge and growth.
    for (const RS<S>& bv : {ra, ra + rb, RS<S>(ra) += b.front(), RS<S>(ra) += rb})
    {
      RS<S> fresh = bv;
      fresh.updateBoxExcess();
      ASSERT_EQ(bv.box_excess, fresh.box_excess) << "trial " << trial;
    }
    // Its closed form is its definition: per corner, the distance from the box corner to the nearest of the
    // corner's 4 vertices, maximised over the 8 corners.
    S by_vertices = 0;
    for (int octant = 0; octant < 8; ++octant)
    {
      const fcl::Vector3<S> box_corner(octant & 1 ? ra.lo[0] : ra.hi[0], octant & 2 ? ra.lo[1] : ra.hi[1],
                                       octant & 4 ? ra.lo[2] : ra.hi[2]);
      S nearest = std::numeric_limits<S>::max();
      for (const auto& v : ra.cornerVertices(octant)) nearest = std::min(nearest, (box_corner - v).norm());
      by_vertices = std::max(by_vertices, nearest);
    }
    ASSERT_NEAR(ra.box_excess, by_vertices, tolerance(ra.magnitude())) << "trial " << trial;
    // The principal box reaches at most box_excess past the polytope along any unit direction.
    for (int d = 0; d < 20; ++d)
    {
      const fcl::Vector3<S> e = fcl::Vector3<double>(g(rng), g(rng), g(rng)).normalized().cast<S>();
      const fcl_rs::detail::Box<S> principal(ra);
      const S box = e.cwiseAbs().dot(principal.h) + e.dot(principal.c);
      ASSERT_LE(box - ra.support(e), ra.box_excess * (1 + 1e-4) + 1e-4 * ra.magnitude()) << "trial " << trial;
    }
    // Skipping exact supports where the box bound decides changes no verdict: the two-sided test
    // separates exactly when some of the 36 exact slab gaps (the distance bound) is positive.
    const fcl::Transform3<S> tf = randomPose<S>(rng, S(4));
    const fcl::Matrix3<S> R = tf.linear();
    const fcl::Vector3<S> T = tf.translation();
    const bool apart = !overlap(R, T, ra, rb, OverlapTest::kTwoSided);
    const bool boxes_apart = !overlap(R, T, ra, rb, OverlapTest::kBoxed);
    EXPECT_EQ(apart, distance(R, T, ra, rb) > 0) << "trial " << trial;
    separated_by_polytopes += apart && !boxes_apart;
  }
  EXPECT_GT(separated_by_polytopes, 10);  // the exact stage is exercised
}

TYPED_TEST(RSTest, DistanceIsALowerBound)
{
  using S = TypeParam;
  auto rng = seededRng("DistanceIsALowerBound");
  int positive = 0;
  for (int trial = 0; trial < 1000; ++trial)
  {
    const auto a = randomCloud<S>(rng, trial, 10);
    const auto b = randomCloud<S>(rng, trial + 3, 10);
    const fcl::Transform3<S> tf = randomPose<S>(rng, S(20));
    const RS<S> ra = fitPoints<S>(a.data(), int(a.size())), rb = fitPoints<S>(b.data(), int(b.size()));
    S closest = std::numeric_limits<S>::max();
    for (const auto& p : a)
      for (const auto& q : b) closest = std::min(closest, (p - tf * q).norm());
    fcl::Vector3<S> P, Q;
    const S d = distance<S>(tf.linear(), tf.translation(), ra, rb, &P, &Q);
    EXPECT_GE(d, S(0));
    EXPECT_LE(d, closest * (1 + tolerance(S(1)))) << "trial " << trial;
    if (d > 0)
    {
      ++positive;
      EXPECT_FALSE(overlap<S>(tf.linear(), tf.translation(), ra, rb)) << "trial " << trial;
      // Witness points lie on their volumes and are at least the bound apart.
      EXPECT_TRUE(ra.contain(P));
      EXPECT_TRUE(rb.contain(Q));
      EXPECT_GE((P - tf * Q).norm(), d * (1 - tolerance(S(1))));
    }
  }
  EXPECT_GT(positive, 100);
}

TYPED_TEST(RSTest, VolumeIsExactBetweenHullAndBox)
{
  using S = TypeParam;
  auto rng = seededRng("VolumeIsExactBetweenHullAndBox");
  for (int trial = 0; trial < 200; ++trial)
  {
    const auto pts = randomCloud<S>(rng, trial, 6 + trial % 30);
    const RS<S> bv = fitPoints<S>(pts.data(), int(pts.size()));
    std::vector<Eigen::Vector3d> input, corners;
    for (const auto& p : pts) input.push_back(p.template cast<double>());
    for (const auto& c : bv.corners()) corners.push_back(c.template cast<double>());
    const double volume = double(bv.volume());
    // Double volumes store their slabs in float: corners carry a few float ulps of the volume's size.
    const double rel = std::is_same<S, float>::value ? 1e-3 : 1e-6;
    const double box = double(bv.width()) * double(bv.height()) * double(bv.depth());
    EXPECT_LE(volume, box * (1 + rel)) << "trial " << trial;
    // Flat clouds give slabs only a few ulps thick, where qhull's reference is itself noise.
    if (double(bv.depth()) < 1e-3 * double(bv.width())) continue;
    EXPECT_NEAR(volume, hullVolume(corners), rel * box) << "trial " << trial;  // the exact polytope volume
    EXPECT_GE(volume, hullVolume(input) * (1 - rel)) << "trial " << trial;
  }
  // A box with distinct extents, in any pose, is its own RS (the PCA frame is its frame).
  auto box = makeBox<S>(6, 3, 1);
  const fcl::Transform3<S> tf = randomPose<S>(rng, S(5));
  for (auto& v : box.vertices) v = tf * v;
  const RS<S> bv = fitPoints<S>(box.vertices.data(), int(box.vertices.size()));
  EXPECT_NEAR(bv.volume(), S(18), S(std::is_same<S, float>::value ? 1e-3 : 1e-6) * 18);  // float slabs
}

TYPED_TEST(RSTest, CentreAndExtentBallContainsTheVolume)
{
  using S = TypeParam;
  auto rng = seededRng("CentreAndExtentBall");
  for (int trial = 0; trial < 100; ++trial)
  {
    const auto pts = randomCloud<S>(rng, trial, 20);
    const RS<S> bv = fitPoints<S>(pts.data(), int(pts.size()));
    const S radius = fcl::Vector3<S>(bv.width(), bv.height(), bv.depth()).norm() / 2;
    for (const auto& c : bv.corners())
      EXPECT_LE((bv.toModel(c) - bv.center()).norm(), radius * (1 + tolerance(S(1))) + tolerance(bv.magnitude()));
    EXPECT_NEAR(bv.size(), bv.width() * bv.width() + bv.height() * bv.height() + bv.depth() * bv.depth(),
                tolerance(bv.size()));
  }
}

TYPED_TEST(RSTest, PrimitivesGetTheirExactRSInTheirOwnFrame)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  auto rng = seededRng("PrimitivesGetTheirExactRS");
  std::normal_distribution<double> g;
  // Each primitive's farthest point along a unit direction d of its frame.
  const fcl::Box<S> box(S(2), S(0.5), S(1));
  const fcl::Sphere<S> sphere(S(0.7));
  const fcl::Ellipsoid<S> ellipsoid(S(1), S(0.4), S(0.2));
  const fcl::Capsule<S> capsule(S(0.3), S(2));
  const fcl::Cylinder<S> cylinder(S(0.5), S(1.5));
  auto sgn = [](S v) { return v < 0 ? S(-1) : S(1); };
  const std::vector<std::pair<std::string, std::function<V(const V&)>>> farthest = {
      {"box", [&](const V& d) { return V(sgn(d[0]) * 1, sgn(d[1]) * S(0.25), sgn(d[2]) * S(0.5)); }},
      {"sphere", [&](const V& d) { return V(d * S(0.7)); }},
      {"ellipsoid", [&](const V& d) {
         const V a2 = ellipsoid.radii.cwiseProduct(ellipsoid.radii);
         return V(a2.cwiseProduct(d) / d.cwiseProduct(ellipsoid.radii).norm());
       }},
      {"capsule", [&](const V& d) { return V(V(0, 0, sgn(d[2])) + d * S(0.3)); }},
      {"cylinder", [&](const V& d) {
         const S r = std::sqrt(d[0] * d[0] + d[1] * d[1]);
         return r > 0 ? V(S(0.5) * d[0] / r, S(0.5) * d[1] / r, sgn(d[2]) * S(0.75)) : V(0, 0, sgn(d[2]) * S(0.75));
       }},
  };
  for (int trial = 0; trial < 20; ++trial)
  {
    const fcl::Transform3<S> tf = randomPose<S>(rng, S(trial < 10 ? 3 : 3000));
    RS<S> bvs[5];
    fcl::computeBV(box, tf, bvs[0]);
    fcl::computeBV(sphere, tf, bvs[1]);
    fcl::computeBV(ellipsoid, tf, bvs[2]);
    fcl::computeBV(capsule, tf, bvs[3]);
    fcl::computeBV(cylinder, tf, bvs[4]);
    // Fitted once in its own frame and placed at tf (placeShapeRS), a shape has the volume fitted at tf.
    const auto expectPlacedIsFitted = [&](const auto& shape, const RS<S>& fitted) {
      RS<S> own;
      fcl::computeBV(shape, fcl::Transform3<S>::Identity(), own);
      const RS<S> placed = placeShapeRS(own, tf);
      EXPECT_TRUE(placed.axis == fitted.axis && placed.origin == fitted.origin && placed.lo == fitted.lo &&
                  placed.hi == fitted.hi)
          << "trial " << trial;
    };
    expectPlacedIsFitted(box, bvs[0]);
    expectPlacedIsFitted(sphere, bvs[1]);
    expectPlacedIsFitted(ellipsoid, bvs[2]);
    expectPlacedIsFitted(capsule, bvs[3]);
    expectPlacedIsFitted(cylinder, bvs[4]);
    for (int s = 0; s < 5; ++s)
    {
      const RS<S>& bv = bvs[s];
      // Contains the shape's surface ...
      for (int i = 0; i < 200; ++i)
      {
        const V d = fcl::Vector3<double>(g(rng), g(rng), g(rng)).normalized().cast<S>();
        ASSERT_TRUE(bv.contain(tf * farthest[std::size_t(s)].second(d))) << farthest[std::size_t(s)].first << " trial " << trial;
      }
      // ... and each slab touches it: the slab's end is the shape's extreme along that direction.
      for (int k = 0; k < kNumSlabs; ++k)
      {
        const V d = detail::slabDirection<S>(k);
        const S extreme = d.dot(farthest[std::size_t(s)].second(d));
        EXPECT_NEAR(bv.hi[k], extreme, tolerance(S(1)) + tolerance(tf.translation().norm())) << farthest[std::size_t(s)].first << " slab " << k;
        EXPECT_NEAR(bv.lo[k], -extreme, tolerance(S(1)) + tolerance(tf.translation().norm())) << farthest[std::size_t(s)].first << " slab " << k;
      }
    }
  }
}

TYPED_TEST(RSTest, PlaneAndHalfspaceBounds)
{
  using S = TypeParam;
  auto rng = seededRng("PlaneAndHalfspaceBounds");
  const fcl::Transform3<S> tf = randomPose<S>(rng, S(3));
  const fcl::Plane<S> plane(fcl::Vector3<S>(0, 0, 1), S(0.5));
  const fcl::Halfspace<S> half(fcl::Vector3<S>(0, 0, 1), S(0.5));
  RS<S> pb, hb;
  fcl::computeBV(plane, tf, pb);
  fcl::computeBV(half, tf, hb);
  std::uniform_real_distribution<double> u(-100, 100);
  for (int i = 0; i < 100; ++i)
  {
    const fcl::Vector3<S> on_plane = tf * fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(0.5));
    const fcl::Vector3<S> below = tf * fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(0.5 - std::abs(u(rng))));
    EXPECT_TRUE(pb.contain(on_plane));
    EXPECT_TRUE(hb.contain(on_plane));
    EXPECT_TRUE(hb.contain(below));
  }
  // Tight along the normal: the bounded slab is exactly the plane's offset.
  const fcl::Vector3<S> normal = tf.linear().col(2);
  for (const RS<S>* bv : {&pb, &hb})
  {
    EXPECT_NEAR(std::abs(bv->axes().col(0).dot(normal)), S(1), tolerance(S(1)));
    EXPECT_NEAR(bv->hi[0] * bv->axes().col(0).dot(normal), normal.dot(tf * fcl::Vector3<S>(0, 0, S(0.5))), tolerance(S(8)));
  }
  // A plane's slab is as thin as storage allows: a few float ulps.
  const auto up = std::numeric_limits<typename RS<S>::Stored>::infinity();
  EXPECT_LE(pb.hi[0], std::nextafter(std::nextafter(std::nextafter(std::nextafter(pb.lo[0], up), up), up), up));
}

/// Every node of the tree contains every vertex of every triangle below it.
template <typename S>
void expectTreeContainsTriangles(const fcl::BVHModel<RS<S>>& model, const TriangleMesh<S>& mesh)
{
  std::function<std::vector<int>(int)> below = [&](int node) -> std::vector<int> {
    const auto& n = model.getBV(node);
    if (n.isLeaf()) return {n.primitiveId()};
    auto left = below(n.leftChild());
    const auto right = below(n.rightChild());
    left.insert(left.end(), right.begin(), right.end());
    return left;
  };
  for (int i = 0; i < model.getNumBVs(); ++i)
    for (int t : below(i))
      for (int c = 0; c < 3; ++c)
        ASSERT_TRUE(model.getBV(i).bv.contain(mesh.vertices[mesh.triangles[std::size_t(t)][c]]))
            << "node " << i << " triangle " << t;
}

TYPED_TEST(RSTest, TreeNodesContainTheirTrianglesAfterBuildAndRefit)
{
  using S = TypeParam;
  auto rng = seededRng("TreeNodesContainTheirTriangles");
  const auto mesh = makeTorus<S>(S(2), S(0.5), 16, 8);
  for (auto split : {fcl::detail::SPLIT_METHOD_MEAN, fcl::detail::SPLIT_METHOD_MEDIAN, fcl::detail::SPLIT_METHOD_BV_CENTER})
  {
    auto model = buildModel<RS<S>>(mesh, split);
    EXPECT_EQ(model->getNumBVs(), 2 * int(mesh.triangles.size()) - 1);
    expectTreeContainsTriangles(*model, mesh);

    // Deform and refit bottom-up (leaf fits + merges) and top-down (fits only).
    for (bool bottomup : {true, false})
    {
      TriangleMesh<S> moved = mesh;
      std::normal_distribution<double> g(0, 0.1);
      for (auto& v : moved.vertices) v += fcl::Vector3<S>(S(g(rng)), S(g(rng)), S(g(rng)));
      ASSERT_EQ(model->beginUpdateModel(), fcl::BVH_OK);
      for (const auto& v : moved.vertices) model->updateVertex(v);
      ASSERT_EQ(model->endUpdateModel(true, bottomup), fcl::BVH_OK);
      expectTreeContainsTriangles(*model, moved);
    }
  }
}

/// Every node of a and b holds the same volume, bit for bit, and the same primitives.
template <typename S>
void expectSameTree(const fcl::BVHModel<RS<S>>& a, const fcl::BVHModel<RS<S>>& b, const std::string& what)
{
  ASSERT_EQ(a.getNumBVs(), b.getNumBVs()) << what;
  int differ = 0;
  for (int k = 0; k < a.getNumBVs(); ++k)
  {
    const auto &x = a.getBV(k), &y = b.getBV(k);
    differ += !(x.bv.axis == y.bv.axis && x.bv.origin == y.bv.origin && x.bv.lo == y.bv.lo && x.bv.hi == y.bv.hi &&
                x.bv.box_excess == y.bv.box_excess && x.first_child == y.first_child &&
                x.first_primitive == y.first_primitive && x.num_primitives == y.num_primitives);
  }
  EXPECT_EQ(differ, 0) << what << ": nodes that differ";
}

// buildModel's NodeFitter must fit exactly the volumes FCL's own fitter does (FitImpl), on meshes whose
// triangles share vertices and on meshes where each corner is its own vertex, and in a top-down refit after
// a motion (fits of current and previous positions).
TYPED_TEST(RSTest, NodeFitterFitsFCLsVolumesBitForBit)
{
  using S = TypeParam;
  auto rng = seededRng("NodeFitterFitsFCLsVolumes");
  const TriangleMesh<S> shared = makeTorus<S>(S(2), S(0.5), 24, 12);
  TriangleMesh<S> unshared;  // the same surface, every corner its own vertex
  for (const auto& t : shared.triangles)
  {
    const std::size_t v = unshared.vertices.size();
    for (int c = 0; c < 3; ++c) unshared.vertices.push_back(shared.vertices[t[c]]);
    unshared.triangles.emplace_back(v, v + 1, v + 2);
  }
  for (const TriangleMesh<S>* mesh : {&shared, static_cast<const TriangleMesh<S>*>(&unshared)})
  {
    const std::string what = mesh == &shared ? "shared vertices" : "unshared vertices";
    const auto fast = buildModel<RS<S>>(*mesh);
    ASSERT_NE(dynamic_cast<const NodeFitter<S>*>(fast->bv_fitter.get()), nullptr) << "buildModel fits RS with NodeFitter";
    fcl::BVHModel<RS<S>> fcl_fit;
    fcl_fit.bv_splitter = std::make_shared<SurfaceAreaSplitter<S>>();
    ASSERT_EQ(fcl_fit.beginModel(), fcl::BVH_OK);
    ASSERT_EQ(fcl_fit.addSubModel(mesh->vertices, mesh->triangles), fcl::BVH_OK);
    ASSERT_EQ(fcl_fit.endModel(), fcl::BVH_OK);
    expectSameTree(*fast, fcl_fit, what + ", build");

    std::normal_distribution<double> g(0, 0.1);
    std::vector<fcl::Vector3<S>> moved = mesh->vertices;
    for (auto& v : moved) v += fcl::Vector3<S>(S(g(rng)), S(g(rng)), S(g(rng)));
    for (fcl::BVHModel<RS<S>>* model : {fast.get(), static_cast<fcl::BVHModel<RS<S>>*>(&fcl_fit)})
    {
      ASSERT_EQ(model->beginUpdateModel(), fcl::BVH_OK);
      for (const auto& v : moved) model->updateVertex(v);
      ASSERT_EQ(model->endUpdateModel(true, false), fcl::BVH_OK);
    }
    expectSameTree(*fast, fcl_fit, what + ", top-down refit");
    expectTreeContainsTriangles(*fast, TriangleMesh<S>{moved, mesh->triangles});
  }
}

}  // namespace
}  // namespace fcl_rs
