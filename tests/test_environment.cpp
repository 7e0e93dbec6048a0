// Environment: a robot among obstacles. Queries against brute force (every link x every obstacle with
// fcl_rs::collide / distance), motion checks against dense sampling (grazing a thin obstacle between two samples
// included), obstacles added, moved and removed, bad input, and the batches against the single calls. Octomap
// obstacles against the same environment with one box obstacle per occupied cell.
#include <algorithm>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <random>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/geometry/shape/triangle_p.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <gtest/gtest.h>

#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/robot.h"
#include "fcl_rs/robot/link_sweeps.h"
#ifdef FCL_RS_TEST_BATCH
#include "fcl_rs/robot/batch_environment.h"
#endif
#if FCL_HAVE_OCTOMAP
#include "fcl_rs/mesh/surface_octree.h"
#include "octree_cells.h"
#endif
#include "test_util.h"

namespace fcl_rs {
namespace {

const RobotModel* panda()
{
  static std::unique_ptr<RobotModel> robot = [] {
    const std::string urdf = test::sharedData("robots/panda/panda.urdf");
    return urdf.empty() ? nullptr : std::make_unique<RobotModel>(loadUrdf(urdf));
  }();
  return robot.get();
}

std::vector<DisabledCollision> pandaSrdf()
{
  return loadDisabledCollisions(test::sharedData("robots/panda/panda.srdf"), *panda());
}

/// Expects f to throw std::invalid_argument with `part` in its message.
void expectInvalid(const std::function<void()>& f, const std::string& part)
{
  try
  {
    f();
    ADD_FAILURE() << "no exception";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << "'" << part << "' not in: " << e.what();
  }
}

template <typename S>
fcl::Transform3<S> at(S x, S y, S z)
{
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.translation() = fcl::Vector3<S>(x, y, z);
  return tf;
}

/// An obstacle as the brute force sees it: its own geometry (mesh trees built here), pose and name.
template <typename S>
struct Reference
{
  std::string name;
  std::shared_ptr<fcl::CollisionGeometry<S>> geometry;
  fcl::Transform3<S> pose;
};

template <typename S>
std::shared_ptr<fcl::CollisionGeometry<S>> referenceTree(BVType bv, const TriangleMesh<S>& mesh)
{
  switch (bv)
  {
    case BVType::kRS: return buildModel<RS<S>>(mesh);
    case BVType::kOBBRSS: return buildModel<fcl::OBBRSS<S>>(mesh);
    case BVType::kOBB: return buildModel<fcl::OBB<S>>(mesh);
    default: throw std::logic_error("unused BV type");
  }
}

/// A planning scene around the Panda: a table, a two-board shelf, a sphere and a torus mesh, and seeded small
/// spheres within reach.
template <typename S>
std::vector<Reference<S>> scene(Environment<S>& env, std::mt19937_64& rng)
{
  std::vector<Reference<S>> refs;
  const auto shape = [&](const std::string& name, std::shared_ptr<fcl::CollisionGeometry<S>> g,
                         const fcl::Transform3<S>& pose) {
    env.addShape(name, g, pose);
    refs.push_back({name, g, pose});
  };
  const auto mesh = [&](const std::string& name, const TriangleMesh<S>& m, const fcl::Transform3<S>& pose) {
    env.addMesh(name, m, pose);
    refs.push_back({name, referenceTree(env.bvType(), m), pose});
  };
  shape("table", std::make_shared<fcl::Box<S>>(S(1.6), S(1.6), S(0.04)), at<S>(0, 0, S(-0.05)));
  shape("shelf_low", std::make_shared<fcl::Box<S>>(S(0.3), S(0.8), S(0.02)), at<S>(S(0.65), 0, S(0.3)));
  shape("shelf_high", std::make_shared<fcl::Box<S>>(S(0.3), S(0.8), S(0.02)), at<S>(S(0.65), 0, S(0.7)));
  mesh("ball", makeSphere<S>(S(0.08), 8, 12), at<S>(S(0.3), S(0.4), S(0.5)));
  mesh("ring", makeTorus<S>(S(0.12), S(0.03), 12, 8), at<S>(S(-0.3), S(-0.4), S(0.4)));
  std::uniform_real_distribution<double> u(-0.7, 0.7), h(0.1, 1.0);
  for (int i = 0; i < 6; ++i)
    shape("pebble" + std::to_string(i), std::make_shared<fcl::Sphere<S>>(S(0.04)), at<S>(S(u(rng)), S(u(rng)), S(h(rng))));
  return refs;
}

/// Brute force: every colliding self pair (SelfCollision::query) and every link x obstacle pair by
/// fcl_rs::collide on every element; the minimum distance over all of them by fcl_rs::distance.
template <typename S>
struct BruteForce
{
  std::vector<BodyPair> pairs;
  S distance = std::numeric_limits<S>::infinity();
};

template <typename S>
BruteForce<S> bruteForce(const Environment<S>& env, const std::vector<Reference<S>>& refs, const fcl::VectorX<S>& q,
                         bool distances)
{
  const SelfCollision<S>& self = env.selfCollision();
  const std::vector<fcl::Transform3<S>> poses = env.kinematics().linkPoses(q);
  BruteForce<S> out;
  SelfCheckRequest self_request;
  self_request.colliding_pairs = true;
  for (const LinkPair& p : self.query(q, self_request).pairs)
    out.pairs.push_back({self.linkNames()[p.first], self.linkNames()[p.second], true});
  const fcl::CollisionRequest<S> request;
  const fcl::DistanceRequest<S> distance_request;
  const auto elementDistance = [&](const LinkElement<S>& e, const fcl::Transform3<S>& pose,
                                   const fcl::CollisionGeometry<S>* g, const fcl::Transform3<S>& tf) {
    fcl::DistanceResult<S> result;
    return std::max(S(0), fcl_rs::distance(e.geometry, fcl::Transform3<S>(pose * e.origin), g, tf, distance_request, result));
  };
  for (std::size_t link = 0; link < poses.size(); ++link)
  {
    const auto elements = self.linkElements(int(link));
    for (const Reference<S>& r : refs)
    {
      bool hit = false;
      for (const LinkElement<S>& e : elements)
      {
        fcl::CollisionResult<S> result;
        hit = hit || fcl_rs::collide(e.geometry, fcl::Transform3<S>(poses[link] * e.origin), r.geometry.get(), r.pose,
                                     request, result) > 0;
        if (distances) out.distance = std::min(out.distance, elementDistance(e, poses[link], r.geometry.get(), r.pose));
      }
      if (hit) out.pairs.push_back({self.linkNames()[link], r.name, false});
    }
  }
  if (distances)
    for (const LinkPair& p : self.pairs())
      for (const LinkElement<S>& e : self.linkElements(p.first))
        for (const LinkElement<S>& f : self.linkElements(p.second))
          out.distance = std::min(out.distance, elementDistance(e, poses[p.first], f.geometry,
                                                                fcl::Transform3<S>(poses[p.second] * f.origin)));
  return out;
}

template <typename S>
class EnvironmentTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(EnvironmentTest, test::Scalars);

TYPED_TEST(EnvironmentTest, QueriesAgreeWithBruteForce)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  for (BVType bv : {BVType::kRS, BVType::kOBBRSS, BVType::kOBB})
  {
    SCOPED_TRACE(bvTypeName(bv));
    auto rng = test::seededRng("QueriesAgreeWithBruteForce/" + test::scalarName<S>() + "/" + bvTypeName(bv));
    Environment<S> env(*panda(), bv, pandaSrdf());
    const std::vector<Reference<S>> refs = scene(env, rng);
    const bool distances = bv != BVType::kOBB;
    int colliding = 0, world = 0;
    for (int i = 0; i < (test::kSanitized ? 4 : 12); ++i)
    {
      const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
      SCOPED_TRACE(::testing::Message() << "configuration " << i << ": " << q.transpose());
      EnvironmentRequest request;
      request.colliding_pairs = true;
      request.minimum_distance = distances;
      const EnvironmentResult<S> result = env.query(q, request);
      const BruteForce<S> expected = bruteForce(env, refs, q, distances);
      EXPECT_EQ(result.pairs, expected.pairs);
      EXPECT_EQ(result.colliding, !expected.pairs.empty());
      EXPECT_EQ(env.query(q).colliding, result.colliding);  // the first-contact query
      colliding += result.colliding;
      world += std::any_of(result.pairs.begin(), result.pairs.end(), [](const BodyPair& p) { return !p.other_is_link; });
      if (!distances) continue;
      if (result.colliding)
      {
        EXPECT_EQ(result.minimum_distance, S(0));
        continue;
      }
      const S tolerance = std::is_same<S, float>::value ? S(1e-4) : S(1e-9);
      EXPECT_NEAR(result.minimum_distance, expected.distance, tolerance);
      EXPECT_FALSE(result.nearest_pair.link.empty());
      // FCL's oriented trees report some nearest points in a mesh's own frame; RS's are in the root frame.
      if (bv != BVType::kRS) continue;
      const S points_tolerance = std::is_same<S, float>::value ? S(1e-3) : S(1e-6);
      EXPECT_NEAR((result.nearest_points[0] - result.nearest_points[1]).norm(), result.minimum_distance,
                  points_tolerance);
    }
    // The scene exercises both answers and the world part.
    // The sanitized build's four configurations may all be free; the twelve of the others must not.
    if (!test::kSanitized)
    {
      EXPECT_GT(colliding, 0);
      EXPECT_GT(world, 0);
    }
  }
}

TYPED_TEST(EnvironmentTest, ObstaclesAddedMovedAndRemoved)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  const fcl::VectorX<S> home = (fcl::VectorX<S>(8) << 0, S(-0.785), 0, S(-2.356), 0, S(1.571), S(0.785), S(0.02)).finished();
  ASSERT_FALSE(env.query(home).colliding);
  const int hand = panda()->linkIndex("panda_hand");
  const fcl::Vector3<S> hand_at = env.kinematics().linkPoses(home)[hand].translation();
  env.addShape("block", std::make_shared<fcl::Box<S>>(S(0.05), S(0.05), S(0.05)), at<S>(S(2), S(2), S(2)));
  EXPECT_FALSE(env.query(home).colliding);
  env.setPose("block", at<S>(hand_at.x(), hand_at.y(), hand_at.z()));
  EnvironmentRequest request;
  request.colliding_pairs = true;
  const EnvironmentResult<S> hit = env.query(home, request);
  ASSERT_TRUE(hit.colliding);
  EXPECT_TRUE(std::any_of(hit.pairs.begin(), hit.pairs.end(),
                          [](const BodyPair& p) { return p.link == "panda_hand" && p.other == "block" && !p.other_is_link; }));
  EXPECT_EQ(env.obstacleNames(), std::vector<std::string>{"block"});
  env.remove("block");
  EXPECT_FALSE(env.contains("block"));
  EXPECT_FALSE(env.query(home).colliding);
  // The distance names the nearest obstacle once one is nearer than any self pair.
  env.addShape("near", std::make_shared<fcl::Sphere<S>>(S(0.01)), at<S>(hand_at.x(), hand_at.y(), hand_at.z() + S(0.2)));
  request.minimum_distance = true;
  const EnvironmentResult<S> near = env.query(home, request);
  EXPECT_FALSE(near.colliding);
  EXPECT_EQ(near.nearest_pair.other, "near");
  EXPECT_FALSE(near.nearest_pair.other_is_link);
}

/// Every shape addShape takes meets the links on the environment's own path (RS: the shape's volume fitted once in
/// its frame and placed per query); the pairs are fcl_rs::collide's, at the poses the shapes were added at and
/// after setPose moves them.
TYPED_TEST(EnvironmentTest, EveryShapeKindAgreesWithBruteForceAsItMoves)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("EveryShapeKindAgreesWithBruteForceAsItMoves/" + test::scalarName<S>());
  auto tetrahedron = std::make_shared<std::vector<fcl::Vector3<S>>>(std::vector<fcl::Vector3<S>>{
      {S(0.1), 0, 0}, {0, S(0.1), 0}, {0, 0, S(0.1)}, {S(-0.05), S(-0.05), S(-0.05)}});
  auto faces = std::make_shared<std::vector<int>>(std::vector<int>{3, 0, 1, 2, 3, 0, 3, 1, 3, 0, 2, 3, 3, 1, 3, 2});
  const std::vector<std::pair<std::string, std::shared_ptr<fcl::CollisionGeometry<S>>>> shapes = {
      {"box", std::make_shared<fcl::Box<S>>(S(0.1), S(0.2), S(0.05))},
      {"sphere", std::make_shared<fcl::Sphere<S>>(S(0.06))},
      {"cylinder", std::make_shared<fcl::Cylinder<S>>(S(0.04), S(0.3))},
      {"capsule", std::make_shared<fcl::Capsule<S>>(S(0.04), S(0.2))},
      {"cone", std::make_shared<fcl::Cone<S>>(S(0.08), S(0.2))},
      {"ellipsoid", std::make_shared<fcl::Ellipsoid<S>>(S(0.05), S(0.1), S(0.08))},
      {"convex", std::make_shared<fcl::Convex<S>>(tetrahedron, 4, faces)}};
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  std::vector<Reference<S>> refs;
  for (const auto& [name, shape] : shapes)
  {
    refs.push_back({name, shape, test::randomPose<S>(rng, S(0.6))});
    env.addShape(name, shape, refs.back().pose);
  }
  int world = 0;
  for (int round = 0; round < 2; ++round)
  {
    if (round == 1)
      for (Reference<S>& r : refs) env.setPose(r.name, r.pose = test::randomPose<S>(rng, S(0.6)));
    for (int i = 0; i < (test::kSanitized ? 3 : 10); ++i)
    {
      const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
      SCOPED_TRACE(::testing::Message() << "round " << round << ", configuration " << i << ": " << q.transpose());
      EnvironmentRequest request;
      request.colliding_pairs = true;
      const EnvironmentResult<S> result = env.query(q, request);
      EXPECT_EQ(result.pairs, bruteForce(env, refs, q, /*distances=*/false).pairs);
      EXPECT_EQ(env.query(q).colliding, result.colliding);
      world += int(std::count_if(result.pairs.begin(), result.pairs.end(),
                                 [](const BodyPair& p) { return !p.other_is_link; }));
    }
  }
  if (!test::kSanitized)
  {
    EXPECT_GT(world, 0);
  }
}

/// A link no joint moves (the Panda's base) meets an obstacle by an answer decided when the obstacle is added or
/// moved: it must follow setPose and agree with brute force at every configuration.
TYPED_TEST(EnvironmentTest, FixedLinksFollowObstaclesAsTheyMove)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("FixedLinksFollowObstaclesAsTheyMove/" + test::scalarName<S>());
  for (BVType bv : {BVType::kRS, BVType::kOBB})
  {
    SCOPED_TRACE(bvTypeName(bv));
    Environment<S> env(*panda(), bv, pandaSrdf());
    std::vector<Reference<S>> refs = {{"plate", std::make_shared<fcl::Box<S>>(S(0.3), S(0.3), S(0.02)), at<S>(0, 0, S(0.05))}};
    env.addShape(refs[0].name, refs[0].geometry, refs[0].pose);
    const BodyPair base_on_plate{"panda_link0", "plate", false};
    for (const S height : {S(0.05), S(-0.5), S(0.1)})
    {
      env.setPose("plate", refs[0].pose = at<S>(0, 0, height));
      for (int i = 0; i < 3; ++i)
      {
        const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
        SCOPED_TRACE(::testing::Message() << "plate at " << height << ", configuration " << q.transpose());
        EnvironmentRequest request;
        request.colliding_pairs = true;
        const std::vector<BodyPair> pairs = env.query(q, request).pairs;
        EXPECT_EQ(pairs, bruteForce(env, refs, q, /*distances=*/false).pairs);
        EXPECT_EQ(std::count(pairs.begin(), pairs.end(), base_on_plate), height > 0 ? 1 : 0);
        EXPECT_TRUE(!(height > 0) || env.query(q).colliding);
      }
    }
  }
}

TYPED_TEST(EnvironmentTest, BadInputIsRefused)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  EXPECT_THROW(Environment<S>(*panda(), BVType::kKDOP18), std::invalid_argument);
  Environment<S> env(*panda(), BVType::kRS);
  const auto box = std::make_shared<fcl::Box<S>>(S(0.1), S(0.1), S(0.1));
  expectInvalid([&] { env.addShape("", box, at<S>(0, 0, 0)); }, "empty");
  expectInvalid([&] { env.addShape("a", nullptr, at<S>(0, 0, 0)); }, "'a'");
  expectInvalid([&] { env.addShape("a", buildModel<RS<S>>(makeBox<S>(1, 1, 1)), at<S>(0, 0, 0)); },
                "obstacle 'a' is not a primitive shape");
  expectInvalid(
      [&] {
        env.addShape("a", std::make_shared<fcl::TriangleP<S>>(fcl::Vector3<S>::Zero(), fcl::Vector3<S>::UnitX(), fcl::Vector3<S>::UnitY()),
                     at<S>(0, 0, 0));
      },
      "obstacle 'a' is a TriangleP");
  expectInvalid([&] { env.addShape("a", std::make_shared<fcl::Sphere<S>>(S(-0.1)), at<S>(0, 0, 0)); },
                "fcl_rs::Environment::addShape: obstacle 'a' is an fcl::Sphere with radius -0.1");
  fcl::Transform3<S> bad = at<S>(0, 0, 0);
  bad.linear()(0, 0) = S(2);
  expectInvalid([&] { env.addShape("a", box, bad); }, "rigid");
  bad = at<S>(std::numeric_limits<S>::quiet_NaN(), 0, 0);
  expectInvalid([&] { env.addShape("a", box, bad); }, "rigid");
  env.addShape("a", box, at<S>(2, 0, 0));
  expectInvalid([&] { env.addShape("a", box, at<S>(0, 0, 0)); }, "exists");
  expectInvalid([&] { env.addMesh("m", TriangleMesh<S>{}, at<S>(0, 0, 0)); }, "");
  expectInvalid([&] { env.setPose("b", at<S>(0, 0, 0)); }, "'b'");
  expectInvalid([&] { env.remove("b"); }, "'b'");
  expectInvalid([&] { env.query(fcl::VectorX<S>::Zero(3)); }, "3 values");
  fcl::VectorX<S> q = fcl::VectorX<S>::Zero(8);
  q[2] = std::numeric_limits<S>::infinity();
  expectInvalid([&] { env.query(q); }, "non-finite");
  expectInvalid([&] { env.checkMotion(fcl::VectorX<S>::Zero(8), q); }, "motion end");
  MotionRequest<S> zero;
  zero.tolerance = 0;
  expectInvalid(
      [&] { env.checkMotion(fcl::VectorX<S>::Zero(8), fcl::VectorX<S>::Zero(8), zero); }, "tolerance");
  expectInvalid([&] { env.checkPath({}); }, "waypoints");
  Environment<S> obb(*panda(), BVType::kOBB);
  EnvironmentRequest distance;
  distance.minimum_distance = true;
  expectInvalid([&] { obb.query(fcl::VectorX<S>::Zero(8), distance); }, "OBB");
  expectInvalid(
      [&] { obb.checkMotion(fcl::VectorX<S>::Zero(8), fcl::VectorX<S>::Zero(8)); }, "OBB");
}

/// The configuration at parameter t of the segment.
template <typename S>
fcl::VectorX<S> along(const fcl::VectorX<S>& from, const fcl::VectorX<S>& to, S t)
{
  return from + t * (to - from);
}

/// The motion check against dense sampling: a free answer has no colliding sample; a colliding one names a
/// colliding configuration, no sample below free_until collides, and free_until is within the tolerance.
template <typename S>
void expectMotionAgreesWithSampling(const Environment<S>& env, const fcl::VectorX<S>& from, const fcl::VectorX<S>& to,
                                    int samples, const MotionRequest<S>& request, int* colliding_count)
{
  const MotionResult<S> motion = env.checkMotion(from, to, request);
  int first = -1;
  for (int k = 0; k <= samples && first < 0; ++k)
    if (env.query(along(from, to, S(k) / S(samples))).colliding) first = k;
  if (!motion.colliding)
  {
    EXPECT_EQ(first, -1) << "the motion check says free, sample " << first << "/" << samples << " collides";
    return;
  }
  ++*colliding_count;
  EXPECT_TRUE(env.query(along(from, to, motion.parameter)).colliding) << "parameter " << motion.parameter;
  EXPECT_LE(motion.free_until, motion.parameter);
  if (request.earliest)
  {
    EXPECT_LE(motion.parameter - motion.free_until, request.tolerance);
  }
  if (first >= 0)
  {
    EXPECT_LE(motion.free_until, S(first) / S(samples) + S(1e-6));
  }
}

TYPED_TEST(EnvironmentTest, MotionChecksAgreeWithDenseSampling)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  for (BVType bv : {BVType::kRS, BVType::kOBBRSS})
  {
    SCOPED_TRACE(bvTypeName(bv));
    auto rng = test::seededRng("MotionChecksAgreeWithDenseSampling/" + test::scalarName<S>() + "/" + bvTypeName(bv));
    Environment<S> env(*panda(), bv, pandaSrdf());
    scene(env, rng);
    std::uniform_real_distribution<double> step(-0.6, 0.6);
    int colliding = 0, segments = 0;
    for (int i = 0; i < (test::kSanitized ? 3 : 8); ++i)
    {
      fcl::VectorX<S> from = env.kinematics().randomConfiguration(rng);
      for (int tries = 0; tries < 100 && env.query(from).colliding; ++tries) from = env.kinematics().randomConfiguration(rng);
      fcl::VectorX<S> to = from;
      for (int v = 0; v < to.size(); ++v)
        to[v] = std::clamp(S(to[v] + step(rng)), env.kinematics().lower()[v], env.kinematics().upper()[v]);
      SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
      for (bool earliest : {true, false})
      {
        MotionRequest<S> request;
        request.earliest = earliest;
        expectMotionAgreesWithSampling(env, from, to, test::kSanitized ? 50 : 150, request, &colliding);
      }
      ++segments;
    }
    // The sanitized build's three segments may all be free; the eight of the others must not.
    if (!test::kSanitized) { EXPECT_GT(colliding, 0); }
    EXPECT_LT(colliding, 2 * segments);
  }
}

// Hundreds of small obstacles in and around the Panda's reach, so that the broad phase's tree has many levels:
// every query equals the brute force over every link x obstacle pair, also after half of them moved and a quarter
// were removed (the tree rebuilt), and motion checks (short and long segments) agree with dense sampling.
TYPED_TEST(EnvironmentTest, HundredsOfObstaclesAgreeWithBruteForce)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("HundredsOfObstaclesAgreeWithBruteForce/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  std::vector<Reference<S>> refs;
  std::uniform_real_distribution<double> u(-1.5, 1.5), h(-0.2, 1.6), size(0.02, 0.06);
  const auto place = [&]() { return at<S>(S(u(rng)), S(u(rng)), S(h(rng))); };
  const int count = test::kSanitized ? 100 : 240;
  for (int i = 0; i < count; ++i)
  {
    std::shared_ptr<fcl::CollisionGeometry<S>> g;
    if (i % 2)
      g = std::make_shared<fcl::Box<S>>(S(size(rng)), S(size(rng)), S(size(rng)));
    else
      g = std::make_shared<fcl::Sphere<S>>(S(size(rng)));
    refs.push_back({"obstacle" + std::to_string(i), g, place()});
    env.addShape(refs.back().name, g, refs.back().pose);
  }
  int colliding = 0, queries = 0;
  const auto expectQueries = [&](int n) {
    for (int i = 0; i < n; ++i)
    {
      const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
      SCOPED_TRACE(::testing::Message() << "configuration " << q.transpose());
      EnvironmentRequest request;
      request.colliding_pairs = true;
      const EnvironmentResult<S> result = env.query(q, request);
      EXPECT_EQ(result.pairs, bruteForce(env, refs, q, false).pairs);
      EXPECT_EQ(env.query(q).colliding, result.colliding);
      colliding += result.colliding;
      ++queries;
    }
  };
  const int per_round = test::kSanitized ? 3 : 10;
  expectQueries(per_round);
  for (std::size_t i = 0; i < refs.size(); i += 2)
  {
    refs[i].pose = place();
    env.setPose(refs[i].name, refs[i].pose);
  }
  for (int i = 0; i < count / 4; ++i)
  {
    const std::size_t k = std::uniform_int_distribution<std::size_t>(0, refs.size() - 1)(rng);
    env.remove(refs[k].name);
    refs.erase(refs.begin() + std::ptrdiff_t(k));
  }
  expectQueries(per_round);
  EXPECT_GT(colliding, 0);
  EXPECT_LT(colliding, queries);

  int motions_colliding = 0;
  for (int i = 0; i < (test::kSanitized ? 2 : 12); ++i)
  {
    fcl::VectorX<S> from = env.kinematics().randomConfiguration(rng);
    for (int tries = 0; tries < 200 && env.query(from).colliding; ++tries)
      from = env.kinematics().randomConfiguration(rng);
    const double reach = i % 2 ? 0.6 : 0.1;  // long and short segments
    std::uniform_real_distribution<double> step(-reach, reach);
    fcl::VectorX<S> to = from;
    for (int v = 0; v < to.size(); ++v)
      to[v] = std::clamp(S(to[v] + step(rng)), env.kinematics().lower()[v], env.kinematics().upper()[v]);
    SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
    expectMotionAgreesWithSampling(env, from, to, test::kSanitized ? 50 : 150, MotionRequest<S>(), &motions_colliding);
  }
  if (!test::kSanitized) { EXPECT_GT(motions_colliding, 0); }
  std::cout << "[hundreds of obstacles] " << colliding << " of " << queries << " configurations collide, "
            << motions_colliding << " motions\n";
}

/// The link `moving` joints up `link`'s chain (LinkSweeps' depth): the frame its bound is relative to.
int linkAbove(const RobotModel& robot, int link, int moving)
{
  int frame = link;
  for (int j = robot.links[link].parent_joint; j >= 0 && moving > 0; j = robot.links[frame].parent_joint)
  {
    frame = robot.joints[j].parent_link;
    moving -= robot.joints[j].variable >= 0 || robot.joints[j].mimic_variable >= 0;
  }
  return frame;
}

TYPED_TEST(EnvironmentTest, LinkSweepsBoundThePathOfEveryVertex)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const RobotModel& robot = *panda();
  const SelfCollision<S> self(robot, BVType::kRS, pandaSrdf());
  std::vector<fcl::Vector3<S>> centers;
  std::vector<S> radii;
  for (int i = 0; i < int(robot.links.size()); ++i)
  {
    centers.push_back(self.linkSphere(i).center);
    radii.push_back(self.linkSphere(i).radius);
  }
  const LinkSweeps<S> sweeps(robot, self.kinematics(), centers, radii);
  // Every link against the root, and each link of a self pair against their common ancestor; every vertex within the
  // link's workspace of the root's origin.
  std::vector<std::pair<int, int>> bounds;  // link, depth
  for (int link = 0; link < int(robot.links.size()); ++link)
    if (!robot.links[link].mesh.vertices.empty()) bounds.emplace_back(link, sweeps.depth(link));
  for (const LinkPair& p : self.pairs())
  {
    bounds.emplace_back(p.first, sweeps.depthBelow(p.first, p.second));
    bounds.emplace_back(p.second, sweeps.depthBelow(p.second, p.first));
  }
  auto rng = test::seededRng("LinkSweepsBoundThePathOfEveryVertex/" + test::scalarName<S>());
  std::uniform_real_distribution<double> step(-1.0, 1.0), unit(0.0, 1.0);
  const int pieces = 200;  // chords along the interval: their sum is at most the path's length
  double tightest = std::numeric_limits<double>::infinity();
  for (int segment = 0; segment < (test::kSanitized ? 4 : 20); ++segment)
  {
    const fcl::VectorX<S> from = self.kinematics().randomConfiguration(rng);
    fcl::VectorX<S> dq(from.size());
    for (int v = 0; v < dq.size(); ++v) dq[v] = S(step(rng)) * (v == dq.size() - 1 ? S(0.04) : S(1));
    double t0 = unit(rng), t1 = unit(rng);
    if (t0 > t1) std::swap(t0, t1);
    std::vector<std::vector<fcl::Transform3<S>>> poses;
    for (int k = 0; k <= pieces; ++k)
      poses.push_back(self.kinematics().linkPoses(fcl::VectorX<S>(from + S(t0 + (t1 - t0) * k / pieces) * dq)));
    std::vector<typename LinkSweeps<S>::Terms> terms;
    sweeps.terms(poses.front(), dq, terms);
    for (const auto& [link, depth] : bounds)
    {
      const int frame = linkAbove(robot, link, depth);
      const double bound = sweeps.sweep(terms, link, depth, t1 - t0);
      std::vector<fcl::Transform3<S>> relative;  // the link in the frame, along the interval
      for (const auto& p : poses) relative.push_back(p[frame].inverse(Eigen::Isometry) * p[link]);
      double longest = 0, farthest = 0;  // a vertex's path, and its distance from the root's origin
      for (const fcl::Vector3d& vertex : robot.links[link].mesh.vertices)
      {
        const auto at = [&](int k) -> fcl::Vector3d { return (relative[k] * vertex.cast<S>()).template cast<double>(); };
        double length = 0;
        for (int k = 0; k < pieces; ++k) length += (at(k + 1) - at(k)).norm();
        longest = std::max(longest, length);
        for (const auto& p : poses) farthest = std::max(farthest, double((p[link] * vertex.cast<S>()).norm()));
      }
      EXPECT_LE(farthest, sweeps.workspace(link) * (1 + 1e-6)) << robot.links[link].name;
      // Each chord rounds by a few ulps of the reach.
      const double rounding = std::is_same_v<S, float> ? 2e-7 * pieces : 1e-12 * pieces;
      EXPECT_LE(longest, bound + rounding) << robot.links[link].name << " below " << robot.links[frame].name
                                           << ", segment " << segment;
      if (longest > 1e-3) tightest = std::min(tightest, bound / longest);
    }
  }
  std::cout << "[sweeps] the tightest bound is " << tightest << " times a vertex's path\n";
}

/// Free segments of the Panda from random configurations (every joint within +-0.5 rad), each with a point of the
/// hand's surface (a random vertex of its mesh) where the hand is at a given parameter: where the motion tests put
/// small obstacles.
template <typename S>
class HandSurfacePoints
{
public:
  explicit HandSurfacePoints(const Environment<S>& env) : env_(env), hand_(panda()->linkIndex("panda_hand")) {}

  /// The next free segment; false when it is not free (the caller draws again).
  bool draw(std::mt19937_64& rng)
  {
    from = env_.kinematics().randomConfiguration(rng);
    to = from;
    std::uniform_real_distribution<double> step(-0.5, 0.5);
    for (int v = 0; v < to.size(); ++v)
      to[v] = std::clamp(S(to[v] + step(rng)), env_.kinematics().lower()[v], env_.kinematics().upper()[v]);
    return !env_.checkMotion(from, to).colliding;
  }
  /// A point of the hand's surface at parameter t of the segment drawn last.
  fcl::Vector3<S> at(S t, std::mt19937_64& rng) const
  {
    const TriangleMesh<double>& mesh = panda()->links[hand_].mesh;
    std::uniform_int_distribution<std::size_t> vertex(0, mesh.vertices.size() - 1);
    return env_.kinematics().linkPoses(along(from, to, t))[hand_] * mesh.vertices[vertex(rng)].template cast<S>();
  }

  fcl::VectorX<S> from, to;

private:
  const Environment<S>& env_;
  int hand_;
};

TYPED_TEST(EnvironmentTest, MotionChecksCatchAGrazingObstacleBetweenSamples)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("MotionChecksCatchAGrazingObstacleBetweenSamples/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  ASSERT_FALSE(panda()->links[panda()->linkIndex("panda_hand")].mesh.vertices.empty());
  HandSurfacePoints<S> segment(env);
  const fcl::VectorX<S>& from = segment.from;
  const fcl::VectorX<S>& to = segment.to;
  const int resolution = 100;  // a discrete checker's samples along the segment
  int missed_by_sampling = 0;
  for (int i = 0; i < 12; ++i)
  {
    if (!segment.draw(rng)) continue;
    // A speck on the hand's surface halfway between two samples.
    const int k = resolution / 2;
    const S t = (S(k) + S(0.5)) / S(resolution);
    const fcl::Vector3<S> p = segment.at(t, rng);
    env.addShape("speck", std::make_shared<fcl::Sphere<S>>(S(2e-4)), at<S>(p.x(), p.y(), p.z()));
    SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
    ASSERT_TRUE(env.query(along(from, to, t)).colliding);
    const MotionResult<S> motion = env.checkMotion(from, to);
    EXPECT_TRUE(motion.colliding);
    EXPECT_LE(motion.free_until, t);
    EXPECT_TRUE(env.query(along(from, to, motion.parameter)).colliding);
    missed_by_sampling += !env.query(along(from, to, S(k) / S(resolution))).colliding &&
                          !env.query(along(from, to, S(k + 1) / S(resolution))).colliding;
    env.remove("speck");
  }
  std::cout << "[grazing] " << missed_by_sampling << " specks fall between two of " << resolution << " samples\n";
  EXPECT_GT(missed_by_sampling, 0);
}

/// A thin slab, turned at random, touching the hand's surface halfway between two samples: motion checks bound a
/// link's distance to an obstacle's box by its separation along one of the box's face normals
/// (SelfCollision::lowestAlong), which must not clear a slab the hand grazes (whatever face the link is nearest).
TYPED_TEST(EnvironmentTest, MotionChecksCatchAGrazingTurnedSlabBetweenSamples)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("MotionChecksCatchAGrazingTurnedSlabBetweenSamples/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  HandSurfacePoints<S> segment(env);
  const fcl::VectorX<S>& from = segment.from;
  const fcl::VectorX<S>& to = segment.to;
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  int checked = 0;
  for (int i = 0; i < 40; ++i)
  {
    if (!segment.draw(rng)) continue;
    const S t = S(0.505);
    const fcl::Vector3<S> p = segment.at(t, rng);
    // A slab 0.04 wide and 1e-4 thin, the surface point just inside one of its corners.
    fcl::Transform3<S> pose = fcl::Transform3<S>::Identity();
    pose.linear() = (Eigen::AngleAxis<S>(S(angle(rng)), fcl::Vector3<S>::UnitZ()) *
                     Eigen::AngleAxis<S>(S(angle(rng)), fcl::Vector3<S>::UnitX()))
                        .toRotationMatrix();
    const fcl::Vector3<S> half(S(0.02), S(0.02), S(5e-5));
    std::uniform_int_distribution<int> sign(0, 1);
    const fcl::Vector3<S> corner(sign(rng) ? half.x() : -half.x(), sign(rng) ? half.y() : -half.y(),
                                 sign(rng) ? half.z() : -half.z());
    pose.translation() = p - pose.linear() * S(0.999) * corner;
    env.addShape("slab", std::make_shared<fcl::Box<S>>(S(2) * half), pose);
    SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
    if (env.query(from).colliding || env.query(to).colliding || !env.query(along(from, to, t)).colliding)
    {
      env.remove("slab");
      continue;
    }
    ++checked;
    for (bool earliest : {true, false})
    {
      MotionRequest<S> request;
      request.earliest = earliest;
      const MotionResult<S> motion = env.checkMotion(from, to, request);
      EXPECT_TRUE(motion.colliding);
      EXPECT_LE(motion.free_until, t);
    }
    env.remove("slab");
  }
  std::cout << "[slab] " << checked << " slabs grazed\n";
  EXPECT_GT(checked, 5);
}

/// SelfCollision::lowestAlong bounds every vertex of the link's mesh along the direction from below, and closely.
TYPED_TEST(EnvironmentTest, LowestAlongBoundsEveryVertex)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const RobotModel& robot = *panda();
  const SelfCollision<S> self(robot, BVType::kRS, pandaSrdf());
  auto rng = test::seededRng("LowestAlongBoundsEveryVertex/" + test::scalarName<S>());
  std::normal_distribution<double> normal;
  for (int k = 0; k < 20; ++k)
  {
    const std::vector<fcl::Transform3<S>> poses = self.kinematics().linkPoses(self.kinematics().randomConfiguration(rng));
    for (int link = 0; link < int(robot.links.size()); ++link)
    {
      if (robot.links[link].mesh.vertices.empty()) continue;
      const fcl::Vector3<S> n = fcl::Vector3d(normal(rng), normal(rng), normal(rng)).normalized().cast<S>();
      double lowest = std::numeric_limits<double>::infinity();
      for (const fcl::Vector3d& v : robot.links[link].mesh.vertices)
        lowest = std::min(lowest, double(n.dot(poses[link] * v.cast<S>())));
      const double bound = double(self.lowestAlong(link, poses[link], n));
      EXPECT_LE(bound, lowest) << robot.links[link].name;
      EXPECT_GT(bound, lowest - (std::is_same_v<S, float> ? 1e-3 : 1e-9)) << robot.links[link].name;
    }
  }
}

/// Without earliest, a motion check takes coarse intervals first, so it may certify the part of a segment after a
/// collision before the part before it: free_until must still be where the certified intervals from the start stop.
/// A small box on the hand's surface at t = 0.3 of free segments: the collision lies early, the rest is free.
TYPED_TEST(EnvironmentTest, MotionChecksWithoutEarliestCertifyOnlyTheFreeStart)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("MotionChecksWithoutEarliestCertifyOnlyTheFreeStart/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  HandSurfacePoints<S> segment(env);
  const fcl::VectorX<S>& from = segment.from;
  const fcl::VectorX<S>& to = segment.to;
  MotionRequest<S> request;
  request.earliest = false;
  const int samples = 1000;
  int checked = 0;
  for (int i = 0; i < 40 && checked < 8; ++i)
  {
    if (!segment.draw(rng)) continue;
    const fcl::Vector3<S> p = segment.at(S(0.3), rng);
    env.addShape("box", std::make_shared<fcl::Box<S>>(S(0.01), S(0.01), S(0.01)), at<S>(p.x(), p.y(), p.z()));
    if (!env.query(from).colliding)
    {
      SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
      const MotionResult<S> motion = env.checkMotion(from, to, request);
      int first = -1;
      for (int k = 0; k <= samples && first < 0; ++k)
        if (env.query(along(from, to, S(k) / S(samples))).colliding) first = k;
      ASSERT_GT(first, 0);
      EXPECT_TRUE(motion.colliding);
      EXPECT_TRUE(env.query(along(from, to, motion.parameter)).colliding) << "parameter " << motion.parameter;
      EXPECT_LE(motion.free_until, S(first) / S(samples) + S(1e-6)) << "parameter " << motion.parameter;
      ++checked;
    }
    env.remove("box");
  }
  EXPECT_EQ(checked, 8);
}

TYPED_TEST(EnvironmentTest, PathsReportTheSegmentAndParameter)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  const fcl::VectorX<S> home = (fcl::VectorX<S>(8) << 0, S(-0.785), 0, S(-2.356), 0, S(1.571), S(0.785), S(0.02)).finished();
  fcl::VectorX<S> turned = home, back = home;
  turned[0] = S(0.6);
  back[0] = S(-0.6);
  EXPECT_FALSE(env.checkPath({home, turned, back}).colliding);
  // A wall crossed only by the second segment (joint 0 turning to -0.6).
  const fcl::Vector3<S> hand = env.kinematics().linkPoses(back)[panda()->linkIndex("panda_hand")].translation();
  env.addShape("wall", std::make_shared<fcl::Box<S>>(S(0.02), S(0.02), S(0.02)), at<S>(hand.x(), hand.y(), hand.z()));
  const MotionResult<S> path = env.checkPath({home, turned, back});
  ASSERT_TRUE(path.colliding);
  EXPECT_GT(path.parameter, S(1));
  EXPECT_LE(path.parameter, S(2));
  EXPECT_LE(path.free_until, path.parameter);
  EXPECT_FALSE(env.checkPath({home}).colliding);
}

#ifdef FCL_RS_TEST_BATCH
/// Batches of queries (pairs and minimum distance) and of motions over n seeded Panda configurations (segments of
/// up to 0.3 rad per joint from them) on two threads equal the single calls.
template <typename S>
void expectBatchesEqualSingleCalls(const Environment<S>& env, std::mt19937_64& rng, int n)
{
  Configurations<S> qs(n, 8), ends(n, 8);
  std::uniform_real_distribution<double> step(-0.3, 0.3);
  for (int i = 0; i < n; ++i)
  {
    qs.row(i) = env.kinematics().randomConfiguration(rng).transpose();
    for (int v = 0; v < 8; ++v)
      ends(i, v) = std::clamp(S(qs(i, v) + step(rng)), env.kinematics().lower()[v], env.kinematics().upper()[v]);
  }
  EnvironmentRequest request;
  request.colliding_pairs = request.minimum_distance = true;
  BatchOptions options;
  options.num_threads = 2;
  const EnvironmentBatchResult<S> batch = environmentBatch(env, qs, request, options);
  const MotionBatchResult<S> motions = motionBatch(env, qs, ends, MotionRequest<S>{}, options);
  for (int i = 0; i < n; ++i)
  {
    SCOPED_TRACE(::testing::Message() << "row " << i);
    const EnvironmentResult<S> one = env.query(qs.row(i).transpose(), request);
    EXPECT_EQ(batch.colliding[i], one.colliding);
    EXPECT_EQ(batch.pairs[i], one.pairs);
    EXPECT_EQ(batch.minimum_distance[i], one.minimum_distance);
    const MotionResult<S> motion = env.checkMotion(qs.row(i).transpose(), ends.row(i).transpose());
    EXPECT_EQ(motions.colliding[i], motion.colliding);
    EXPECT_EQ(motions.parameter[i], motion.parameter);
    EXPECT_EQ(motions.free_until[i], motion.free_until);
  }
}

TYPED_TEST(EnvironmentTest, BatchesEqualSingleCalls)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("BatchesEqualSingleCalls/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  scene(env, rng);
  const int n = test::kSanitized ? 2 : 4;
  expectBatchesEqualSingleCalls(env, rng, n);
  Configurations<S> qs(n, 8);
  qs.rowwise() = env.kinematics().lower().transpose();
  expectInvalid([&] { motionBatch(env, qs, Configurations<S>(n - 1, 8)); }, "ends");
}
#endif

/// A two-joint arm without self pairs (its two geometric links are adjacent), written under the test's temporary
/// directory: a mesh link (an OBJ slab) with a cylinder, and a link of a sphere and a tilted box.
const RobotModel& slabArm()
{
  static const RobotModel robot = [] {
    const std::string dir = ::testing::TempDir();
    std::ofstream obj(dir + "/fcl_rs_environment_slab.obj");
    const TriangleMesh<double> slab = makeBox<double>(0.6, 0.08, 0.05);
    for (const fcl::Vector3d& v : slab.vertices) obj << "v " << v.x() + 0.3 << " " << v.y() << " " << v.z() << "\n";
    for (const auto& t : slab.triangles) obj << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
    obj.close();
    const std::string path = dir + "/fcl_rs_environment_slab_arm.urdf";
    std::ofstream(path) << R"(<?xml version="1.0"?>
<robot name="slab_arm">
  <link name="base"/>
  <link name="rod">
    <collision><geometry><mesh filename="fcl_rs_environment_slab.obj"/></geometry></collision>
    <collision><origin xyz="0.3 0 0.06"/><geometry><cylinder radius="0.03" length="0.1"/></geometry></collision>
  </link>
  <link name="hand">
    <collision><origin xyz="0.2 0 0"/><geometry><sphere radius="0.06"/></geometry></collision>
    <collision><origin xyz="0.1 0 0" rpy="0.3 0.2 0.1"/><geometry><box size="0.2 0.04 0.05"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="rod"/><origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="rod"/><child link="hand"/><origin xyz="0.6 0 0"/><axis xyz="0 0.6 0.8"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
</robot>
)";
    return loadUrdf(path);
  }();
  return robot;
}

/// A link's distance to a plane or halfspace (-1: they meet), by element: the mesh through fcl_rs's own mesh-plane
/// traversal on an RS tree, a box, cylinder or sphere by its closed form (centre height less the half extent along
/// the normal).
template <typename S>
S linkFlatReference(const RobotModel& robot, int link, const fcl::Transform3<S>& pose, const fcl::Vector3<S>& n, S d,
                    bool plane)
{
  S best = std::numeric_limits<S>::infinity();
  const auto keep = [&](S centre_height, S half_extent) {
    const S gap = (plane ? std::abs(centre_height) : centre_height) - half_extent;
    best = std::min(best, gap <= 0 ? S(-1) : gap);
  };
  const RobotLink& l = robot.links[std::size_t(link)];
  if (!l.mesh.triangles.empty())
  {
    TriangleMesh<S> mesh;
    for (const auto& v : l.mesh.vertices) mesh.vertices.push_back(v.template cast<S>());
    mesh.triangles = l.mesh.triangles;
    const auto tree = buildModel<RS<S>>(mesh);
    std::shared_ptr<fcl::CollisionGeometry<S>> flat;
    if (plane)
      flat = std::make_shared<fcl::Plane<S>>(n, d);
    else
      flat = std::make_shared<fcl::Halfspace<S>>(n, d);
    fcl::CollisionResult<S> collision;
    fcl::DistanceResult<S> distance;
    const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
    if (fcl_rs::collide(tree.get(), pose, flat.get(), I, fcl::CollisionRequest<S>(), collision))
      best = -1;
    else
      best = std::min(best, fcl_rs::distance(tree.get(), pose, flat.get(), I, fcl::DistanceRequest<S>(), distance));
  }
  for (const Primitive& p : l.primitives)
  {
    const fcl::Transform3<S> placed = pose * fcl::Transform3<S>(p.origin.template cast<S>());
    const fcl::Vector3<S> u = placed.linear().transpose() * n;  // the normal in the shape's frame
    const S height = n.dot(placed.translation()) - d;
    const fcl::Vector3<S> size = p.size.template cast<S>();
    switch (p.type)
    {
      case Primitive::Type::kBox: keep(height, u.cwiseAbs().dot(size) / 2); break;
      case Primitive::Type::kSphere: keep(height, size.x()); break;
      case Primitive::Type::kCylinder:
        keep(height, size.x() * std::sqrt(std::max(S(0), 1 - u.z() * u.z())) + size.y() / 2 * std::abs(u.z()));
        break;
    }
  }
  return best;
}

/// A table top (a tilted halfspace) and a wall (a plane), measured exactly against mesh and primitive links with
/// every BV type: colliding pairs and the minimum distance are linkFlatReference's, the nearest points realise it
/// with the second on the flat; motion checks agree with dense sampling.
TYPED_TEST(EnvironmentTest, PlanesAndHalfspacesAreMeasuredExactly)
{
  using S = TypeParam;
  const RobotModel& robot = slabArm();
  const S tol = std::is_same_v<S, float> ? S(2e-4) : S(1e-9);
  fcl::Transform3<S> table_pose = at<S>(0, 0, S(0.1));
  table_pose.linear() = Eigen::AngleAxis<S>(S(0.05), fcl::Vector3<S>::UnitX()).toRotationMatrix();
  const auto table = std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>::UnitZ(), S(0));  // z <= 0 at its pose
  const auto wall = std::make_shared<fcl::Plane<S>>(fcl::Vector3<S>::UnitX(), S(0));
  struct Flat
  {
    std::string name;
    fcl::Vector3<S> n;
    S d;
    bool plane;
  };
  const fcl::Vector3<S> table_n = table_pose.linear().col(2);
  const std::vector<Flat> flats = {{"table", table_n, table_n.dot(table_pose.translation()), false},
                                   {"wall", fcl::Vector3<S>::UnitX(), S(0.7), true}};
  for (BVType bv : {BVType::kRS, BVType::kOBBRSS, BVType::kRSS, BVType::kOBB})
  {
    SCOPED_TRACE(bvTypeName(bv));
    auto rng = test::seededRng("PlanesAndHalfspacesAreMeasuredExactly/" + test::scalarName<S>() + "/" + bvTypeName(bv));
    Environment<S> env(robot, bv);
    env.addShape("table", table, table_pose);
    env.addShape("wall", wall, at<S>(S(0.7), 0, 0));
    const bool distances = bv != BVType::kOBB;
    int colliding = 0, free = 0;
    for (int i = 0; i < (test::kSanitized ? 8 : 24); ++i)
    {
      const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
      SCOPED_TRACE(::testing::Message() << "configuration " << i << ": " << q.transpose());
      std::vector<fcl::Transform3<S>> poses;
      env.kinematics().linkPoses(q, poses);
      // Links in model order, obstacles in insertion order: the order of the result's pairs.
      std::vector<BodyPair> expected_pairs;
      S expected_distance = std::numeric_limits<S>::infinity();
      bool grazing = false;
      for (int link : {robot.linkIndex("rod"), robot.linkIndex("hand")})
        for (const Flat& f : flats)
        {
          const S d = linkFlatReference(robot, link, poses[std::size_t(link)], f.n, f.d, f.plane);
          grazing = grazing || (d >= 0 && d < tol);
          if (d < 0) expected_pairs.push_back({robot.links[std::size_t(link)].name, f.name, false});
          expected_distance = std::min(expected_distance, d);
        }
      if (grazing) continue;
      const EnvironmentResult<S> result = env.query(q, EnvironmentRequest{true, distances});
      EXPECT_EQ(result.colliding, !expected_pairs.empty());
      EXPECT_TRUE(result.pairs == expected_pairs) << result.pairs.size() << " pairs, " << expected_pairs.size() << " expected";
      (expected_pairs.empty() ? free : colliding) += 1;
      if (!distances || !expected_pairs.empty()) continue;
      EXPECT_NEAR(result.minimum_distance, expected_distance, tol * (1 + expected_distance));
      EXPECT_NEAR((result.nearest_points[0] - result.nearest_points[1]).norm(), result.minimum_distance, tol);
      for (const Flat& f : flats)
        if (result.nearest_pair.other == f.name)
        {
          EXPECT_NEAR(f.n.dot(result.nearest_points[1]) - f.d, 0, tol);
        }
    }
    if (!test::kSanitized)
    {
      EXPECT_GT(colliding, 0);
      EXPECT_GT(free, 0);
    }
    if (!distances) continue;
    int colliding_motions = 0;
    for (int i = 0; i < (test::kSanitized ? 2 : 6); ++i)
    {
      const fcl::VectorX<S> from = env.kinematics().randomConfiguration(rng), to = env.kinematics().randomConfiguration(rng);
      SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
      expectMotionAgreesWithSampling(env, from, to, test::kSanitized ? 50 : 150, MotionRequest<S>(), &colliding_motions);
    }
    std::cout << "[flats] " << bvTypeName(bv) << ": " << colliding << " colliding and " << free
              << " free configurations, " << colliding_motions << " colliding motions\n";
  }
}

#if FCL_HAVE_OCTOMAP
/// The boxes of an octree's occupied leaf cells in its own frame (the cells FCL's traversals test, from the
/// same computeChildBV recursion).
template <typename S>
std::vector<fcl::AABB<S>> occupiedCells(const fcl::OcTree<S>& octree)
{
  std::vector<fcl::AABB<S>> cells;
  for (const test::LeafCell<S>& cell : test::leafCells(octree))
    if (cell.node && octree.isNodeOccupied(cell.node)) cells.push_back(cell.box);
  return cells;
}

/// An octomap obstacle "map" in env and, in reference (the brute force), one Box obstacle "map#i" per occupied
/// cell at the cell's pose, placed as the traversals place a cell (fcl::constructBox).
template <typename S>
struct MapPair
{
  std::vector<fcl::AABB<S>> cells;

  MapPair(Environment<S>& env, Environment<S>& reference, std::shared_ptr<fcl::OcTree<S>> octree,
          const fcl::Transform3<S>& pose)
    : cells(occupiedCells(*octree))
  {
    env.addOcTree("map", octree, pose);
    for (std::size_t i = 0; i < cells.size(); ++i)
    {
      fcl::Box<S> box;
      fcl::Transform3<S> tf;
      fcl::constructBox(cells[i], pose, box, tf);
      reference.addShape("map#" + std::to_string(i), std::make_shared<fcl::Box<S>>(box), tf);
    }
  }

  void move(Environment<S>& env, Environment<S>& reference, const fcl::Transform3<S>& pose) const
  {
    env.setPose("map", pose);
    for (std::size_t i = 0; i < cells.size(); ++i)
    {
      fcl::Box<S> box;
      fcl::Transform3<S> tf;
      fcl::constructBox(cells[i], pose, box, tf);
      reference.setPose("map#" + std::to_string(i), tf);
    }
  }
};

/// The reference's pairs with every cell named as its map ("map#3" -> "map"), each pair once (a link's cells
/// are consecutive, in the map's place among the obstacles).
std::vector<BodyPair> asMap(std::vector<BodyPair> pairs)
{
  for (BodyPair& p : pairs)
    if (!p.other_is_link) p.other = p.other.substr(0, p.other.find('#'));
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

/// A scan within the Panda's reach: the surfaces of a torus and a ball (576 occupied cells of 4 cm).
template <typename S>
std::shared_ptr<fcl::OcTree<S>> scanMap(double cell = 0.04)
{
  const auto map = surfaceOcTree(makeTorus<double>(0.25, 0.05, 20, 8), cell);
  addSurface(*map, makeSphere<double>(0.1, 6, 10), at<double>(0, 0, 0.2));
  return std::make_shared<fcl::OcTree<S>>(map);
}

/// The scan's pose: turned by the seed, in front of the Panda.
template <typename S>
fcl::Transform3<S> scanPose(std::mt19937_64& rng)
{
  fcl::Transform3<S> pose = test::randomPose<S>(rng, S(0));
  pose.translation() = fcl::Vector3<S>(S(0.35), S(-0.1), S(0.45));
  return pose;
}

/// The environment with the octree and the reference with its cells agree: pairs, verdicts, minimum distance,
/// nearest pair and (RS) nearest points.
template <typename S>
struct Tolerances
{
  S distance, points;
};

/// The Panda's: RS measures a cell and a triangle with the same exact distance as a box and a triangle, FCL's
/// types run its GJK on the same box and triangle, and the finger boxes meet a cell and a box with FCL's box
/// distance on the same two boxes; float rounds.
template <typename S>
Tolerances<S> meshTolerances()
{
  return std::is_same<S, float>::value ? Tolerances<S>{S(1e-4), S(1e-3)} : Tolerances<S>{S(2e-6), S(1e-5)};
}

template <typename S>
void expectSameAnswers(const Environment<S>& env, const Environment<S>& reference, const fcl::VectorX<S>& q,
                       int* map_pairs, int* map_shape_pairs, int* map_nearest,
                       const Tolerances<S>& tolerances = meshTolerances<S>())
{
  const bool distances = env.bvType() != BVType::kOBB;
  EnvironmentRequest request;
  request.colliding_pairs = true;
  request.minimum_distance = distances;
  const EnvironmentResult<S> result = env.query(q, request);
  const EnvironmentResult<S> expected = reference.query(q, request);
  EXPECT_EQ(result.pairs, asMap(expected.pairs));
  EXPECT_EQ(result.colliding, expected.colliding);
  EXPECT_EQ(env.query(q).colliding, result.colliding);  // the first-contact query
  for (const BodyPair& p : result.pairs)
    if (p.other == "map")
    {
      ++*map_pairs;
      // The Panda's fingers are URDF boxes: FCL shapes against the octree.
      *map_shape_pairs += p.link.find("finger") != std::string::npos;
    }
  if (!distances || result.colliding) return;
  EXPECT_NEAR(result.minimum_distance, expected.minimum_distance, tolerances.distance);
  const BodyPair nearest = asMap({expected.nearest_pair}).front();
  EXPECT_EQ(result.nearest_pair, nearest);
  *map_nearest += result.nearest_pair.other == "map";
  if (env.bvType() != BVType::kRS || !(result.nearest_pair == nearest)) return;
  // Link first, then the cell (the octree's result names the octree first: swapped back). Where faces are parallel
  // (a finger box above a cell) the nearest points are not unique, and which pair a traversal reports depends on
  // the best distance it starts at, which the pairs measured before set (they differ between the map and its
  // boxes); every nearest pair of two convex bodies has the same separation vector.
  const fcl::Vector3<S> separation = result.nearest_points[1] - result.nearest_points[0];
  const fcl::Vector3<S> expected_separation = expected.nearest_points[1] - expected.nearest_points[0];
  EXPECT_NEAR((separation - expected_separation).norm(), 0, tolerances.points);
  EXPECT_NEAR(separation.norm(), result.minimum_distance, tolerances.points);
}

TYPED_TEST(EnvironmentTest, OcTreeQueriesAgreeWithOneBoxPerCell)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const std::shared_ptr<fcl::OcTree<S>> octree = scanMap<S>();
  for (BVType bv : {BVType::kRS, BVType::kOBBRSS, BVType::kOBB, BVType::kRSS})
  {
    SCOPED_TRACE(bvTypeName(bv));
    auto rng = test::seededRng("OcTreeQueriesAgreeWithOneBoxPerCell/" + test::scalarName<S>() + "/" + bvTypeName(bv));
    Environment<S> env(*panda(), bv, pandaSrdf()), reference(*panda(), bv, pandaSrdf());
    const auto table = std::make_shared<fcl::Box<S>>(S(1.6), S(1.6), S(0.04));
    env.addShape("table", table, at<S>(0, 0, S(-0.05)));
    reference.addShape("table", table, at<S>(0, 0, S(-0.05)));
    const fcl::Transform3<S> pose = scanPose<S>(rng);
    const MapPair<S> map(env, reference, octree, pose);
    env.addMesh("ball", makeSphere<S>(S(0.08), 8, 12), at<S>(S(-0.3), S(0.4), S(0.5)));
    reference.addMesh("ball", makeSphere<S>(S(0.08), 8, 12), at<S>(S(-0.3), S(0.4), S(0.5)));
    int map_pairs = 0, map_shape_pairs = 0, map_nearest = 0;
    for (int i = 0; i < (test::kSanitized ? 4 : 12); ++i)
    {
      const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
      SCOPED_TRACE(::testing::Message() << "configuration " << i << ": " << q.transpose());
      expectSameAnswers(env, reference, q, &map_pairs, &map_shape_pairs, &map_nearest);
    }
    std::cout << "[octree " << bvTypeName(bv) << "] " << map.cells.size() << " cells; pairs with the map "
              << map_pairs << " (finger boxes " << map_shape_pairs << "), nearest " << map_nearest << "\n";
    if (!test::kSanitized) { EXPECT_GT(map_pairs, 0); }
  }
}

/// A two-joint arm of URDF primitives only (a cylinder, a sphere and a box), written under the test's temporary
/// directory: every link element kind FCL meets an octree with.
const RobotModel& primitiveArm()
{
  static const RobotModel robot = [] {
    const std::string path = ::testing::TempDir() + "/fcl_rs_environment_primitive_arm.urdf";
    std::ofstream(path) << R"(<?xml version="1.0"?>
<robot name="primitive_arm">
  <link name="base"/>
  <link name="rod">
    <collision><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.03" length="0.5"/></geometry></collision>
  </link>
  <link name="hand">
    <collision><origin xyz="0.2 0 0"/><geometry><sphere radius="0.06"/></geometry></collision>
    <collision><origin xyz="0.1 0 0"/><geometry><box size="0.2 0.04 0.04"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="rod"/><origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="rod"/><child link="hand"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
</robot>
)";
    return loadUrdf(path);
  }();
  return robot;
}

TYPED_TEST(EnvironmentTest, OcTreeMeetsEveryUrdfPrimitive)
{
  using S = TypeParam;
  const std::shared_ptr<fcl::OcTree<S>> octree = scanMap<S>();
  auto rng = test::seededRng("OcTreeMeetsEveryUrdfPrimitive/" + test::scalarName<S>());
  Environment<S> env(primitiveArm(), BVType::kRS), reference(primitiveArm(), BVType::kRS);
  fcl::Transform3<S> pose = test::randomPose<S>(rng, S(0));
  pose.translation() = fcl::Vector3<S>(S(0.45), 0, S(0.35));
  const MapPair<S> map(env, reference, octree, pose);
  int map_pairs = 0, map_shape_pairs = 0, map_nearest = 0;
  std::map<std::string, int> hits;
  for (int i = 0; i < (test::kSanitized ? 6 : 16); ++i)
  {
    const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
    SCOPED_TRACE(::testing::Message() << "configuration " << i << ": " << q.transpose());
    // FCL's GJK (libccd) meets a cylinder or sphere and a box in the two argument orders; it stops when an
    // iteration gains less than its tolerance, not when the gap is within it: the orders were seen 1.2e-5 apart
    // in distance and 4.4e-4 in nearest points (double; float about as much).
    expectSameAnswers(env, reference, q, &map_pairs, &map_shape_pairs, &map_nearest, Tolerances<S>{S(1e-4), S(2e-3)});
    for (const BodyPair& p : env.query(q, EnvironmentRequest{true, false}).pairs) hits[p.link] += p.other == "map";
  }
  std::cout << "[octree primitives] rod " << hits["rod"] << ", hand " << hits["hand"] << " colliding, nearest "
            << map_nearest << "\n";
  if (!test::kSanitized)
  {
    EXPECT_GT(hits["rod"], 0);
    EXPECT_GT(hits["hand"], 0);
    EXPECT_GT(map_nearest, 0);
  }
}

TYPED_TEST(EnvironmentTest, OcTreeMeetsLinkShapesAndMoves)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const fcl::VectorX<S> home = (fcl::VectorX<S>(8) << 0, S(-0.785), 0, S(-2.356), 0, S(1.571), S(0.785), S(0.02)).finished();
  // A small scanned ball (1.2 cm, 5 mm cells) about the origin, to be put at the left finger's rubber tip.
  const auto octree = std::make_shared<fcl::OcTree<S>>(surfaceOcTree(makeSphere<double>(0.012, 6, 10), 0.005));
  // The finger boxes take FCL's shape-octree paths whatever the BV type; the sanitized build (CI's budget) builds
  // the environments of two types only.
  std::vector<BVType> types{BVType::kRS, BVType::kOBBRSS};
  if (!test::kSanitized) types.insert(types.end(), {BVType::kOBB, BVType::kRSS});
  for (BVType bv : types)
  {
    SCOPED_TRACE(bvTypeName(bv));
    Environment<S> env(*panda(), bv, pandaSrdf()), reference(*panda(), bv, pandaSrdf());
    const MapPair<S> map(env, reference, octree, at<S>(2, 2, 2));
    int map_pairs = 0, map_shape_pairs = 0, map_nearest = 0;
    expectSameAnswers(env, reference, home, &map_pairs, &map_shape_pairs, &map_nearest);
    EXPECT_FALSE(env.query(home).colliding);
    const fcl::Transform3<S> finger = env.kinematics().linkPoses(home)[panda()->linkIndex("panda_leftfinger")];
    const fcl::Vector3<S> tip = finger * fcl::Vector3<S>(0, S(7.58e-3), S(45.25e-3));
    map.move(env, reference, at<S>(tip.x(), tip.y(), tip.z()));
    expectSameAnswers(env, reference, home, &map_pairs, &map_shape_pairs, &map_nearest);
    EXPECT_GT(map_shape_pairs, 0);
    // 4 cm beyond the tip, along the finger: the finger's box is the nearest body.
    const fcl::Vector3<S> beyond = finger * fcl::Vector3<S>(0, S(7.58e-3), S(0.085));
    map.move(env, reference, at<S>(beyond.x(), beyond.y(), beyond.z()));
    expectSameAnswers(env, reference, home, &map_pairs, &map_shape_pairs, &map_nearest);
    if (bv != BVType::kOBB)
    {
      EnvironmentRequest request;
      request.minimum_distance = true;
      const EnvironmentResult<S> result = env.query(home, request);
      EXPECT_EQ(result.nearest_pair, (BodyPair{"panda_leftfinger", "map", false}));
      EXPECT_GT(map_nearest, 0);
    }
    env.remove("map");
    EXPECT_FALSE(env.query(home).colliding);
    EXPECT_EQ(env.obstacleNames(), std::vector<std::string>{});
  }
}

TYPED_TEST(EnvironmentTest, OcTreeMotionChecksAgreeWithDenseSampling)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("OcTreeMotionChecksAgreeWithDenseSampling/" + test::scalarName<S>());
  // A scanned ball (5 cm, 2 cm cells) put on each segment's way.
  const auto octree = std::make_shared<fcl::OcTree<S>>(surfaceOcTree(makeSphere<double>(0.05, 6, 10), 0.02));
  Environment<S> rs(*panda(), BVType::kRS, pandaSrdf()), obbrss(*panda(), BVType::kOBBRSS, pandaSrdf());
  rs.addOcTree("map", octree, at<S>(2, 2, 2));
  obbrss.addOcTree("map", octree, at<S>(2, 2, 2));
  const int hand = panda()->linkIndex("panda_hand");
  const auto free = [&] {
    fcl::VectorX<S> q = rs.kinematics().randomConfiguration(rng);
    for (int tries = 0; tries < 100 && rs.query(q).colliding; ++tries) q = rs.kinematics().randomConfiguration(rng);
    return q;
  };
  std::uniform_real_distribution<double> step(-0.6, 0.6);
  const int samples = test::kSanitized ? 50 : 150;
  int colliding = 0, segments = 0;
  for (int i = 0; i < (test::kSanitized ? 2 : 6); ++i)
  {
    rs.setPose("map", at<S>(2, 2, 2));
    const fcl::VectorX<S> from = free();
    fcl::VectorX<S> to = from;
    for (int tries = 0; tries < 100 && (tries == 0 || rs.query(to).colliding); ++tries)
      for (int v = 0; v < to.size(); ++v)
        to[v] = std::clamp(S(from[v] + step(rng)), rs.kinematics().lower()[v], rs.kinematics().upper()[v]);
    // The ball about the hand halfway (every other segment), or 25 cm farther out from the robot's axis.
    fcl::Vector3<S> ball = rs.kinematics().linkPoses(along(from, to, S(0.5)))[hand].translation();
    if (i % 2) ball += S(0.25) * fcl::Vector3<S>(ball.x(), ball.y(), 0).normalized();
    rs.setPose("map", at<S>(ball.x(), ball.y(), ball.z()));
    SCOPED_TRACE(::testing::Message() << "segment " << i << " from " << from.transpose() << " to " << to.transpose());
    for (bool earliest : {true, false})
    {
      MotionRequest<S> request;
      request.earliest = earliest;
      expectMotionAgreesWithSampling(rs, from, to, samples, request, &colliding);
    }
    ++segments;
    if (i >= (test::kSanitized ? 1 : 2)) continue;
    // FCL's octree distance (OBBRSS): the first two segments, with and without contact.
    obbrss.setPose("map", rs.pose("map"));
    int obbrss_colliding = 0;
    expectMotionAgreesWithSampling(obbrss, from, to, samples, MotionRequest<S>{}, &obbrss_colliding);
    EXPECT_EQ(obbrss_colliding, rs.checkMotion(from, to).colliding ? 1 : 0);
  }
  std::cout << "[octree motion] " << colliding << " colliding of " << 2 * segments << "\n";
  EXPECT_GT(colliding, 0);
  EXPECT_LT(colliding, 2 * segments);
}

TYPED_TEST(EnvironmentTest, OcTreesWithoutOccupiedCellsNeverCollideUntilRefreshed)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("OcTreesWithoutOccupiedCellsNeverCollideUntilRefreshed/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf()), bare(*panda(), BVType::kRS, pandaSrdf());
  // A map without any node, and one whose cells (over the whole workspace) are all observed free.
  const auto nothing = std::make_shared<octomap::OcTree>(0.02);
  env.addOcTree("nothing", std::make_shared<fcl::OcTree<S>>(nothing), at<S>(0, 0, 0));
  const auto free_space = std::make_shared<octomap::OcTree>(0.05);
  for (double x = -0.8; x <= 0.8; x += 0.1)
    for (double y = -0.8; y <= 0.8; y += 0.1)
      for (double z = 0; z <= 1.2; z += 0.1) free_space->updateNode(octomap::point3d(float(x), float(y), float(z)), false);
  env.addOcTree("free", std::make_shared<fcl::OcTree<S>>(free_space), at<S>(0, 0, 0));
  for (auto* e : {&env, &bare}) e->addShape("post", std::make_shared<fcl::Box<S>>(S(0.05), S(0.05), S(1)), at<S>(S(0.6), S(0.3), S(0.5)));
  EnvironmentRequest request;
  request.colliding_pairs = request.minimum_distance = true;
  for (int i = 0; i < (test::kSanitized ? 3 : 6); ++i)
  {
    const fcl::VectorX<S> q = env.kinematics().randomConfiguration(rng);
    SCOPED_TRACE(::testing::Message() << "configuration " << i << ": " << q.transpose());
    const EnvironmentResult<S> result = env.query(q, request), expected = bare.query(q, request);
    EXPECT_EQ(result.colliding, expected.colliding);
    EXPECT_EQ(result.pairs, expected.pairs);
    EXPECT_EQ(result.minimum_distance, expected.minimum_distance);
    EXPECT_EQ(result.nearest_pair, expected.nearest_pair);
    if (i > 0) continue;
    fcl::VectorX<S> to = q;
    to[0] = std::clamp(S(q[0] + S(0.4)), env.kinematics().lower()[0], env.kinematics().upper()[0]);
    const MotionResult<S> motion = env.checkMotion(q, to), bare_motion = bare.checkMotion(q, to);
    EXPECT_EQ(motion.colliding, bare_motion.colliding);
    EXPECT_EQ(motion.parameter, bare_motion.parameter);
    EXPECT_EQ(motion.free_until, bare_motion.free_until);
  }
  const fcl::VectorX<S> home = (fcl::VectorX<S>(8) << 0, S(-0.785), 0, S(-2.356), 0, S(1.571), S(0.785), S(0.02)).finished();
  // The map filled after they were added: read again by refreshOcTree.
  const fcl::Vector3<S> hand = env.kinematics().linkPoses(home)[panda()->linkIndex("panda_hand")].translation();
  addSurface(*nothing, makeSphere<double>(0.03, 6, 10), at<double>(double(hand.x()), double(hand.y()), double(hand.z())));
  EXPECT_FALSE(env.query(home).colliding);  // the cells were read when it was added
  env.refreshOcTree("nothing");
  request.minimum_distance = false;
  const EnvironmentResult<S> hit = env.query(home, request);
  ASSERT_TRUE(hit.colliding);
  EXPECT_TRUE(std::any_of(hit.pairs.begin(), hit.pairs.end(), [](const BodyPair& p) { return p.other == "nothing"; }));
  env.remove("nothing");
  EXPECT_FALSE(env.query(home).colliding);
}

TYPED_TEST(EnvironmentTest, OcTreeBadInputIsRefused)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  Environment<S> env(*panda(), BVType::kRS);
  const auto octree = std::make_shared<fcl::OcTree<S>>(std::make_shared<octomap::OcTree>(0.1));
  expectInvalid([&] { env.addOcTree("m", nullptr, at<S>(0, 0, 0)); }, "'m'");
  expectInvalid([&] { env.addOcTree("", octree, at<S>(0, 0, 0)); }, "empty");
  fcl::Transform3<S> bad = at<S>(0, 0, 0);
  bad.linear()(1, 1) = S(0.5);
  expectInvalid([&] { env.addOcTree("m", octree, bad); }, "rigid");
  expectInvalid([&] { env.addOcTree("m", octree, at<S>(std::numeric_limits<S>::infinity(), 0, 0)); }, "rigid");
  EXPECT_FALSE(env.contains("m"));
  env.addOcTree("m", octree, at<S>(0, 0, 0));
  expectInvalid([&] { env.addOcTree("m", octree, at<S>(0, 0, 0)); }, "exists");
  expectInvalid([&] { env.setPose("m", bad); }, "rigid");
  env.addShape("box", std::make_shared<fcl::Box<S>>(S(0.1), S(0.1), S(0.1)), at<S>(2, 0, 0));
  expectInvalid([&] { env.refreshOcTree("box"); }, "not an octree");
  expectInvalid([&] { env.refreshOcTree("x"); }, "'x'");
  // An octree is not a shape.
  expectInvalid([&] { env.addShape("o", octree, at<S>(0, 0, 0)); }, "'o'");
}

#ifdef FCL_RS_TEST_BATCH
TYPED_TEST(EnvironmentTest, OcTreeBatchesEqualSingleCalls)
{
  using S = TypeParam;
  if (!panda()) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  auto rng = test::seededRng("OcTreeBatchesEqualSingleCalls/" + test::scalarName<S>());
  Environment<S> env(*panda(), BVType::kRS, pandaSrdf());
  const fcl::Transform3<S> pose = scanPose<S>(rng);
  env.addOcTree("map", scanMap<S>(), pose);
  expectBatchesEqualSingleCalls(env, rng, test::kSanitized ? 2 : 4);
}
#endif
#endif  // FCL_HAVE_OCTOMAP

}  // namespace
}  // namespace fcl_rs
