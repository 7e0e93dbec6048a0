// Batches (issue 16): every thread count gives exactly the single-query answers (the threaded cases form the
// Concurrency suite, which CI also runs under ThreadSanitizer with the batch on std::threads: docs/batch.md).
#include <memory>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h>
#include <gtest/gtest.h>

#include "fcl_rs/batch.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/robot/batch_self_collision.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

constexpr int kThreadCounts[] = {1, 2, 4};

template <typename S>
struct PosePairs
{
  const std::shared_ptr<fcl::BVHModel<RS<S>>> torus = buildModel<RS<S>>(makeTorus<S>(S(0.6), S(0.2), 16, 8));
  const std::shared_ptr<fcl::BVHModel<RS<S>>> sphere = buildModel<RS<S>>(makeSphere<S>(S(0.5), 10, 20));
  const fcl::Box<S> box{S(0.5), S(0.4), S(0.3)};
  std::vector<fcl::Transform3<S>> poses_a, poses_b;

  explicit PosePairs(const std::string& what, int n)
  {
    auto rng = test::seededRng(what);
    for (int i = 0; i < n; ++i)
    {
      poses_a.push_back(test::randomPose<S>(rng, S(0.5)));
      poses_b.push_back(test::randomPose<S>(rng, S(0.9)));
    }
  }
};

/// A chain of six box links that folds onto itself: root, five links on revolute joints about x and y
/// alternately, and a sphere primitive on link 3, so mesh-mesh, mesh-shape pairs and misses all occur.
RobotModel foldingChain()
{
  RobotModel robot;
  robot.name = "folding_chain";
  for (int i = 0; i < 6; ++i)
  {
    RobotLink link;
    link.name = "link" + std::to_string(i);
    const TriangleMesh<double> box = makeBox<double>(0.12, 0.12, 0.4);
    for (const auto& v : box.vertices) link.mesh.vertices.push_back(v + fcl::Vector3d(0, 0, 0.2));
    link.mesh.triangles = box.triangles;
    if (i == 3)
    {
      Primitive ball;
      ball.type = Primitive::Type::kSphere;
      ball.size = fcl::Vector3d(0.1, 0, 0);
      ball.origin.translation() << 0.15, 0, 0.2;
      link.primitives.push_back(ball);
    }
    if (i > 0)
    {
      RobotJoint joint;
      joint.name = "joint" + std::to_string(i);
      joint.type = JointType::kRevolute;
      joint.parent_link = i - 1;
      joint.child_link = i;
      joint.origin.translation() << 0, 0, 0.42;
      joint.axis = i % 2 ? fcl::Vector3d::UnitX() : fcl::Vector3d::UnitY();
      joint.lower = -2.8;
      joint.upper = 2.8;
      joint.variable = robot.numVariables();
      link.parent_joint = int(robot.joints.size());
      robot.variable_joints.push_back(int(robot.joints.size()));
      robot.joints.push_back(joint);
    }
    robot.links.push_back(link);
  }
  return robot;
}

template <typename S>
Configurations<S> randomConfigurations(const Kinematics<S>& kinematics, const std::string& what, int n)
{
  auto rng = test::seededRng(what);
  Configurations<S> q(n, kinematics.numVariables());
  for (int i = 0; i < n; ++i) q.row(i) = kinematics.randomConfiguration(rng).transpose();
  return q;
}

template <typename S>
class Concurrency : public ::testing::Test
{
};
TYPED_TEST_SUITE(Concurrency, test::Scalars);

TYPED_TEST(Concurrency, CollideBatchEqualsSingleQueries)
{
  using S = TypeParam;
  const PosePairs<S> scene("collideBatch", 60);
  const fcl::CollisionRequest<S> request(/*num_max_contacts=*/100000, /*enable_contact=*/true);
  for (const fcl::CollisionGeometry<S>* b : {static_cast<const fcl::CollisionGeometry<S>*>(scene.sphere.get()),
                                             static_cast<const fcl::CollisionGeometry<S>*>(&scene.box)})
  {
    std::vector<fcl::CollisionResult<S>> single(scene.poses_a.size());
    int colliding = 0;
    for (std::size_t i = 0; i < single.size(); ++i)
      colliding += collide(scene.torus.get(), scene.poses_a[i], b, scene.poses_b[i], request, single[i]) > 0;
    EXPECT_GT(colliding, 5);
    EXPECT_LT(colliding, int(single.size()) - 5);
    for (int threads : kThreadCounts)
    {
      const auto batch = collideBatch<S>(*scene.torus, scene.poses_a, *b, scene.poses_b, request, {threads});
      ASSERT_EQ(batch.size(), single.size());
      for (std::size_t i = 0; i < single.size(); ++i)
        EXPECT_TRUE(test::sameContacts(batch[i], single[i])) << "pose " << i << ", " << threads << " threads";
    }
  }
}

TYPED_TEST(Concurrency, DistanceBatchEqualsSingleQueries)
{
  using S = TypeParam;
  const PosePairs<S> scene("distanceBatch", 40);
  fcl::DistanceRequest<S> request;
  request.enable_nearest_points = true;
  std::vector<fcl::DistanceResult<S>> single(scene.poses_a.size());
  for (std::size_t i = 0; i < single.size(); ++i)
    distance<S>(scene.torus.get(), scene.poses_a[i], scene.sphere.get(), scene.poses_b[i], request, single[i]);
  for (int threads : kThreadCounts)
  {
    const auto batch = distanceBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, scene.poses_b, request, {threads});
    ASSERT_EQ(batch.size(), single.size());
    for (std::size_t i = 0; i < single.size(); ++i)
    {
      EXPECT_EQ(batch[i].min_distance, single[i].min_distance) << "pose " << i << ", " << threads << " threads";
      EXPECT_EQ(batch[i].nearest_points[0], single[i].nearest_points[0]);
      EXPECT_EQ(batch[i].nearest_points[1], single[i].nearest_points[1]);
      EXPECT_EQ(batch[i].b1, single[i].b1);
      EXPECT_EQ(batch[i].b2, single[i].b2);
    }
  }
}

TYPED_TEST(Concurrency, SelfCollisionBatchEqualsSingleChecks)
{
  using S = TypeParam;
  const RobotModel robot = foldingChain();
  for (BVType bv : {BVType::kRS, BVType::kOBBRSS})
  {
    SelfCollision<S> checker(robot, bv);
    const Configurations<S> q = randomConfigurations(checker.kinematics(), "selfCollisionBatch", 120);
    std::vector<std::vector<LinkPair>> single;
    int colliding = 0;
    for (int i = 0; i < q.rows(); ++i)
    {
      single.push_back(checker.check(q.row(i).transpose()));
      colliding += !single.back().empty();
    }
    EXPECT_GT(colliding, 5);
    EXPECT_LT(colliding, int(q.rows()) - 5);
    SelfCheckRequest request;
    request.colliding_pairs = request.minimum_distance = true;
    std::vector<S> reference_distance;
    for (int threads : kThreadCounts)
    {
      const SelfCollisionBatchResult<S> batch = selfCollisionBatch(checker, q, request, {threads});
      const SelfCollisionBatchResult<S> flags = selfCollisionBatch(checker, q, {}, {threads});
      ASSERT_EQ(batch.colliding.size(), single.size());
      EXPECT_TRUE(flags.pairs.empty() && flags.minimum_distance.empty());
      for (std::size_t i = 0; i < single.size(); ++i)
      {
        EXPECT_EQ(bool(batch.colliding[i]), !single[i].empty()) << "configuration " << i << ", " << threads;
        EXPECT_EQ(flags.colliding[i], batch.colliding[i]);
        EXPECT_EQ(batch.pairs[i], single[i]);
        // Colliding exactly when the distance is 0; a free configuration's distance is positive.
        EXPECT_EQ(batch.minimum_distance[i] == 0, !single[i].empty()) << batch.minimum_distance[i];
        const SelfCheckResult<S> one = checker.query(q.row(Eigen::Index(i)).transpose(), request);
        EXPECT_EQ(one.minimum_distance, batch.minimum_distance[i]);
      }
      if (reference_distance.empty()) reference_distance = batch.minimum_distance;
      EXPECT_EQ(batch.minimum_distance, reference_distance);
    }
  }
}

TYPED_TEST_SUITE(Batch, test::Scalars);
template <typename S>
class Batch : public ::testing::Test
{
};

TYPED_TEST(Batch, MinimumDistanceIsTheSmallestLinkDistance)
{
  using S = TypeParam;
  const RobotModel robot = foldingChain();
  const SelfCollision<S> checker(robot, BVType::kRS);
  const Configurations<S> q = randomConfigurations(checker.kinematics(), "minimumDistance", 30);
  SelfCheckRequest request;
  request.minimum_distance = true;
  // Every triangle pair of the two links' meshes, in double.
  const auto mesh_distance = [&](int a, const fcl::Transform3d& ta, int b, const fcl::Transform3d& tb) {
    const TriangleMesh<double>&ma = robot.links[std::size_t(a)].mesh, &mb = robot.links[std::size_t(b)].mesh;
    double d = std::numeric_limits<double>::infinity();
    fcl::Vector3d p, r;
    for (const auto& x : ma.triangles)
      for (const auto& y : mb.triangles)
        d = std::min(d, fcl::detail::TriangleDistance<double>::triDistance(
                            ta * ma.vertices[x[0]], ta * ma.vertices[x[1]], ta * ma.vertices[x[2]],
                            tb * mb.vertices[y[0]], tb * mb.vertices[y[1]], tb * mb.vertices[y[2]], p, r));
    return d;
  };
  int checked = 0;
  for (int i = 0; i < q.rows(); ++i)
  {
    const fcl::VectorX<S> qi = q.row(i).transpose();
    const SelfCheckResult<S> result = checker.query(qi, request);
    if (result.colliding) continue;
    const auto poses = checker.kinematics().linkPoses(qi);
    // Link 3's sphere only adds geometry, so the meshes' distance bounds the links' distance from above, and
    // it is the exact answer whenever it is below every distance that involves the sphere.
    double brute = std::numeric_limits<double>::infinity();
    for (const LinkPair& p : checker.pairs())
      brute = std::min(brute, mesh_distance(p.first, poses[std::size_t(p.first)].template cast<double>(), p.second,
                                            poses[std::size_t(p.second)].template cast<double>()));
    EXPECT_LE(double(result.minimum_distance), brute * (1 + 1e-4) + 1e-6);
    EXPECT_GT(result.minimum_distance, 0);
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

TYPED_TEST(Batch, BadInputIsAnError)
{
  using S = TypeParam;
  const PosePairs<S> scene("batchErrors", 3);
  std::vector<fcl::Transform3<S>> fewer(scene.poses_b.begin(), scene.poses_b.end() - 1);
  test::expectError([&] { collideBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, fewer, {}); },
                    {"collideBatch", "3 poses", "2"});
  test::expectError([&] { distanceBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, fewer, fcl::DistanceRequest<S>()); },
                    {"distanceBatch", "3 poses", "2"});
  test::expectError([&] { collideBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, scene.poses_b, {}, {-1}); },
                    {"thread count", "-1"});

  // Each pose array is validated once, before any query, naming the element; so is the request.
  std::vector<fcl::Transform3<S>> bad = scene.poses_b;
  bad[2].translation()[0] = std::numeric_limits<S>::infinity();
  for (const int threads : {1, 2})
  {
    test::expectError([&] { collideBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, bad, {}, {threads}); },
                      {"fcl_rs::collideBatch: poses_b[2] is not a rigid transform: entry (0, 3) is inf"});
    test::expectError(
        [&] { distanceBatch<S>(*scene.torus, bad, *scene.sphere, scene.poses_b, fcl::DistanceRequest<S>(), {threads}); },
                      {"fcl_rs::distanceBatch: poses_a[2] is not a rigid transform: entry (0, 3) is inf"});
  }
  bad = scene.poses_a;
  bad[1].linear() *= S(1.001);
  test::expectError([&] { collideBatch<S>(*scene.torus, bad, *scene.sphere, scene.poses_b, {}); },
                    {"fcl_rs::collideBatch: poses_a[1] is not a rigid transform: its rotation is not orthonormal"});
  test::expectError([&] { collideBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, scene.poses_b, {0}); },
                    {"fcl_rs::collideBatch: request.num_max_contacts must be at least 1"});
  fcl::DistanceRequest<S> bad_request;
  bad_request.abs_err = std::numeric_limits<S>::quiet_NaN();
  test::expectError([&] { distanceBatch<S>(*scene.torus, scene.poses_a, *scene.sphere, scene.poses_b, bad_request); },
                    {"fcl_rs::distanceBatch: request.abs_err"});
  // So are the two shapes' sizes (tests/test_validate.cpp tries every kind).
  const fcl::Box<S> flat(S(1), S(0), S(1));
  test::expectError([&] { collideBatch<S>(flat, scene.poses_a, *scene.torus, scene.poses_b, {}); },
                    {"fcl_rs::collideBatch: a is an fcl::Box with side (1, 0, 1)"});
  test::expectError([&] { distanceBatch<S>(*scene.torus, scene.poses_a, flat, scene.poses_b, fcl::DistanceRequest<S>()); },
                    {"fcl_rs::distanceBatch: b is an fcl::Box with side (1, 0, 1)"});

  const RobotModel robot = foldingChain();
  const SelfCollision<S> rs(robot, BVType::kRS);
  const Configurations<S> wide = Configurations<S>::Zero(4, 7);
  test::expectError([&] { selfCollisionBatch(rs, wide); }, {"7 columns", "5 joint variables"});
  Configurations<S> nan = Configurations<S>::Zero(4, 5);
  nan(2, 1) = std::numeric_limits<S>::quiet_NaN();
  test::expectError([&] { selfCollisionBatch(rs, nan, {}, {2}); },
                    {"fcl_rs::selfCollisionBatch: configurations[2, 1] is not finite: nan"});
  nan(2, 1) = -std::numeric_limits<S>::infinity();
  test::expectError([&] { selfCollisionBatch(rs, nan, {}, {1}); }, {"configurations[2, 1] is not finite: -inf"});
  const SelfCollision<S> kdop(robot, BVType::kKDOP18);
  test::expectError([&] { selfCollisionBatch(kdop, Configurations<S>::Zero(4, 5)); }, {"KDOP18"});
  const SelfCollision<S> obb(robot, BVType::kOBB);
  SelfCheckRequest distance;
  distance.minimum_distance = true;
  test::expectError([&] { selfCollisionBatch(obb, Configurations<S>::Zero(1, 5), distance); }, {"OBB"});
  EXPECT_TRUE(selfCollisionBatch(obb, Configurations<S>::Zero(0, 5)).colliding.empty());
}

}  // namespace
}  // namespace fcl_rs
