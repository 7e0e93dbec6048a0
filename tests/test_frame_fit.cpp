// Frame fits of RS nodes: containment after refitFrames, collisions against brute force, tessellation
// independence of the area-weighted frame, the convex hull helper.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/bvh/frame_fit.h"
#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

using test::randomPose;
using test::randomRotation;
using test::seededRng;

constexpr FrameFit kFits[] = {FrameFit::kVertices, FrameFit::kTriangleArea, FrameFit::kConvexHull};
constexpr OverlapTest kTests[] = {OverlapTest::kTwoSided, OverlapTest::kOneSided, OverlapTest::kBoxed};

template <typename S>
class FrameFitTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(FrameFitTest, test::Scalars);

/// Triangles with random vertices in a box: overlapping, sliver and needle triangles, no topology.
template <typename S, typename Rng>
TriangleMesh<S> triangleSoup(Rng& rng, int n)
{
  std::uniform_real_distribution<double> u(-1, 1);
  TriangleMesh<S> m;
  for (int i = 0; i < n; ++i)
  {
    const fcl::Vector3<S> base(S(3 * u(rng)), S(u(rng)), S(0.3 * u(rng)));
    for (int c = 0; c < 3; ++c)
      m.vertices.push_back(base + fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) * S(0.4));
    m.triangles.emplace_back(std::size_t(3 * i), std::size_t(3 * i + 1), std::size_t(3 * i + 2));
  }
  return m;
}

/// Meshes that stress frame fits: closed, symmetric (ties), flat, far from the origin, unstructured.
template <typename S, typename Rng>
std::vector<std::pair<std::string, TriangleMesh<S>>> testMeshes(Rng& rng)
{
  const fcl::Transform3<S> far = randomPose<S>(rng, S(1000));
  return {{"torus", makeTorus<S>(S(2), S(0.5), 16, 8)},
          {"rotated box", transformed(makeBox<S>(S(1), S(1), S(1)), randomPose<S>(rng, S(2)))},
          {"diamond", makeDiamond<S>(S(1), S(1.2), 12)},
          {"far ellipsoid", transformed(makeEllipsoid<S>(S(2), S(1), S(0.3), 8, 16), far)},
          {"flat", transformed(makeBox<S>(S(3), S(2), S(0)), randomPose<S>(rng, S(2)))},
          {"soup", triangleSoup<S>(rng, 60)}};
}

template <typename S>
void expectNodesContainTriangles(const fcl::BVHModel<RS<S>>& model, const std::vector<const fcl::Vector3<S>*>& arrays,
                                 const std::string& what)
{
  const std::vector<int> order = primitiveOrder(model);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(sorted.size());
  std::iota(identity.begin(), identity.end(), 0);
  ASSERT_EQ(sorted, identity) << what << ": the primitive order is not a permutation";
  for (int k = 0; k < model.getNumBVs(); ++k)
  {
    const auto& node = model.getBV(k);
    ASSERT_FALSE(node.bv.empty()) << what << " node " << k;
    for (int i = node.first_primitive; i < node.first_primitive + node.num_primitives; ++i)
    {
      const fcl::Triangle& t = model.tri_indices[order[std::size_t(i)]];
      for (const fcl::Vector3<S>* v : arrays)
        for (int c = 0; c < 3; ++c)
          ASSERT_TRUE(node.bv.contain(v[t[c]])) << what << ": node " << k << " misses vertex " << t[c] << " ("
                                                << v[t[c]].transpose() << ")";
    }
  }
}

TYPED_TEST(FrameFitTest, EveryNodeContainsItsTriangles)
{
  using S = TypeParam;
  auto rng = seededRng("EveryNodeContainsItsTriangles");
  for (const auto& [name, mesh] : testMeshes<S>(rng))
    for (FrameFit fit : kFits)
    {
      const std::string what = name + " / " + frameFitName(fit);
      auto model = buildModel<RS<S>>(mesh);
      refitFrames(*model, fit);
      expectNodesContainTriangles<S>(*model, {mesh.vertices.data()}, what);

      // After a motion update the nodes must hold both vertex arrays, as FCL's own fits do.
      TriangleMesh<S> moved = mesh;
      std::normal_distribution<double> g(0, 0.05);
      for (auto& v : moved.vertices) v += fcl::Vector3<S>(S(g(rng)), S(g(rng)), S(g(rng)));
      ASSERT_EQ(model->beginUpdateModel(), fcl::BVH_OK);
      ASSERT_EQ(model->updateSubModel(moved.vertices), fcl::BVH_OK);
      ASSERT_EQ(model->endUpdateModel(), fcl::BVH_OK);
      refitFrames(*model, fit);
      expectNodesContainTriangles<S>(*model, {mesh.vertices.data(), moved.vertices.data()}, what + " after update");
    }
}

TYPED_TEST(FrameFitTest, CollisionsMatchBruteForce)
{
  using S = TypeParam;
  auto rng = seededRng("CollisionsMatchBruteForce");
  struct Pair
  {
    std::string name;
    TriangleMesh<S> a, b;
  };
  const std::vector<Pair> pairs = {
      {"torus x torus", makeTorus<S>(S(1), S(0.3), 16, 8), makeTorus<S>(S(1), S(0.3), 16, 8)},
      {"ellipsoid x diamond", makeEllipsoid<S>(S(1.5), S(0.6), S(0.2), 8, 16), makeDiamond<S>(S(0.8), S(1), 10)},
      {"soup x box", triangleSoup<S>(rng, 50), transformed(makeBox<S>(S(2), S(0.5), S(0.5)), randomPose<S>(rng, S(0.5)))}};
  const fcl::CollisionRequest<S> all(std::numeric_limits<std::size_t>::max(), false);
  for (const Pair& pair : pairs)
    for (FrameFit fit : kFits)
    {
      auto ma = buildModel<RS<S>>(pair.a);
      auto mb = buildModel<RS<S>>(pair.b);
      refitFrames(*ma, fit);
      refitFrames(*mb, fit);
      const S reach = test::meshRadius(pair.a) + test::meshRadius(pair.b);
      int colliding = 0;
      for (int pose = 0; pose < 12; ++pose)
      {
        const fcl::Transform3<S> tf1 = randomPose<S>(rng, S(0.2));
        const fcl::Transform3<S> tf2 = randomPose<S>(rng, S(0.45) * reach);
        const test::TrianglePairs brute = test::bruteForcePairs(pair.a, tf1, pair.b, tf2);
        colliding += !brute.empty();
        for (OverlapTest test : kTests)
        {
          fcl::CollisionResult<S> result;
          collideWithStats(*ma, tf1, *mb, tf2, all, result, test);
          EXPECT_TRUE(test::contactPairs(result) == brute)
              << pair.name << " / " << frameFitName(fit) << " / overlap test " << int(test) << " pose " << pose << ": "
              << test::contactPairs(result).size() << " pairs, brute force " << brute.size();
        }
      }
      EXPECT_GT(colliding, 0) << pair.name << ": no pose collides, the test proves nothing";
    }
}

/// A convex pentagon in the plane z = 0, in two triangulations: a fan from a corner, and a fan from an
/// inner point with one edge cut into many short pieces (which crowds vertices along that edge).
template <typename S>
std::pair<TriangleMesh<S>, TriangleMesh<S>> twoTessellations(const fcl::Transform3<S>& tf)
{
  const std::vector<fcl::Vector3<S>> corners = {{0, 0, 0}, {4, 0, 0}, {5, 1.5, 0}, {2, 2.5, 0}, {-0.5, 1.2, 0}};
  TriangleMesh<S> fan;
  fan.vertices = corners;
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) fan.triangles.emplace_back(0, i, i + 1);

  TriangleMesh<S> fine;
  fine.vertices.push_back(fcl::Vector3<S>(S(2), S(1), S(0)));  // inner point
  for (std::size_t i = 0; i < corners.size(); ++i)
  {
    const fcl::Vector3<S>& p = corners[i];
    const fcl::Vector3<S>& q = corners[(i + 1) % corners.size()];
    const int pieces = i == 0 ? 40 : 1;
    for (int k = 0; k < pieces; ++k) fine.vertices.push_back(p + (q - p) * (S(k) / S(pieces)));
  }
  const std::size_t rim = fine.vertices.size() - 1;
  for (std::size_t i = 1; i <= rim; ++i) fine.triangles.emplace_back(0, i, i % rim + 1);
  return {transformed(fan, tf), transformed(fine, tf)};
}

/// Angle in degrees between two axes (as lines: a and -a are the same axis).
template <typename S>
double axisAngle(const fcl::Vector3<S>& a, const fcl::Vector3<S>& b)
{
  return std::acos(std::min(1.0, std::abs(double(a.normalized().dot(b.normalized()))))) * 180 / M_PI;
}

TYPED_TEST(FrameFitTest, AreaWeightedFrameIgnoresTessellation)
{
  using S = TypeParam;
  auto rng = seededRng("AreaWeightedFrameIgnoresTessellation");
  const double tol_deg = std::is_same<S, float>::value ? 1e-2 : 1e-6;
  // Tree nodes store their frames rounded to RS::Stored: each axis turns by up to sqrt(3) storageEps radians.
  const double stored_deg = 2 * std::sqrt(3.0) * double(detail::storageEps<S>()) * 180 / M_PI;
  for (int trial = 0; trial < 5; ++trial)
  {
    const auto [fan, fine] = twoTessellations<S>(randomPose<S>(rng, S(10)));
    std::array<PrincipalFrame<S>, 2> frame;
    std::array<fcl::Matrix3<S>, 2> root_area, root_vertices;
    const TriangleMesh<S>* meshes[] = {&fan, &fine};
    for (int m = 0; m < 2; ++m)
    {
      auto model = buildModel<RS<S>>(*meshes[m]);
      root_vertices[m] = model->getBV(0).bv.axes();
      refitFrames(*model, FrameFit::kTriangleArea);
      root_area[m] = model->getBV(0).bv.axes();
      const TriangleMesh<S>& mesh = *meshes[m];
      frame[m] = areaWeightedFrame<S>(int(mesh.triangles.size()), [&](int i, int c) -> const fcl::Vector3<S>& {
        return mesh.vertices[mesh.triangles[std::size_t(i)][c]];
      });
    }
    EXPECT_LT((frame[0].mean - frame[1].mean).norm(), S(2e4) * std::numeric_limits<S>::epsilon()) << "trial " << trial;
    for (int axis = 0; axis < 3; ++axis)
    {
      EXPECT_LT(axisAngle<S>(frame[0].axis.col(axis), frame[1].axis.col(axis)), tol_deg) << "trial " << trial;
      EXPECT_LT(axisAngle<S>(root_area[0].col(axis), root_area[1].col(axis)), tol_deg + stored_deg) << "trial " << trial;
    }
    // Vertex PCA follows the crowded edge: its in-plane axes turn.
    EXPECT_GT(axisAngle<S>(root_vertices[0].col(0), root_vertices[1].col(0)), 5.0) << "trial " << trial;
  }
}

TYPED_TEST(FrameFitTest, HullFrameOfConvexMeshIsItsSurfaceFrame)
{
  using S = TypeParam;
  auto rng = seededRng("HullFrameOfConvexMeshIsItsSurfaceFrame");
  // A convex polyhedron's hull surface is its own surface, however qhull triangulates it.
  const TriangleMesh<S> mesh = transformed(makeEllipsoid<S>(S(3), S(1.5), S(0.5), 10, 20), randomPose<S>(rng, S(5)));
  std::vector<Eigen::Vector3d> points;
  for (const auto& v : mesh.vertices) points.push_back(v.template cast<double>());
  const ConvexHull hull = convexHull(points);
  ASSERT_TRUE(hull.solid());
  EXPECT_EQ(hull.vertices.size(), mesh.vertices.size());
  const PrincipalFrame<S> from_hull = hullSurfaceFrame<S>(hull);
  const PrincipalFrame<S> from_mesh = areaWeightedFrame<S>(int(mesh.triangles.size()), [&](int i, int c) -> const fcl::Vector3<S>& {
    return mesh.vertices[mesh.triangles[std::size_t(i)][c]];
  });
  const double tol_deg = std::is_same<S, float>::value ? 1e-2 : 1e-6;
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_LT(axisAngle<S>(from_hull.axis.col(axis), from_mesh.axis.col(axis)), tol_deg);
  EXPECT_LT((from_hull.mean - from_mesh.mean).norm(), S(1e-4));
}

TEST(ConvexHull, VolumeVerticesAndFlatInput)
{
  auto rng = seededRng("ConvexHullVolume");
  std::uniform_real_distribution<double> u(-1, 1);
  const fcl::Matrix3d R = randomRotation<double>(rng);
  const Eigen::Vector3d offset(1e4, -2e4, 5e3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i)
    points.push_back(R * Eigen::Vector3d(i & 1 ? 1.5 : -1.5, i & 2 ? 1 : -1, i & 4 ? 0.25 : -0.25) + offset);
  for (int i = 0; i < 200; ++i)
    points.push_back(R * Eigen::Vector3d(1.5 * u(rng), u(rng), 0.25 * u(rng)) + offset);
  points.push_back(points[3]);  // a repeat
  const ConvexHull hull = convexHull(points);
  ASSERT_TRUE(hull.solid());
  EXPECT_NEAR(hull.volume, 3.0 * 2.0 * 0.5, 1e-9);
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  for (const auto& t : hull.triangles)
    for (int c : t) EXPECT_TRUE(c >= 0 && c < 8);

  // Exactly coplanar points have no solid hull: every distinct point is kept for the caller. (Rounded
  // coplanar points may give qhull a hull of near-zero volume instead.)
  std::vector<Eigen::Vector3d> flat, tilted;
  for (int i = 0; i < 30; ++i)
  {
    flat.push_back(Eigen::Vector3d(u(rng), u(rng), 0) + offset);
    tilted.push_back(R * (flat.back() - offset) + offset);
  }
  flat.push_back(flat.front());
  const ConvexHull flat_hull = convexHull(flat);
  EXPECT_FALSE(flat_hull.solid());
  EXPECT_EQ(flat_hull.volume, 0.0);
  EXPECT_EQ(flat_hull.vertices.size(), 30u);
  EXPECT_LT(convexHull(tilted).volume, 1e-9);

  EXPECT_FALSE(convexHull({Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()}).solid());
  EXPECT_THROW(convexHull({Eigen::Vector3d(0, std::nan(""), 0)}), std::domain_error);
}

TEST(RefitFrames, RejectsModelsThatAreNotBuiltTriangleTrees)
{
  fcl::BVHModel<RSd> empty;
  EXPECT_THROW(refitFrames(empty, FrameFit::kTriangleArea), std::invalid_argument);
  fcl::BVHModel<RSd> cloud;
  cloud.beginModel();
  cloud.addSubModel(std::vector<fcl::Vector3d>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  cloud.endModel();
  EXPECT_THROW(refitFrames(cloud, FrameFit::kConvexHull), std::invalid_argument);
}

}  // namespace
}  // namespace fcl_rs
