// fcl_rs::distance: RS trees against FCL's RSS and OBBRSS trees.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/geometry/shape/triangle_p.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/shape_switch.h"
#include "test_util.h"

namespace {

using fcl_rs::TriangleMesh;
using fcl_rs::test::closeDistances;
using fcl_rs::test::distanceTolerance;
using fcl_rs::test::nearbyPoses;
using fcl_rs::test::scalarName;

/// A mesh with RS, RSS and OBBRSS trees built once, plus the ball (bounding-box centre, radius) used to place it.
template <typename S>
struct Mesh
{
  std::string name;
  TriangleMesh<S> tri;
  fcl::Vector3<S> center;
  S radius = 0;
  std::shared_ptr<fcl::BVHModel<fcl_rs::RS<S>>> rs;
  std::shared_ptr<fcl::BVHModel<fcl::RSS<S>>> rss;
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> obbrss;
};

template <typename S>
Mesh<S> prepare(const std::string& name, TriangleMesh<S> tri)
{
  Mesh<S> m;
  m.name = name;
  fcl::Vector3<S> lo = tri.vertices.front(), hi = lo;
  for (const auto& v : tri.vertices)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  m.center = (lo + hi) / 2;
  for (const auto& v : tri.vertices) m.radius = std::max(m.radius, (v - m.center).norm());
  m.rs = fcl_rs::buildModel<fcl_rs::RS<S>>(tri);
  m.rss = fcl_rs::buildModel<fcl::RSS<S>>(tri);
  m.obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(tri);
  m.tri = std::move(tri);
  return m;
}

template <typename S>
std::optional<Mesh<S>> sharedMesh(const std::string& relative)
{
  const std::string path = fcl_rs::test::sharedData(relative);
  if (path.empty()) return std::nullopt;
  return prepare<S>(relative, fcl_rs::loadMesh<S>(path));
}

#define REQUIRE_SHARED(var, S, relative) FCL_RS_REQUIRE_SHARED(var, relative, sharedMesh<S>(relative))

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
template <typename S>
fcl::Vector3<S> closestOnTriangle(const fcl::Vector3<S>& p, const fcl::Vector3<S>& a, const fcl::Vector3<S>& b,
                                  const fcl::Vector3<S>& c)
{
  const fcl::Vector3<S> ab = b - a, ac = c - a, ap = p - a;
  const S d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const fcl::Vector3<S> bp = p - b;
  const S d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const S vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const fcl::Vector3<S> cp = p - c;
  const S d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const S vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const S va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const S denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Distance from p (model coordinates) to the nearest triangle of the mesh.
template <typename S>
S distanceToMesh(const TriangleMesh<S>& m, const fcl::Vector3<S>& p)
{
  S best = std::numeric_limits<S>::max();
  for (const auto& t : m.triangles)
    best = std::min(best, (p - closestOnTriangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]])).norm());
  return best;
}

template <typename S, typename Geometry1, typename Geometry2>
fcl::DistanceResult<S> fclDistance(const Geometry1* g1, const fcl::Transform3<S>& tf1, const Geometry2* g2,
                                   const fcl::Transform3<S>& tf2, const fcl::DistanceRequest<S>& request)
{
  fcl::DistanceResult<S> r;
  fcl::distance(g1, tf1, g2, tf2, request, r);
  return r;
}

/// The leaf triangles below node i.
template <typename BV>
void subtreeTriangles(const fcl::BVHModel<BV>& m, int i, std::vector<int>& out)
{
  const auto& node = m.getBV(i);
  if (node.isLeaf())
  {
    out.push_back(node.primitiveId());
    return;
  }
  subtreeTriangles(m, node.leftChild(), out);
  subtreeTriangles(m, node.rightChild(), out);
}

/// Nodes from the root down to the leaf of triangle `primitive`.
template <typename BV>
std::vector<int> pathToPrimitive(const fcl::BVHModel<BV>& m, int primitive)
{
  std::vector<int> path;
  std::function<bool(int)> descend = [&](int i) {
    path.push_back(i);
    const auto& node = m.getBV(i);
    if (node.isLeaf() ? node.primitiveId() == primitive : descend(node.leftChild()) || descend(node.rightChild()))
      return true;
    path.pop_back();
    return false;
  };
  descend(0);
  return path;
}

struct DistanceTally
{
  int poses = 0;
  int colliding = 0;
  double max_rel_rss = 0;     // max |d_rs - d_fcl| / max(d, scale) against RSS
  double max_rel_obbrss = 0;  // ... against OBBRSS
  double max_point_off = 0;   // max distance of a nearest point from its mesh, / scale
  int node_pairs = 0;
  double tightness_sum = 0;   // sum over bounded node pairs of traversal bound / true distance
};

/// Mesh-mesh distance on seeded nearby poses: RS == RSS == OBBRSS, nearest points on the meshes and as far
/// apart as the distance, RS lower bounds of root and random node pairs never above the true distance. Two fifths
/// of the poses in the sanitizer build (CI's budget).
template <typename S>
void checkMeshPair(const Mesh<S>& a, const Mesh<S>& b, S spread, int n = fcl_rs::test::kSanitized ? 80 : 200)
{
  const std::string what = "distance/mesh-mesh/" + a.name + "/" + b.name + "/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  const S scale = a.radius + b.radius;
  DistanceTally t;
  int failures = 0;
  for (int i = 0; i < n && failures < 5; ++i)
  {
    const auto [tf1, tf2] = nearbyPoses(rng, a, b, spread, S(2) * scale);
    SCOPED_TRACE(what + " pose #" + std::to_string(i));
    ++t.poses;
    const fcl::DistanceRequest<S> request(/*enable_nearest_points=*/true);
    fcl::DistanceResult<S> rs;
    const S ret = fcl_rs::distance<S>(a.rs.get(), tf1, b.rs.get(), tf2, request, rs);
    const auto rss = fclDistance<S>(a.rss.get(), tf1, b.rss.get(), tf2, request);
    const auto obbrss = fclDistance<S>(a.obbrss.get(), tf1, b.obbrss.get(), tf2, request);
    t.colliding += rss.min_distance <= 0;
    const S d = rs.min_distance;
    t.max_rel_rss = std::max<double>(t.max_rel_rss, std::abs(d - rss.min_distance) / std::max(std::abs(d), scale));
    t.max_rel_obbrss =
        std::max<double>(t.max_rel_obbrss, std::abs(d - obbrss.min_distance) / std::max(std::abs(d), scale));
    bool ok = closeDistances(d, rss.min_distance, scale) && closeDistances(d, obbrss.min_distance, scale) && ret == d;
    EXPECT_EQ(ret, d) << "returned value differs from result.min_distance";
    EXPECT_TRUE(closeDistances(d, rss.min_distance, scale)) << "RS " << d << " vs RSS " << rss.min_distance;
    EXPECT_TRUE(closeDistances(d, obbrss.min_distance, scale)) << "RS " << d << " vs OBBRSS " << obbrss.min_distance;
    EXPECT_TRUE(rs.o1 == a.rs.get() && rs.o2 == b.rs.get());

    // Nearest points: world frame, on the meshes, their distance the reported one (colliding poses report 0
    // and some point pair of the intersecting triangles, as FCL does).
    const S off1 = distanceToMesh(a.tri, fcl::Vector3<S>(tf1.inverse(Eigen::Isometry) * rs.nearest_points[0]));
    const S off2 = distanceToMesh(b.tri, fcl::Vector3<S>(tf2.inverse(Eigen::Isometry) * rs.nearest_points[1]));
    t.max_point_off = std::max<double>(t.max_point_off, std::max(off1, off2) / scale);
    ok &= off1 <= distanceTolerance<S>() * scale && off2 <= distanceTolerance<S>() * scale;
    EXPECT_LE(off1, distanceTolerance<S>() * scale) << "nearest point 0 is not on mesh " << a.name;
    EXPECT_LE(off2, distanceTolerance<S>() * scale) << "nearest point 1 is not on mesh " << b.name;
    if (d > 0)
    {
      const S gap = (rs.nearest_points[0] - rs.nearest_points[1]).norm();
      ok &= closeDistances(gap, d, scale);
      EXPECT_TRUE(closeDistances(gap, d, scale)) << "nearest points are " << gap << " apart, distance " << d;
    }

    // Lower bounds, with (R, T) as the traversal uses them: fcl_rs::distance (the 18 slab directions) and the
    // traversal's distanceLowerBound (also with early exit), against FCL's triangle distance over the subtrees.
    // Node pairs: the roots, random pairs, and the ancestors of the nearest triangle pair (the tight cases).
    const fcl::Transform3<S> rel = tf1.inverse(Eigen::Isometry) * tf2;
    const fcl::Matrix3<S> R = rel.linear();
    const fcl::Vector3<S> T = rel.translation();
    const S true_d = std::max(rss.min_distance, S(0));
    const S slack = 16 * std::numeric_limits<S>::epsilon() * scale;
    const auto check_bounds = [&](int n1, int n2, S truth) {
      const auto& bv1 = a.rs->getBV(n1).bv;
      const auto& bv2 = b.rs->getBV(n2).bv;
      const S slab = fcl_rs::distance<S>(R, T, bv1, bv2);
      const S bound = fcl_rs::distanceLowerBound<S>(R, T, bv1, bv2);
      const S early = fcl_rs::distanceLowerBound<S>(R, T, bv1, bv2, truth);
      ok &= slab <= truth + slack && bound <= truth + slack && early <= truth + slack;
      EXPECT_LE(slab, truth + slack) << "slab bound of nodes " << n1 << ", " << n2 << " exceeds their distance";
      EXPECT_LE(bound, truth + slack) << "traversal bound of nodes " << n1 << ", " << n2 << " exceeds their distance";
      EXPECT_LE(early, truth + slack) << "early-exit bound of nodes " << n1 << ", " << n2 << " exceeds their distance";
      t.tightness_sum += truth > 0 ? double(bound / truth) : 1.0;
    };
    const auto subtree_distance = [&](int n1, int n2) {
      std::vector<int> t1, t2;
      subtreeTriangles(*a.rs, n1, t1);
      subtreeTriangles(*b.rs, n2, t2);
      // Keeps the brute force cheap; small nodes are the tight ones.
      if (t1.size() * t2.size() > 4000) return std::numeric_limits<S>::quiet_NaN();
      S sub = std::numeric_limits<S>::max();
      for (int i1 : t1)
        for (int i2 : t2)
        {
          const auto& x = a.tri.triangles[i1];
          const auto& y = b.tri.triangles[i2];
          fcl::Vector3<S> p, q;
          sub = std::min(sub, fcl::detail::TriangleDistance<S>::triDistance(
                                  a.tri.vertices[x[0]], a.tri.vertices[x[1]], a.tri.vertices[x[2]],
                                  b.tri.vertices[y[0]], b.tri.vertices[y[1]], b.tri.vertices[y[2]], rel, p, q));
        }
      return sub;
    };
    check_bounds(0, 0, true_d);
    std::uniform_int_distribution<int> pick1(0, a.rs->getNumBVs() - 1), pick2(0, b.rs->getNumBVs() - 1);
    std::vector<std::pair<int, int>> node_pairs;
    for (int k = 0; k < 4; ++k) node_pairs.emplace_back(pick1(rng), pick2(rng));
    const auto path1 = pathToPrimitive(*a.rs, rs.b1), path2 = pathToPrimitive(*b.rs, rs.b2);
    for (std::size_t up1 = 0; up1 < 4 && up1 < path1.size(); ++up1)
      for (std::size_t up2 = 0; up2 < 4 && up2 < path2.size(); ++up2)
        node_pairs.emplace_back(path1[path1.size() - 1 - up1], path2[path2.size() - 1 - up2]);
    for (const auto& [n1, n2] : node_pairs)
    {
      const S sub = subtree_distance(n1, n2);
      if (std::isnan(sub)) continue;
      ++t.node_pairs;
      check_bounds(n1, n2, sub);
    }
    failures += !ok;
  }
  std::cout << "[distance] " << what << ": " << t.poses << " poses, " << t.colliding << " colliding, max rel diff vs RSS "
            << t.max_rel_rss << ", vs OBBRSS " << t.max_rel_obbrss << ", max nearest-point offset / scale "
            << t.max_point_off << ", " << t.node_pairs << " node pairs bounded (mean bound / distance "
            << t.tightness_sum / std::max(1, t.node_pairs + t.poses) << ")\n";
  EXPECT_LT(failures, 5) << "stopped " << what << " after 5 failing poses";
  // Guards the test itself: both free and colliding poses.
  EXPECT_GE(t.colliding, 1) << what << ": no colliding pose";
  EXPECT_LE(t.colliding, t.poses * 3 / 4) << what << ": too few free poses";
}

template <typename S>
class DistanceMeshMesh : public ::testing::Test {};
TYPED_TEST_SUITE(DistanceMeshMesh, fcl_rs::test::Scalars);

TYPED_TEST(DistanceMeshMesh, GeneratedShapesMatchRSSAndOBBRSS)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));
  const auto ellipsoid = prepare<S>("ellipsoid", fcl_rs::makeEllipsoid<S>(1, S(0.5), S(0.25)));
  const auto box = prepare<S>("box", fcl_rs::makeBox<S>(1, S(0.4), S(0.2)));
  checkMeshPair(torus, ellipsoid, S(0.8));
  checkMeshPair(box, torus, S(0.8));
  checkMeshPair(ellipsoid, ellipsoid, S(0.8));
}

TYPED_TEST(DistanceMeshMesh, RealMeshesMatchRSSAndOBBRSS)
{
  using S = TypeParam;
  REQUIRE_SHARED(rob, S, "models/fcl_rob.obj");
  REQUIRE_SHARED(link3, S, "robots/panda/meshes/collision/link3.stl");
  REQUIRE_SHARED(hand, S, "robots/panda/meshes/collision/hand.stl");
  checkMeshPair(rob, rob, S(0.8));
  checkMeshPair(link3, hand, S(0.8));
}

TYPED_TEST(DistanceMeshMesh, ErrorBoundsAreHonoured)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));
  const auto ellipsoid = prepare<S>("ellipsoid", fcl_rs::makeEllipsoid<S>(1, S(0.5), S(0.25)));
  auto rng = fcl_rs::test::seededRng("distance/err/" + scalarName<S>());
  const S scale = torus.radius + ellipsoid.radius;
  for (int i = 0; i < 100; ++i)
  {
    const auto [tf1, tf2] = nearbyPoses(rng, torus, ellipsoid, S(1.5), scale);
    const S exact = fclDistance<S>(torus.rss.get(), tf1, ellipsoid.rss.get(), tf2, fcl::DistanceRequest<S>()).min_distance;
    fcl::DistanceRequest<S> rel_req(false, false, /*rel_err=*/S(0.3)), abs_req(false, false, 0, /*abs_err=*/S(0.2));
    fcl::DistanceResult<S> rel_res, abs_res;
    fcl_rs::distance<S>(torus.rs.get(), tf1, ellipsoid.rs.get(), tf2, rel_req, rel_res);
    fcl_rs::distance<S>(torus.rs.get(), tf1, ellipsoid.rs.get(), tf2, abs_req, abs_res);
    const S slack = distanceTolerance<S>() * scale;
    EXPECT_GE(rel_res.min_distance, exact - slack);
    EXPECT_LE(rel_res.min_distance, S(1.3) * exact + slack);
    EXPECT_GE(abs_res.min_distance, exact - slack);
    EXPECT_LE(abs_res.min_distance, exact + S(0.2) + slack);
  }
}

/// A point uniform in [-scale, scale]^3.
template <typename S, typename Rng>
fcl::Vector3<S> randomPoint(Rng& rng, S scale)
{
  std::uniform_real_distribution<double> u(-1, 1);
  return fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) * scale;
}

/// A unit vector tilted from d by about `tilt` radians (0: d itself), seeded.
template <typename S, typename Rng>
Eigen::Vector3d tilted(Rng& rng, const fcl::Vector3<S>& d, double tilt)
{
  std::normal_distribution<double> g;
  const Eigen::Vector3d unit = d.template cast<double>().normalized();
  return (unit + tilt * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
}

// distanceAlong (no descent) gives distanceTrees's answer to the bit whenever it answers: on seeded nearby poses of
// convex (ellipsoid, box) and non-convex (torus) meshes, along the nearest points' direction, tilted ones and a
// random one, starting from no distance, from above and from below the answer. Along the nearest points'
// direction it answers for most free poses of the convex pairs, so the comparison is not vacuous.
TYPED_TEST(DistanceMeshMesh, DistanceAlongAGapDirectionIsTheTraversals)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));
  const auto ellipsoid = prepare<S>("ellipsoid", fcl_rs::makeEllipsoid<S>(1, S(0.5), S(0.25)));
  const auto box = prepare<S>("box", fcl_rs::makeBox<S>(1, S(0.4), S(0.2)));
  for (const auto& [a, b, convex] : {std::make_tuple(&ellipsoid, &box, true), std::make_tuple(&ellipsoid, &ellipsoid, true),
                                     std::make_tuple(&torus, &ellipsoid, false)})
  {
    const std::string what = "distance/along/" + a->name + "/" + b->name + "/" + scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    int free_poses = 0, answered_along_gap = 0;
    for (int i = 0; i < 40; ++i)
    {
      SCOPED_TRACE(what + " pose #" + std::to_string(i));
      const auto [tf1, tf2] = nearbyPoses(rng, *a, *b, S(0.8), S(2) * (a->radius + b->radius));
      const fcl::DistanceRequest<S> request(/*enable_nearest_points=*/true);
      fcl::DistanceResult<S> reference;
      fcl_rs::distance<S>(a->rs.get(), tf1, b->rs.get(), tf2, request, reference);
      if (!(reference.min_distance > 0)) continue;
      ++free_poses;
      const fcl::Vector3<S> gap = reference.nearest_points[1] - reference.nearest_points[0];
      for (const double tilt : {0.0, 0.01, 0.3, 10.0})
      {
        const Eigen::Vector3d direction = tf1.linear().template cast<double>().transpose() * tilted(rng, gap, tilt);
        for (const S start : {std::numeric_limits<S>::max(), S(1.5) * reference.min_distance,
                              S(0.5) * reference.min_distance})
        {
          fcl::DistanceResult<S> result;
          result.min_distance = start;
          fcl_rs::MeshDistanceTraversalNodeRS<S> node;
          fcl_rs::initialize(node, *a->rs, tf1, *b->rs, tf2, request, result);
          if (!fcl_rs::distanceAlong(node, direction)) continue;
          node.postprocess();
          answered_along_gap += tilt == 0 && start == std::numeric_limits<S>::max();
          EXPECT_EQ(result.min_distance, std::min(start, reference.min_distance)) << "tilt " << tilt << ", start " << start;
          if (start > reference.min_distance)
          {
            EXPECT_NEAR((result.nearest_points[1] - result.nearest_points[0]).norm(), result.min_distance,
                        distanceTolerance<S>() * (a->radius + b->radius));
          }
        }
      }
    }
    std::cout << "[distance] " << what << ": " << free_poses << " free poses, " << answered_along_gap
              << " answered along the nearest points' direction\n";
    EXPECT_GE(free_poses, 10) << what;
    if (convex)
    {
      EXPECT_GE(answered_along_gap, free_poses / 2) << what;
    }
  }
}

// The traversal's leaf filter (distance_traversal.h) skips a triangle pair only when its exact distance reaches the
// given distance, and skips pairs apart along their centroids' line; pairs far from the origin stress its rounding.
TYPED_TEST(DistanceMeshMesh, LeafFilterSkipsOnlyPairsThatCannotImprove)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  auto rng = fcl_rs::test::seededRng("distance/leaf-filter/" + scalarName<S>());
  const auto point = [&](S scale) { return randomPoint(rng, scale); };
  int separated = 0, skipped_at_half = 0;
  for (int i = 0; i < 4000; ++i)
  {
    const S far = i % 2 ? S(0) : S(1000);  // the pair's place: at the origin or 1000 away
    const V base = point(far), offset = point(S(3));
    V p[3], q[3];
    for (int k = 0; k < 3; ++k)
    {
      p[k] = base + point(S(1));
      q[k] = base + offset + point(i % 3 ? S(1) : S(0.01));  // some slivers
    }
    V P, Q;
    const S exact = fcl::detail::TriangleDistance<S>::triDistance(p, q, P, Q);
    // The exact distance as FCL computes it carries its own rounding, of the coordinates' size.
    const S slack = 64 * std::numeric_limits<S>::epsilon() * (far + 4);
    EXPECT_FALSE(fcl_rs::leafCannotImprove(p, q, exact + slack))
        << "skipped a pair " << exact << " apart for a distance " << exact + slack << " (pair " << i << ")";
    if (exact > 4 * slack)
    {
      ++separated;
      skipped_at_half += fcl_rs::leafCannotImprove(p, q, exact / 2);
    }
  }
  {
    const S nan = std::numeric_limits<S>::quiet_NaN();
    const V p[3] = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}, q[3] = {V(0, 0, 5), V(1, 0, nan), V(0, 1, 5)};
    EXPECT_FALSE(fcl_rs::leafCannotImprove(p, q, S(1))) << "a NaN vertex must leave the pair to the exact test";
  }
  // Not vacuous: most separated pairs are at least half their distance apart along the centroids' line.
  EXPECT_GT(skipped_at_half, separated / 2) << skipped_at_half << " of " << separated << " separated pairs skipped";
}

// The traversal's bound measures its exact gap along the (unnormalised) line through the box centres and divides
// once: on two single-triangle volumes the bound is at most the triangles' distance (the volumes contain them),
// near the origin and 1000 away, at node sizes from 1e-3 to 1, and close to it when the triangles face each other.
TYPED_TEST(DistanceMeshMesh, TraversalBoundOfTriangleVolumesStaysBelowTheirDistance)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  auto rng = fcl_rs::test::seededRng("distance/traversal-bound/" + scalarName<S>());
  int separated = 0, tight = 0;
  for (int i = 0; i < 2000; ++i)
  {
    const S far = i % 2 ? S(0) : S(1000), size = i % 3 == 0 ? S(1e-3) : i % 3 == 1 ? S(0.1) : S(1);
    const fcl::Matrix3<S> R = fcl_rs::test::randomRotation<S>(rng);
    const V T = randomPoint(rng, far);
    V p[3], q[3], moved[3];
    const V base1 = randomPoint(rng, far), base2 = R.transpose() * (base1 + randomPoint(rng, S(4) * size) - T);
    for (int k = 0; k < 3; ++k)
    {
      p[k] = base1 + randomPoint(rng, size);
      q[k] = base2 + randomPoint(rng, size);
      moved[k] = R * q[k] + T;
    }
    const fcl_rs::RS<S> b1 = fcl_rs::fitPoints<S>(p, 3), b2 = fcl_rs::fitPoints<S>(q, 3);
    V P, Q;
    const S exact = fcl::detail::TriangleDistance<S>::triDistance(p, moved, P, Q);
    // FCL's distance of the moved triangles carries the rounding of coordinates of the pair's place.
    const S slack = 64 * std::numeric_limits<S>::epsilon() * (far + 4 * size);
    const S bound = fcl_rs::distanceLowerBound<S>(R, T, b1, b2);
    EXPECT_LE(bound, exact + slack) << "bound " << bound << " above the triangles' distance (pair " << i << ")";
    EXPECT_LE(fcl_rs::distanceLowerBound<S>(R, T, b1, b2, exact / 2), exact + slack) << "early exit, pair " << i;
    if (exact > size)
    {
      ++separated;
      tight += bound >= exact / 2;
    }
  }
  // Not vacuous: most clearly separated pairs are bounded within half their distance.
  EXPECT_GT(tight, separated / 2) << tight << " of " << separated << " separated pairs bounded within half";
}

/// Every bounded shape FCL measures against a mesh (planes and halfspaces: PlaneAndHalfspace below).
template <typename S>
std::vector<std::pair<std::string, std::shared_ptr<fcl::CollisionGeometry<S>>>> shapes()
{
  return {
      {"box", std::make_shared<fcl::Box<S>>(S(0.6), S(0.3), S(0.2))},
      {"sphere", std::make_shared<fcl::Sphere<S>>(S(0.3))},
      {"ellipsoid", std::make_shared<fcl::Ellipsoid<S>>(S(0.4), S(0.2), S(0.1))},
      {"capsule", std::make_shared<fcl::Capsule<S>>(S(0.1), S(0.6))},
      {"cone", std::make_shared<fcl::Cone<S>>(S(0.2), S(0.5))},
      {"cylinder", std::make_shared<fcl::Cylinder<S>>(S(0.2), S(0.5))},
  };
}

template <typename S>
class DistanceMeshShape : public ::testing::Test {};
TYPED_TEST_SUITE(DistanceMeshShape, fcl_rs::test::Scalars);

/// The smallest leaf distance over all of the mesh's triangles (TriangleShapeLeaf, judged against the exact oracle
/// in test_triangle_shape.cpp), -1 if any triangle meets the shape: what the traversal must find.
template <typename S>
S bruteForceLeafDistance(const TriangleMesh<S>& mesh, const fcl::Transform3<S>& tf1,
                         const fcl::CollisionGeometry<S>& shape, const fcl::Transform3<S>& tf2)
{
  const auto over = [&](const auto& typed) -> S {
    using Shape = std::decay_t<decltype(typed)>;
    if constexpr (std::is_same_v<Shape, fcl::TriangleP<S>>)
      throw std::invalid_argument("bruteForceLeafDistance: a TriangleP has no mesh-shape leaf test");
    else
    {
      const fcl_rs::TriangleShapeLeaf<Shape> leaf(typed, tf1, tf2);
      S best = std::numeric_limits<S>::max();
      for (const auto& t : mesh.triangles)
      {
        const fcl::Vector3<S> p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        fcl::Vector3<S> a, b;
        const S d = leaf.distance(p, a, b);
        if (d < 0) return S(-1);
        best = std::min(best, d);
      }
      return best;
    }
  };
  return fcl_rs::detail::withShape(shape, over, []() -> S {
    throw std::invalid_argument("bruteForceLeafDistance: not a primitive shape");
  });
}

/// Both argument orders give the leaves' minimum over the whole mesh exactly (the traversal prunes nothing it
/// needs), -1 exactly when fcl_rs::collide reports the pair, nearest points that realise the distance (point 0 on
/// the mesh, point 1 on the sphere for the sphere). FCL's RSS answer (its GJK leaves) is only logged: libccd's and
/// GJKSolver_indep's tolerances put it up to 1e-6 off here (docs/distance.md).
TYPED_TEST(DistanceMeshShape, BothOrdersFindTheNearestLeaf)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));
  for (const auto solver : {fcl::GST_LIBCCD, fcl::GST_INDEP})
    for (const auto& [name, shape] : shapes<S>())
    {
      const std::string what = "distance/mesh-shape/torus/" + name + "/solver" + std::to_string(int(solver)) + "/" +
                               scalarName<S>();
      auto rng = fcl_rs::test::seededRng(what);
      const bool sphere = name == "sphere";
      int colliding = 0;
      double max_rss = 0, max_off = 0;
      for (int i = 0; i < 40; ++i)
      {
        SCOPED_TRACE(what + " pose #" + std::to_string(i));
        const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
        fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, S(1.6));
        tf2.translation() += tf1.translation();
        fcl::DistanceRequest<S> request(true);
        request.gjk_solver_type = solver;
        const S scale = 2;
        fcl::CollisionResult<S> contact;
        fcl::CollisionRequest<S> collision_request;
        collision_request.gjk_solver_type = solver;
        fcl_rs::collide<S>(torus.rs.get(), tf1, shape.get(), tf2, collision_request, contact);
        colliding += contact.isCollision();
        const S brute = bruteForceLeafDistance(torus.tri, tf1, *shape, tf2);
        for (const bool mesh_first : {true, false})
        {
          SCOPED_TRACE(mesh_first ? "mesh first" : "shape first");
          fcl::DistanceResult<S> rs;
          if (mesh_first)
            fcl_rs::distance<S>(torus.rs.get(), tf1, shape.get(), tf2, request, rs);
          else
            fcl_rs::distance<S>(shape.get(), tf2, torus.rs.get(), tf1, request, rs);
          // As in FCL, the mesh is always result.o1, whichever order it was given in.
          EXPECT_EQ(rs.o1, torus.rs.get());
          EXPECT_EQ(rs.o2, shape.get());
          EXPECT_EQ(rs.min_distance <= 0, contact.isCollision()) << "distance " << rs.min_distance;
          // A sphere that meets the mesh reports 0 (FCL's sphere-triangle convention, fcl_rs/traversal), others -1.
          EXPECT_EQ(rs.min_distance, sphere && brute < 0 ? S(0) : brute);
          if (rs.min_distance <= 0) continue;
          const auto rss = mesh_first ? fclDistance<S>(torus.rss.get(), tf1, shape.get(), tf2, request)
                                      : fclDistance<S>(shape.get(), tf2, torus.rss.get(), tf1, request);
          if (rss.min_distance > 0) max_rss = std::max<double>(max_rss, std::abs(rs.min_distance - rss.min_distance) / scale);
          // Nearest points, world frame: as far apart as the distance, point 0 on the mesh, point 1 on the sphere.
          const S tol = 16 * std::numeric_limits<S>::epsilon() * scale;
          const S off = distanceToMesh(torus.tri, fcl::Vector3<S>(tf1.inverse(Eigen::Isometry) * rs.nearest_points[0]));
          max_off = std::max<double>(max_off, off / scale);
          EXPECT_LE(off, tol) << "nearest point 0 is not on the mesh";
          EXPECT_NEAR((rs.nearest_points[0] - rs.nearest_points[1]).norm(), rs.min_distance, tol);
          if (sphere)
          {
            EXPECT_NEAR((rs.nearest_points[1] - tf2.translation()).norm(), S(0.3), tol) << "nearest point 1 is not on the sphere";
          }
        }
      }
      std::cout << "[distance] " << what << ": 40 poses, " << colliding << " colliding, max |RS - FCL's RSS| / scale "
                << max_rss << ", max offset of nearest point 0 from the mesh / scale " << max_off << "\n";
      EXPECT_GE(colliding, 1) << what << ": no colliding pose";
      EXPECT_LE(colliding, 38) << what << ": too few free poses";
    }
}

// distanceAlong for a mesh and a shape (box, sphere, capsule, cylinder; the others have no closed-form support and
// are refused) gives distanceMeshShape's answer to the bit whenever it answers, as for meshes above; seeded poses of
// an ellipsoid mesh about each shape, along the nearest points' direction, a tilted one and a random one.
TYPED_TEST(DistanceMeshShape, DistanceAlongAGapDirectionIsTheTraversals)
{
  using S = TypeParam;
  using Solver = fcl::detail::GJKSolver_libccd<S>;
  const auto ellipsoid = prepare<S>("ellipsoid", fcl_rs::makeEllipsoid<S>(1, S(0.5), S(0.25)));
  for (const auto& [name, shape] : shapes<S>())
  {
    const std::string what = "distance/along/ellipsoid/" + name + "/" + scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    const bool closed_form = name == "box" || name == "sphere" || name == "capsule" || name == "cylinder";
    int free_poses = 0, answered_along_gap = 0;
    for (int i = 0; i < 30; ++i)
    {
      SCOPED_TRACE(what + " pose #" + std::to_string(i));
      const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
      fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, S(1.6));
      tf2.translation() += tf1.translation();
      const fcl::DistanceRequest<S> request(/*enable_nearest_points=*/true);
      fcl::DistanceResult<S> reference;
      fcl_rs::distance<S>(ellipsoid.rs.get(), tf1, shape.get(), tf2, request, reference);
      if (!(reference.min_distance > 0)) continue;
      ++free_poses;
      const fcl::Vector3<S> gap = reference.nearest_points[1] - reference.nearest_points[0];
      for (const double tilt : {0.0, 0.3, 10.0})
      {
        const Eigen::Vector3d direction = tf2.linear().template cast<double>().transpose() * tilted(rng, gap, tilt);
        const bool answered = fcl_rs::detail::withShape(
            *shape,
            [&](const auto& geometry) {
              using Shape = std::decay_t<decltype(geometry)>;
              if constexpr (std::is_same_v<Shape, fcl::TriangleP<S>> || std::is_same_v<Shape, fcl::Plane<S>> ||
                            std::is_same_v<Shape, fcl::Halfspace<S>>)
                return false;
              else
              {
                Solver solver;
                fcl::DistanceResult<S> result;
                fcl_rs::MeshShapeDistanceTraversalNodeRS<Shape, Solver> node;
                fcl_rs::initialize(node, *ellipsoid.rs, tf1, geometry, tf2, &solver, request, result);
                if (!fcl_rs::distanceAlong(node, direction)) return false;
                EXPECT_EQ(result.min_distance, reference.min_distance) << "tilt " << tilt;
                EXPECT_NEAR((result.nearest_points[1] - result.nearest_points[0]).norm(), result.min_distance,
                            16 * std::numeric_limits<S>::epsilon() * 2);
                return true;
              }
            },
            []() { return false; });
        EXPECT_TRUE(closed_form || !answered) << "a shape without a closed-form support was measured along";
        answered_along_gap += answered && tilt == 0;
      }
    }
    std::cout << "[distance] " << what << ": " << free_poses << " free poses, " << answered_along_gap
              << " answered along the nearest points' direction\n";
    EXPECT_GE(free_poses, 10) << what;
    if (closed_form)
    {
      EXPECT_GE(answered_along_gap, free_poses / 2) << what;
    }
  }
}

/// Signed distance: free poses as the unsigned distance; colliding ones minus the deepest penetration over all
/// contacts. Box: the contacts' depths come from FCL's own triangle-box test (GJKSolver_indep's are negative
/// numbers, hence magnitudes), so RS must equal minus the deepest of FCL's RSS contacts, and FCL's own answer
/// (minus the first contact's depth) can only be shallower. Sphere: FCL's depths are negative and its signed
/// distance undefined, so the oracle is geometric: no triangle is deeper than the sphere's radius minus the
/// distance from its centre to the mesh.
TYPED_TEST(DistanceMeshShape, SignedDistanceIsTheDeepestContact)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));
  const S radius = S(0.3);
  const fcl::Sphere<S> sphere(radius);
  const fcl::Box<S> box(S(0.6), S(0.3), S(0.2));
  const S tol = distanceTolerance<S>() * 2;
  for (const auto solver : {fcl::GST_LIBCCD, fcl::GST_INDEP})
  {
    const std::string what = "distance/signed/solver" + std::to_string(int(solver)) + "/" + scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    fcl::DistanceRequest<S> request(true, /*enable_signed_distance=*/true);
    request.gjk_solver_type = solver;
    fcl::CollisionRequest<S> all_contacts(std::numeric_limits<std::size_t>::max(), /*enable_contact=*/true);
    all_contacts.gjk_solver_type = solver;
    int negative_box = 0, negative_sphere = 0, exact_sphere = 0, fcl_shallower = 0;
    for (int i = 0; i < 100; ++i)
    {
      SCOPED_TRACE(what + " pose #" + std::to_string(i));
      const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
      fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, S(1.2));
      tf2.translation() += tf1.translation();

      // FCL's own signed answer only with libccd: with GJKSolver_indep all its depths are negative, and FCL's
      // search for the deepest contact then fails its assertion (double) or reads past the list (float).
      const bool fcl_signed = solver == fcl::GST_LIBCCD;
      fcl::DistanceRequest<S> rss_request = request;
      rss_request.enable_signed_distance = fcl_signed;
      fcl::DistanceResult<S> rs_box, rss_box;
      fcl_rs::distance<S>(&box, tf2, torus.rs.get(), tf1, request, rs_box);
      fcl::distance(torus.rss.get(), tf1, &box, tf2, rss_request, rss_box);
      fcl::CollisionResult<S> contacts;
      fcl::collide(torus.rss.get(), tf1, &box, tf2, all_contacts, contacts);
      if (contacts.isCollision())
      {
        ++negative_box;
        S deepest = 0;
        for (std::size_t c = 0; c < contacts.numContacts(); ++c)
          deepest = std::max(deepest, std::abs(contacts.getContact(c).penetration_depth));
        EXPECT_TRUE(closeDistances(rs_box.min_distance, -deepest, S(1))) << "RS " << rs_box.min_distance << ", deepest " << deepest;
        EXPECT_EQ(rs_box.nearest_points[0], rs_box.nearest_points[1]);
        if (fcl_signed)
        {
          EXPECT_GE(rss_box.min_distance, rs_box.min_distance - tol) << "FCL's first contact is deeper than all";
          fcl_shallower += rss_box.min_distance > rs_box.min_distance + tol;
        }
      }
      else
      {
        EXPECT_GT(rs_box.min_distance, 0);
        // RSS's box leaves are FCL's GJK: libccd's to its tolerance; GJKSolver_indep's box-triangle distances can be
        // far off (percents), but never below the true distance, which RS's exact leaves give.
        if (solver == fcl::GST_LIBCCD)
        {
          EXPECT_TRUE(closeDistances(rs_box.min_distance, rss_box.min_distance, S(2)))
              << "RS " << rs_box.min_distance << " vs RSS " << rss_box.min_distance;
        }
        else
        {
          EXPECT_LE(rs_box.min_distance, rss_box.min_distance + tol) << "RS above GJKSolver_indep's distance";
        }
      }

      fcl::DistanceResult<S> rs_sphere;
      fcl_rs::distance<S>(torus.rs.get(), tf1, &sphere, tf2, request, rs_sphere);
      const S centre_to_mesh = distanceToMesh(torus.tri, fcl::Vector3<S>(tf1.inverse(Eigen::Isometry) * tf2.translation()));
      if (centre_to_mesh < radius)
      {
        ++negative_sphere;
        EXPECT_LE(rs_sphere.min_distance, 0);
        EXPECT_GE(rs_sphere.min_distance, centre_to_mesh - radius - tol) << "deeper than the sphere reaches";
        exact_sphere += rs_sphere.min_distance <= centre_to_mesh - radius + tol;
      }
      else
      {
        EXPECT_NEAR(rs_sphere.min_distance, centre_to_mesh - radius, tol);
      }
    }
    std::cout << "[distance] " << what << ": 100 poses; box: " << negative_box << " negative, FCL's own answer shallower in "
              << fcl_shallower << "; sphere: " << negative_sphere << " negative, " << exact_sphere
              << " of them exactly radius - centre distance\n";
    EXPECT_GE(negative_box, 5);
    EXPECT_GE(negative_sphere, 5);
  }
}

/// The README's quick start: a tetrahedron against a 0.5 box centred at (2, 0, 0) is 0.75 apart (vertex (1, 0, 0) to
/// the face x = 1.75), with either solver (FCL's libccd GJK says 0.829), and the nearest points realise it.
TYPED_TEST(DistanceMeshShape, QuickStartTetrahedronIsThreeQuartersFromTheBox)
{
  using S = TypeParam;
  TriangleMesh<S> tetra;
  tetra.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const auto mesh = prepare<S>("tetrahedron", tetra);
  const fcl::Box<S> box(S(0.5), S(0.5), S(0.5));
  fcl::Transform3<S> at = fcl::Transform3<S>::Identity();
  at.translation() << 2, 0, 0;
  for (const auto solver : {fcl::GST_LIBCCD, fcl::GST_INDEP})
  {
    fcl::DistanceRequest<S> request(true);
    request.gjk_solver_type = solver;
    fcl::DistanceResult<S> result;
    fcl_rs::distance<S>(mesh.rs.get(), fcl::Transform3<S>::Identity(), &box, at, request, result);
    EXPECT_EQ(result.min_distance, S(0.75)) << "solver " << int(solver);
    EXPECT_EQ(result.nearest_points[0], fcl::Vector3<S>(1, 0, 0));
    EXPECT_EQ(result.nearest_points[1].x(), S(1.75));
    EXPECT_EQ((result.nearest_points[1] - result.nearest_points[0]).norm(), S(0.75));
  }
}

/// A plane or halfspace in the world frame (|n| = 1), its heights n . x - d taken in long double of world vertices
/// computed in long double: the closed form the traversal is judged against, independent of the leaf and the bound.
template <typename S>
struct WorldPlane
{
  Eigen::Matrix<long double, 3, 1> n;
  long double d;

  WorldPlane(const fcl::Vector3<S>& n_local, S d_local, const fcl::Transform3<S>& tf)
    : n(tf.linear().template cast<long double>() * n_local.template cast<long double>()),
      d(d_local + n.dot(tf.translation().template cast<long double>()))
  {
  }
  long double height(const fcl::Vector3<S>& world) const { return n.dot(world.template cast<long double>()) - d; }
  /// The heights of the mesh's vertices at tf.
  std::vector<long double> heights(const TriangleMesh<S>& m, const fcl::Transform3<S>& tf) const
  {
    const Eigen::Matrix<long double, 3, 3> R = tf.linear().template cast<long double>();
    const Eigen::Matrix<long double, 3, 1> t = tf.translation().template cast<long double>();
    std::vector<long double> h;
    for (const auto& v : m.vertices) h.push_back(n.dot(R * v.template cast<long double>() + t) - d);
    return h;
  }
};

/// The closed forms: a halfspace's distance is the lowest vertex height (minus the penetration depth when negative);
/// a plane's the smallest |height| when every vertex is on one side. Plane penetration as FCL's triangle-plane test
/// measures it: per straddling triangle the smaller of its deepest heights on the two sides, the largest of those.
template <typename Shape, typename S>
long double closedFormDistance(const TriangleMesh<S>& m, const std::vector<long double>& h)
{
  const long double lo = *std::min_element(h.begin(), h.end()), hi = *std::max_element(h.begin(), h.end());
  if (std::is_same<Shape, fcl::Halfspace<S>>::value) return lo;
  if (lo > 0 || hi < 0) return std::min(std::abs(lo), std::abs(hi));
  long double deepest = 0;
  for (const auto& t : m.triangles)
  {
    long double above = 0, below = 0;
    for (int k = 0; k < 3; ++k) above = std::max(above, h[t[k]]), below = std::max(below, -h[t[k]]);
    deepest = std::max(deepest, std::min(above, below));
  }
  return -deepest;
}

template <typename S>
class DistancePlaneAndHalfspace : public ::testing::Test
{
protected:
  const Mesh<S> torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));

  /// Both orders and both solvers at (tf1, the shape at tf2): the traversal's distance is the leaves' minimum over
  /// all triangles exactly, negative (-1) exactly when fcl_rs::collide reports the pair; a positive one is the
  /// closed form's, with nearest points on the mesh and on the plane that realise it; the signed distance is the
  /// closed form's. Returns the closed form.
  template <typename Shape>
  long double check(const Shape& shape, const fcl::Transform3<S>& tf1, const fcl::Transform3<S>& tf2,
                    fcl::GJKSolverType solver)
  {
    const WorldPlane<S> plane(shape.n, shape.d, tf2);
    const long double expected = closedFormDistance<Shape>(torus.tri, plane.heights(torus.tri, tf1));
    const S scale = 4, tol = distanceTolerance<S>() * scale;
    fcl::CollisionRequest<S> collision_request;
    collision_request.gjk_solver_type = solver;
    fcl::CollisionResult<S> contact;
    fcl_rs::collide<S>(torus.rs.get(), tf1, &shape, tf2, collision_request, contact);
    const S brute = bruteForceLeafDistance(torus.tri, tf1, shape, tf2);
    for (const bool mesh_first : {true, false})
    {
      SCOPED_TRACE(mesh_first ? "mesh first" : "shape first");
      fcl::DistanceRequest<S> request(true);
      request.gjk_solver_type = solver;
      fcl::DistanceResult<S> r;
      if (mesh_first)
        fcl_rs::distance<S>(torus.rs.get(), tf1, &shape, tf2, request, r);
      else
        fcl_rs::distance<S>(&shape, tf2, torus.rs.get(), tf1, request, r);
      EXPECT_EQ(r.o1, torus.rs.get());
      EXPECT_EQ(r.o2, &shape);
      EXPECT_EQ(r.min_distance, brute);
      EXPECT_EQ(r.min_distance < 0, contact.isCollision()) << "distance " << r.min_distance;
      if (r.min_distance < 0)
      {
        EXPECT_EQ(r.min_distance, S(-1));
        EXPECT_LE(expected, tol) << "a meeting reported " << double(expected) << " away";
      }
      else
      {
        EXPECT_NEAR(double(r.min_distance), double(expected), double(tol));
        EXPECT_LE(distanceToMesh(torus.tri, fcl::Vector3<S>(tf1.inverse(Eigen::Isometry) * r.nearest_points[0])), tol)
            << "nearest point 0 is not on the mesh";
        EXPECT_NEAR(double(plane.height(r.nearest_points[1])), 0.0, double(tol)) << "nearest point 1 is not on the plane";
        EXPECT_NEAR((r.nearest_points[0] - r.nearest_points[1]).norm(), r.min_distance, tol);
      }
      request.enable_signed_distance = true;
      fcl::DistanceResult<S> signed_result;
      if (mesh_first)
        fcl_rs::distance<S>(torus.rs.get(), tf1, &shape, tf2, request, signed_result);
      else
        fcl_rs::distance<S>(&shape, tf2, torus.rs.get(), tf1, request, signed_result);
      if (signed_result.min_distance > 0 || expected > tol)
      {
        EXPECT_EQ(signed_result.min_distance, r.min_distance);
      }
      else
      {
        EXPECT_NEAR(double(signed_result.min_distance), double(expected), double(tol)) << "signed";
      }
    }
    return expected;
  }
};
TYPED_TEST_SUITE(DistancePlaneAndHalfspace, fcl_rs::test::Scalars);

/// Seeded poses: the torus (radius 1.25) at a random pose, the plane or halfspace with a random normal at a height
/// within 1.7 of its centre (the halfspace mostly below it), crossing it or apart, both solvers.
TYPED_TEST(DistancePlaneAndHalfspace, SeededPosesMatchTheClosedForm)
{
  using S = TypeParam;
  const auto run = [&](const auto* kind, const char* name, double lowest, double highest) {
    using Shape = std::decay_t<decltype(*kind)>;
    const std::string what = std::string("distance/plane-halfspace/") + name + "/" + scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    std::uniform_real_distribution<double> height(lowest, highest);
    int crossing = 0, apart = 0;
    for (int i = 0; i < 24; ++i)
    {
      SCOPED_TRACE(what + " pose #" + std::to_string(i));
      const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
      fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, S(1));
      tf2.translation() += tf1.translation();
      const fcl::Vector3<S> n = fcl_rs::test::randomRotation<S>(rng).col(0);
      // The local offset that puts the plane at the drawn height above the torus's centre.
      const S n_world_dot = (tf2.linear() * n).dot(tf2.translation() - tf1.translation());
      const Shape shape(n, S(height(rng)) - n_world_dot);
      const long double d = this->check(shape, tf1, tf2, i % 2 ? fcl::GST_INDEP : fcl::GST_LIBCCD);
      (d < 0 ? crossing : apart) += 1;
    }
    std::cout << "[distance] " << what << ": 24 poses, " << crossing << " crossing, " << apart << " apart\n";
    EXPECT_GE(crossing, 4);
    EXPECT_GE(apart, 4);
  };
  run(static_cast<const fcl::Plane<S>*>(nullptr), "plane", -1.7, 1.7);
  run(static_cast<const fcl::Halfspace<S>*>(nullptr), "halfspace", -2.4, 1);
}

/// Grazing: the plane or halfspace through the torus's lowest vertex along a random normal (the mesh on the
/// halfspace's empty side) meets it (-1, as collide reports), however the plane is posed; moved 1e-3 away it is
/// 1e-3 away, moved 1e-3 into the mesh it meets it.
TYPED_TEST(DistancePlaneAndHalfspace, GrazingPosesTouch)
{
  using S = TypeParam;
  const std::string what = "distance/plane-halfspace/grazing/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  for (int i = 0; i < 8; ++i)
  {
    SCOPED_TRACE(what + " pose #" + std::to_string(i));
    const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(2));
    const fcl::Transform3<S> tf2 = i % 2 ? fcl_rs::test::randomPose<S>(rng, S(2)) : fcl::Transform3<S>::Identity();
    const fcl::Vector3<S> n = fcl_rs::test::randomRotation<S>(rng).col(0);
    // The lowest world vertex along the world normal, as a local offset.
    const WorldPlane<S> at_zero(n, S(0), tf2);
    const std::vector<long double> h = at_zero.heights(this->torus.tri, tf1);
    const S lowest = S(*std::min_element(h.begin(), h.end()));
    for (const S shift : {S(0), S(-1e-3), S(1e-3)})
    {
      SCOPED_TRACE("shift " + std::to_string(shift));
      const fcl::Plane<S> plane(n, lowest + shift);
      const fcl::Halfspace<S> halfspace(n, lowest + shift);
      const long double plane_distance = this->check(plane, tf1, tf2, fcl::GST_LIBCCD);
      const long double halfspace_distance = this->check(halfspace, tf1, tf2, fcl::GST_LIBCCD);
      fcl::DistanceResult<S> r;
      fcl_rs::distance<S>(this->torus.rs.get(), tf1, &halfspace, tf2, fcl::DistanceRequest<S>(), r);
      if (shift < 0)
      {
        EXPECT_NEAR(double(plane_distance), 1e-3, 1e-5);
        EXPECT_NEAR(double(halfspace_distance), 1e-3, 1e-5);
        EXPECT_GT(r.min_distance, 0);
      }
      else
        EXPECT_EQ(r.min_distance, S(-1)) << "touching or crossing, but distance " << r.min_distance;
    }
  }
}

template <typename S>
class DistanceShapeSigned : public ::testing::Test {};
TYPED_TEST_SUITE(DistanceShapeSigned, fcl_rs::test::Scalars);

/// Signed distances of shapes whose deepest directions form a circle or a sphere (concentric, coaxial, same pose):
/// FCL's libccd EPA ran for minutes on them (no iteration limit) and GJKSolver_indep's depths were far off. Each is
/// checked against its closed-form depth for both solvers, both orders, at the centre and 1e-7 off it, and the
/// nearest points against libccd's convention: moving o1 by p2 - p1 makes the shapes touch.
TYPED_TEST(DistanceShapeSigned, ConcentricAndCoaxialPairsMatchClosedForms)
{
  using S = TypeParam;
  using Geometry = std::shared_ptr<fcl::CollisionGeometry<S>>;
  const S tol = std::is_same_v<S, float> ? S(2e-5) : S(2e-6);  // distance_tolerance 1e-6 and float rounding
  struct Case
  {
    const char* name;
    Geometry a, b;
    double depth;
    bool epa = false;  // not closed form: the same bounded EPA for both solvers, run once
  };
  const double cone_side = 0.5 * 1 / std::sqrt(4.0 + 0.25);  // centre of a cone r 0.5, lz 2 to its side
  const std::vector<Case> cases = {
      {"sphere-sphere", std::make_shared<fcl::Sphere<S>>(1), std::make_shared<fcl::Sphere<S>>(S(0.5)), 1.5},
      {"sphere-capsule", std::make_shared<fcl::Sphere<S>>(1), std::make_shared<fcl::Capsule<S>>(S(0.3), 1), 1.3},
      {"capsule-capsule", std::make_shared<fcl::Capsule<S>>(S(0.5), 2), std::make_shared<fcl::Capsule<S>>(S(0.3), 1),
       0.8},
      {"sphere-box", std::make_shared<fcl::Sphere<S>>(1), std::make_shared<fcl::Box<S>>(S(0.5), S(0.7), S(0.9)), 1.25},
      {"sphere-cylinder", std::make_shared<fcl::Sphere<S>>(1), std::make_shared<fcl::Cylinder<S>>(S(0.3), 1), 1.3},
      {"sphere-cone", std::make_shared<fcl::Sphere<S>>(S(0.5)), std::make_shared<fcl::Cone<S>>(S(0.5), 2),
       0.5 + cone_side},
      {"round ellipsoid-sphere", std::make_shared<fcl::Ellipsoid<S>>(S(0.5), S(0.5), S(0.5)),
       std::make_shared<fcl::Sphere<S>>(1), 1.5},
      {"sphere-near sphere", std::make_shared<fcl::Sphere<S>>(1),
       std::make_shared<fcl::Ellipsoid<S>>(S(0.5), S(0.5), S(0.51)), 1.5, true},
      {"cylinder-cylinder", std::make_shared<fcl::Cylinder<S>>(S(0.5), 2),
       std::make_shared<fcl::Cylinder<S>>(S(0.3), 1), 0.8, true},
      {"capsule-cylinder", std::make_shared<fcl::Capsule<S>>(S(0.5), 2),
       std::make_shared<fcl::Cylinder<S>>(S(0.3), 1), 0.8, true},
      {"box-box", std::make_shared<fcl::Box<S>>(1, 2, 3), std::make_shared<fcl::Box<S>>(1, 2, 3), 1, true},
      {"ellipsoid-ellipsoid", std::make_shared<fcl::Ellipsoid<S>>(1, S(0.7), S(0.5)),
       std::make_shared<fcl::Ellipsoid<S>>(S(0.4), S(0.6), S(0.3)), 0.8, true},
  };
  fcl::Transform3<S> tf1 = fcl::Transform3<S>::Identity();
  tf1.linear() = fcl::AngleAxis<S>(S(0.7), fcl::Vector3<S>(1, 2, 3).normalized()).toRotationMatrix();
  tf1.translation() << S(0.3), S(-0.2), S(0.1);
  for (const auto solver : {fcl::GST_LIBCCD, fcl::GST_INDEP})
    for (const Case& c : cases)
      if (solver == fcl::GST_LIBCCD || !c.epa)
      for (const bool swapped : {false, true})
        for (const S offset : {S(0), S(1e-7)})
        {
          if (swapped && c.epa) continue;  // EPA's cost (milliseconds at its bound) once per pair
          SCOPED_TRACE(std::string(c.name) + (swapped ? " swapped" : "") + " offset " + std::to_string(offset) +
                       " solver " + std::to_string(int(solver)));
          const auto& o1 = swapped ? c.b : c.a;
          const auto& o2 = swapped ? c.a : c.b;
          fcl::Transform3<S> tf2 = tf1;
          tf2.translation() += fcl::Vector3<S>(offset, offset / 2, 0);
          fcl::DistanceRequest<S> request(true, /*enable_signed_distance=*/true);
          request.gjk_solver_type = solver;
          fcl::DistanceResult<S> result;
          fcl_rs::distance<S>(o1.get(), tf1, o2.get(), tf2, request, result);
          EXPECT_NEAR(result.min_distance, -c.depth, tol + offset * 2);
          fcl::Transform3<S> touching = tf1;
          touching.translation() += result.nearest_points[1] - result.nearest_points[0];
          fcl::DistanceResult<S> moved;
          fcl_rs::distance<S>(o1.get(), touching, o2.get(), tf2, request, moved);
          // Loosely: FCL's GJK measures the moved pair, and it stops early on cylinders touching along a line.
          EXPECT_NEAR(moved.min_distance, 0, S(1e-4)) << "nearest points " << result.nearest_points[0].transpose()
                                                      << " and " << result.nearest_points[1].transpose();
        }
  // Apart, the closed forms give the distance and points on the surfaces.
  const fcl::Sphere<S> sphere(1);
  const fcl::Box<S> box(S(0.5), S(0.7), S(0.9));
  fcl::Transform3<S> away = tf1;
  away.translation() += tf1.linear() * fcl::Vector3<S>(2, 0, 0);
  fcl::DistanceRequest<S> request(true, /*enable_signed_distance=*/true);
  fcl::DistanceResult<S> result;
  fcl_rs::distance<S>(&sphere, away, &box, tf1, request, result);
  EXPECT_NEAR(result.min_distance, S(0.75), tol);
  EXPECT_NEAR((result.nearest_points[0] - away.translation()).norm(), 1, tol);
  EXPECT_NEAR((result.nearest_points[0] - result.nearest_points[1]).norm(), S(0.75), tol);
}

/// Two parallel cones side by side (found by fuzz_api): libccd's EPA meets a zero-area face, and FCL's check for one
/// (only without NDEBUG: the sanitizer stage) throws FailedAtThisConfiguration. The pair is measured in a turned frame
/// instead; the depth is what the same pair turned by another rotation measures, and moving o1 by p2 - p1 makes the
/// cones touch.
TYPED_TEST(DistanceShapeSigned, DegenerateEpaFaceIsMeasuredInATurnedFrame)
{
  using S = TypeParam;
  const fcl::Cone<S> cone(S(0.2), S(0.5));
  fcl::Transform3<S> tf1 = fcl::Transform3<S>::Identity();
  tf1.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  fcl::Transform3<S> tf2 = tf1;
  tf1.translation() << S(-0.00390625), S(-0.0015716552734375), S(-0.07666015625);
  tf2.translation() << S(0.244140625), S(-0.07080078125), S(-0.07666015625);
  fcl::DistanceRequest<S> request(true, /*enable_signed_distance=*/true);
  fcl::DistanceResult<S> result;
  fcl_rs::distance<S>(&cone, tf1, &cone, tf2, request, result);
  EXPECT_LT(result.min_distance, 0);

  fcl::Transform3<S> turn = fcl::Transform3<S>::Identity();
  turn.linear() = fcl::AngleAxis<S>(S(0.4), fcl::Vector3<S>(2, -1, 1).normalized()).toRotationMatrix();
  fcl::DistanceResult<S> turned;
  fcl_rs::distance<S>(&cone, fcl::Transform3<S>(turn * tf1), &cone, fcl::Transform3<S>(turn * tf2), request, turned);
  const S tol = std::is_same_v<S, float> ? S(2e-5) : S(2e-6);  // distance_tolerance 1e-6 and float rounding
  EXPECT_NEAR(result.min_distance, turned.min_distance, tol);

  fcl::Transform3<S> touching = tf1;
  touching.translation() += result.nearest_points[1] - result.nearest_points[0];
  fcl::DistanceResult<S> moved;
  fcl_rs::distance<S>(&cone, touching, &cone, tf2, request, moved);
  EXPECT_NEAR(moved.min_distance, 0, S(1e-4)) << "nearest points " << result.nearest_points[0].transpose() << " and "
                                              << result.nearest_points[1].transpose();
}

template <typename S>
class DistanceDispatch : public ::testing::Test {};
TYPED_TEST_SUITE(DistanceDispatch, fcl_rs::test::Scalars);

TYPED_TEST(DistanceDispatch, OtherPairsPassThroughAndUnsupportedPairsThrow)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.25)));
  const fcl::Transform3<S> id = fcl::Transform3<S>::Identity();
  fcl::Transform3<S> away = id;
  away.translation() << 3, 0, 0;
  const fcl::Sphere<S> sphere(S(0.5));
  fcl::DistanceResult<S> r1, r2;
  const fcl::DistanceRequest<S> request;
  EXPECT_EQ(fcl_rs::distance<S>(&sphere, id, &sphere, away, request, r1),
            fcl::distance(&sphere, id, &sphere, away, request, r2));
  EXPECT_EQ(r1.min_distance, r2.min_distance);
  fcl::DistanceResult<S> r3, r4;
  EXPECT_EQ(fcl_rs::distance<S>(torus.rss.get(), id, torus.rss.get(), away, request, r3),
            fcl::distance(torus.rss.get(), id, torus.rss.get(), away, request, r4));

  fcl::DistanceResult<S> r;
  EXPECT_THROW(fcl_rs::distance<S>(torus.rs.get(), id, torus.obbrss.get(), away, request, r), std::invalid_argument);
  EXPECT_THROW(fcl_rs::distance<S>(torus.obbrss.get(), id, torus.rs.get(), away, request, r), std::invalid_argument);
  // FCL's GJK has no support function for planes and halfspaces: pairs of shapes with one are refused.
  const fcl::Halfspace<S> halfspace(fcl::Vector3<S>(0, 0, 1), -1);
  const fcl::Plane<S> plane(fcl::Vector3<S>(0, 0, 1), -1);
  EXPECT_THROW(fcl_rs::distance<S>(&sphere, id, &halfspace, away, request, r), std::invalid_argument);
  EXPECT_THROW(fcl_rs::distance<S>(&plane, away, &sphere, id, request, r), std::invalid_argument);
  fcl::BVHModel<fcl_rs::RS<S>> unbuilt;
  EXPECT_THROW(fcl_rs::distance<S>(&unbuilt, id, torus.rs.get(), away, request, r), std::invalid_argument);
  EXPECT_THROW(fcl_rs::distance<S>(nullptr, id, torus.rs.get(), away, request, r), std::invalid_argument);

  const fcl::CollisionObject<S> o1(torus.rs, id), o2(torus.rs, away);
  fcl::DistanceResult<S> by_object, by_geometry;
  fcl_rs::distance<S>(&o1, &o2, request, by_object);
  fcl_rs::distance<S>(torus.rs.get(), id, torus.rs.get(), away, request, by_geometry);
  EXPECT_EQ(by_object.min_distance, by_geometry.min_distance);
  EXPECT_GT(by_object.min_distance, 0);
}

}  // namespace
