// Concurrency (issue 4): many threads querying the same const models get exactly the single-threaded answers.
// Run under ThreadSanitizer by scripts/test.sh --all (build-tsan), where a data race fails the test.
#include <algorithm>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision_object.h>
#include <gtest/gtest.h>

#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

constexpr int kThreads = 8;
constexpr int kPoses = 40;

/// Everything one pose's queries return.
template <typename S>
struct Answer
{
  fcl::CollisionResult<S> mesh_mesh;                 // exhaustive, with contact geometry (object overload)
  QueryStats rs_stats, obbrss_stats;                 // collideWithStats, local-frame paths
  test::TrianglePairs rs_pairs, obbrss_pairs;
  std::vector<fcl::CollisionResult<S>> mesh_shape;   // every shape, both orders, with contacts

  bool operator==(const Answer& o) const
  {
    if (!test::sameContacts(mesh_mesh, o.mesh_mesh) || mesh_shape.size() != o.mesh_shape.size()) return false;
    for (std::size_t i = 0; i < mesh_shape.size(); ++i)
      if (!test::sameContacts(mesh_shape[i], o.mesh_shape[i])) return false;
    const auto same = [](const QueryStats& a, const QueryStats& b) {
      return a.num_bv_tests == b.num_bv_tests && a.num_leaf_tests == b.num_leaf_tests;
    };
    return same(rs_stats, o.rs_stats) && same(obbrss_stats, o.obbrss_stats) && rs_pairs == o.rs_pairs &&
           obbrss_pairs == o.obbrss_pairs;
  }
};

/// Models shared by all threads; nothing in them is written after construction.
template <typename S>
struct Scene
{
  const TriangleMesh<S> sphere_mesh = makeSphere<S>(S(0.5), 10, 20);
  const TriangleMesh<S> torus_mesh = makeTorus<S>(S(0.6), S(0.2), 16, 8);
  const std::shared_ptr<fcl::BVHModel<RS<S>>> sphere = buildModel<RS<S>>(sphere_mesh);
  const std::shared_ptr<fcl::BVHModel<RS<S>>> torus = buildModel<RS<S>>(torus_mesh);
  const std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> sphere_obbrss = buildModel<fcl::OBBRSS<S>>(sphere_mesh);
  const std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> torus_obbrss = buildModel<fcl::OBBRSS<S>>(torus_mesh);
  const std::vector<std::shared_ptr<fcl::CollisionGeometry<S>>> shapes = {
      std::make_shared<fcl::Box<S>>(S(0.5), S(0.4), S(0.3)), std::make_shared<fcl::Sphere<S>>(S(0.3)),
      std::make_shared<fcl::Capsule<S>>(S(0.1), S(0.6)), std::make_shared<fcl::Cylinder<S>>(S(0.2), S(0.5)),
      std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(0, 0, 1), S(-0.3))};
  std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>> poses;
  // Collision objects are made here, once: FCL's CollisionObject constructor writes its geometry's local AABB,
  // so constructing objects on shared geometry in several threads at once is a data race inside FCL.
  std::vector<std::pair<std::unique_ptr<fcl::CollisionObject<S>>, std::unique_ptr<fcl::CollisionObject<S>>>> objects;

  explicit Scene(const std::string& what)
  {
    auto rng = test::seededRng(what);
    for (int i = 0; i < kPoses; ++i)
    {
      poses.emplace_back(test::randomPose<S>(rng, S(0.5)), test::randomPose<S>(rng, S(0.9)));
      objects.emplace_back(std::make_unique<fcl::CollisionObject<S>>(sphere, poses.back().first),
                           std::make_unique<fcl::CollisionObject<S>>(torus, poses.back().second));
    }
  }

  Answer<S> query(int i) const
  {
    const auto& [tf1, tf2] = poses[std::size_t(i)];
    Answer<S> a;
    fcl_rs::collide(objects[std::size_t(i)].first.get(), objects[std::size_t(i)].second.get(),
            test::allContactsRequest<S>(true), a.mesh_mesh);
    const fcl::CollisionRequest<S> pairs_only = test::allContactsRequest<S>(false);
    fcl::CollisionResult<S> r1, r2;
    a.rs_stats = collideWithStats(*sphere, tf1, *torus, tf2, pairs_only, r1);
    a.obbrss_stats = collideWithStats(*sphere_obbrss, tf1, *torus_obbrss, tf2, pairs_only, r2);
    a.rs_pairs = test::contactPairs(r1);
    a.obbrss_pairs = test::contactPairs(r2);
    for (const auto& shape : shapes)
    {
      fcl::CollisionResult<S> mesh_first, shape_first;
      fcl_rs::collide<S>(torus.get(), tf2, shape.get(), tf1, test::allContactsRequest<S>(true), mesh_first);
      fcl_rs::collide<S>(shape.get(), tf1, torus.get(), tf2, test::allContactsRequest<S>(true), shape_first);
      a.mesh_shape.push_back(mesh_first);
      a.mesh_shape.push_back(shape_first);
    }
    return a;
  }
};

/// Runs query(i) for every pose in kThreads threads at once; returns the mismatches with reference per thread.
template <typename Answer, typename Query>
std::vector<int> mismatchesUnderThreads(int poses, const std::vector<Answer>& reference, const Query& query)
{
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      // Each thread walks all poses from a different start, so different poses run at the same time.
      for (int k = 0; k < poses; ++k)
      {
        const int i = (k + t * poses / kThreads) % poses;
        mismatches[std::size_t(t)] += !(query(i) == reference[std::size_t(i)]);
      }
    });
  for (auto& th : threads) th.join();
  return mismatches;
}

template <typename S>
class Concurrency : public ::testing::Test
{
};
TYPED_TEST_SUITE(Concurrency, test::Scalars);

TYPED_TEST(Concurrency, QueriesOnSharedModelsMatchOneThread)
{
  using S = TypeParam;
  const Scene<S> scene("concurrency/queries");
  std::vector<Answer<S>> reference;
  int colliding = 0, shape_hits = 0;
  for (int i = 0; i < kPoses; ++i)
  {
    reference.push_back(scene.query(i));
    colliding += reference.back().mesh_mesh.isCollision();
    for (const auto& r : reference.back().mesh_shape) shape_hits += r.isCollision();
  }
  // Guards the test: the narrow phase (and its contact computation) runs for many poses.
  EXPECT_GT(colliding, kPoses / 4);
  EXPECT_GT(shape_hits, kPoses);

  const std::vector<int> mismatches =
      mismatchesUnderThreads(kPoses, reference, [&](int i) { return scene.query(i); });
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[std::size_t(t)], 0) << "thread " << t << " differs from one thread";
}

// collideWithStats on fixed-axis volumes (AABB, k-DOP) moves world-frame copies of the const models and rebuilds
// them. FCL's BVHModel copy constructor shares bv_splitter / bv_fitter with the original, so concurrent queries
// on one model rebuild through one splitter object: a data race (seen as a crash in the splitter).
TYPED_TEST(Concurrency, WorldFrameStatsOnSharedModelsMatchOneThread)
{
  using S = TypeParam;
  const auto sphere = buildModel<fcl::AABB<S>>(makeSphere<S>(S(0.5), 10, 20));
  const auto torus = buildModel<fcl::KDOP<S, 18>>(makeTorus<S>(S(0.6), S(0.2), 16, 8));
  const auto torus_aabb = buildModel<fcl::AABB<S>>(makeTorus<S>(S(0.6), S(0.2), 16, 8));
  const auto sphere_kdop = buildModel<fcl::KDOP<S, 18>>(makeSphere<S>(S(0.5), 10, 20));
  auto rng = test::seededRng("concurrency/world-frame");
  std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>> poses;
  for (int i = 0; i < kPoses / 4; ++i) poses.emplace_back(test::randomPose<S>(rng, S(0.5)), test::randomPose<S>(rng, S(0.9)));
  using Answer = std::pair<test::TrianglePairs, test::TrianglePairs>;
  const auto query = [&](int i) {
    const auto& [tf1, tf2] = poses[std::size_t(i)];
    fcl::CollisionResult<S> a, k;
    collideWithStats(*sphere, tf1, *torus_aabb, tf2, test::allContactsRequest<S>(false), a);
    collideWithStats(*sphere_kdop, tf1, *torus, tf2, test::allContactsRequest<S>(false), k);
    return Answer(test::contactPairs(a), test::contactPairs(k));
  };
  std::vector<Answer> reference;
  for (int i = 0; i < int(poses.size()); ++i) reference.push_back(query(i));
  const std::vector<int> mismatches = mismatchesUnderThreads(int(poses.size()), reference, query);
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[std::size_t(t)], 0) << "thread " << t;
}

TYPED_TEST(Concurrency, BuildsOfOneConstMeshAreIdentical)
{
  using S = TypeParam;
  const TriangleMesh<S> mesh = makeTorus<S>(S(0.6), S(0.2), 24, 12);
  const auto reference = buildModel<RS<S>>(mesh);
  const auto same = [&](const fcl::BVHModel<RS<S>>& m) {
    if (m.getNumBVs() != reference->getNumBVs()) return false;
    for (int i = 0; i < m.getNumBVs(); ++i)
    {
      const auto &a = m.getBV(i), &b = reference->getBV(i);
      if (a.bv.axis != b.bv.axis || a.bv.origin != b.bv.origin || a.bv.lo != b.bv.lo || a.bv.hi != b.bv.hi ||
          a.first_child != b.first_child)
        return false;
    }
    return true;
  };
  std::vector<int> identical(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 3; ++k) identical[std::size_t(t)] += same(*buildModel<RS<S>>(mesh));
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(identical[std::size_t(t)], 3) << "thread " << t << " built a different tree";
}

TEST(Concurrency, ParallelLoadsOfOneFileAreIdentical)
{
  const std::string path = test::assimpModel("STL/Spider_ascii.stl");
  ASSERT_FALSE(path.empty()) << "Debian's assimp-testmodels are required (the project's scripts install them)";
  const TriangleMesh<double> reference = loadMeshFile(path);
  std::vector<int> identical(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 2; ++k)
      {
        const TriangleMesh<double> m = loadMeshFile(path);
        identical[std::size_t(t)] += m.vertices == reference.vertices &&
                                     std::equal(m.triangles.begin(), m.triangles.end(), reference.triangles.begin(),
                                                reference.triangles.end(), [](const fcl::Triangle& a, const fcl::Triangle& b) {
                                                  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
                                                });
      }
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(identical[std::size_t(t)], 2) << "thread " << t << " loaded a different mesh";
}

}  // namespace
}  // namespace fcl_rs
