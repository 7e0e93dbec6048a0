// RS meshes against fcl::OcTree (fcl_rs/traversal/octree_traversal.h through fcl_rs::collide and
// fcl_rs::distance): the same answers as FCL's OBBRSS mesh against the same octree, both argument orders, float
// and double, on seeded poses about an octree sampled from a generated mesh's surface.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <tuple>
#include <vector>

#include <fcl/geometry/octree/octree.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/mesh/surface_octree.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

using test::randomPose;
using test::seededRng;

/// An octree of a torus's surface (radii 1 and 0.3, cells of 0.08) and a small ellipsoid mesh with RS and OBBRSS
/// trees, posed about the torus so that about half the poses collide.
template <typename S>
struct Scene
{
  std::shared_ptr<octomap::OcTree> map;
  std::shared_ptr<fcl::OcTree<S>> octree;
  std::shared_ptr<fcl::BVHModel<RS<S>>> rs;
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> obbrss;
  std::vector<fcl::Transform3<S>> poses;

  explicit Scene(const char* seed_name, int num_poses = 24)
  {
    map = surfaceOcTree(makeTorus<double>(1.0, 0.3, 24, 12), 0.08);
    octree = std::make_shared<fcl::OcTree<S>>(map);
    const TriangleMesh<S> body = makeEllipsoid<S>(S(0.35), S(0.2), S(0.12), 6, 10);
    rs = buildModel<RS<S>>(body);
    obbrss = buildModel<fcl::OBBRSS<S>>(body);
    auto rng = seededRng(seed_name);
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), radial(0.4, 1.6), height(-0.5, 0.5);
    for (int i = 0; i < num_poses; ++i)
    {
      fcl::Transform3<S> tf = randomPose<S>(rng, S(0));
      const double a = angle(rng), r = radial(rng);
      tf.translation() = fcl::Vector3<S>(S(r * std::cos(a)), S(r * std::sin(a)), S(height(rng)));
      poses.push_back(tf);
    }
  }
};

template <typename S>
class OcTreeTraversalTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(OcTreeTraversalTest, test::Scalars);

using ContactKey = std::tuple<int, int>;

template <typename S>
S deepest(const fcl::CollisionResult<S>& result)
{
  S depth = 0;
  for (std::size_t c = 0; c < result.numContacts(); ++c)
    depth = std::max(depth, std::abs(result.getContact(c).penetration_depth));
  return depth;
}

template <typename S>
std::set<ContactKey> contactKeys(const fcl::CollisionResult<S>& result, const fcl::CollisionGeometry<S>* octree)
{
  std::set<ContactKey> keys;
  for (std::size_t i = 0; i < result.numContacts(); ++i)
  {
    const fcl::Contact<S>& c = result.getContact(i);
    EXPECT_EQ(c.o1, octree);  // FCL names the octree first in either argument order
    keys.emplace(c.b1, c.b2);
  }
  return keys;
}

/// fcl_rs::collide on the RS mesh and fcl::collide on the OBBRSS mesh, octree first or second.
template <typename S>
void collideBoth(const Scene<S>& scene, const fcl::Transform3<S>& tf, bool octree_first,
                 const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& rs, fcl::CollisionResult<S>& fcl)
{
  const fcl::Transform3<S> id = fcl::Transform3<S>::Identity();
  if (octree_first)
  {
    fcl_rs::collide<S>(scene.octree.get(), id, scene.rs.get(), tf, request, rs);
    fcl::collide<S>(scene.octree.get(), id, scene.obbrss.get(), tf, request, fcl);
  }
  else
  {
    fcl_rs::collide<S>(scene.rs.get(), tf, scene.octree.get(), id, request, rs);
    fcl::collide<S>(scene.obbrss.get(), tf, scene.octree.get(), id, request, fcl);
  }
}

TYPED_TEST(OcTreeTraversalTest, ContactsAreFCLsInBothOrders)
{
  using S = TypeParam;
  const Scene<S> scene("OcTreeContactsAreFCLs");
  int colliding = 0;
  for (std::size_t i = 0; i < scene.poses.size(); ++i)
    for (bool octree_first : {true, false})
    {
      // Every contact, with and without contact geometry, then the first only.
      for (bool geometry : {false, true})
      {
        fcl::CollisionRequest<S> all(std::numeric_limits<std::size_t>::max(), geometry);
        fcl::CollisionResult<S> rs, fcl;
        collideBoth(scene, scene.poses[i], octree_first, all, rs, fcl);
        ASSERT_EQ(contactKeys(rs, scene.octree.get()), contactKeys(fcl, scene.octree.get()))
            << "pose " << i << " octree first " << octree_first << " geometry " << geometry;
        colliding += geometry && rs.isCollision();
        if (!geometry || !rs.isCollision()) continue;
        // The same leaf test of the same cell and triangle: the same depth.
        EXPECT_EQ(deepest(rs), deepest(fcl)) << "pose " << i;
      }
      fcl::CollisionRequest<S> first;
      fcl::CollisionResult<S> rs, fcl;
      collideBoth(scene, scene.poses[i], octree_first, first, rs, fcl);
      EXPECT_EQ(rs.isCollision(), fcl.isCollision()) << "pose " << i;
      EXPECT_EQ(rs.numContacts(), fcl.numContacts()) << "pose " << i;
    }
  EXPECT_GT(colliding, 4);
  EXPECT_LT(colliding, int(2 * scene.poses.size()) - 4);
}

/// Cost sources as comparable values: the overlap box's corners and the cost density.
template <typename S>
std::multiset<std::vector<S>> costKeys(const fcl::CollisionResult<S>& result)
{
  std::vector<fcl::CostSource<S>> sources;
  result.getCostSources(sources);
  std::multiset<std::vector<S>> keys;
  for (const auto& c : sources)
    keys.insert(
        {c.aabb_min[0], c.aabb_min[1], c.aabb_min[2], c.aabb_max[0], c.aabb_max[1], c.aabb_max[2], c.cost_density});
  return keys;
}

// Occupancy thresholds and cost as FCL defines them: some cells made uncertain (between the free and the
// occupied threshold) and some free, the octree's thresholds moved, exact and approximate cost; contacts and cost
// sources (unknown space included) are FCL's.
TYPED_TEST(OcTreeTraversalTest, ThresholdsAndCostSourcesAreFCLs)
{
  using S = TypeParam;
  Scene<S> scene("OcTreeThresholdsAndCost", 10);
  // Every third leaf uncertain (probability 0.6), every seventh free (0.3).
  int k = 0;
  for (auto it = scene.map->begin_leafs(); it != scene.map->end_leafs(); ++it, ++k)
  {
    if (k % 3 == 0) scene.map->setNodeValue(it.getKey(), octomap::logodds(0.6f));
    if (k % 7 == 0) scene.map->setNodeValue(it.getKey(), octomap::logodds(0.3f));
  }
  scene.map->updateInnerOccupancy();
  for (double occupied : {0.7, 0.55})
  {
    scene.octree->setOccupancyThres(S(occupied));
    scene.octree->setFreeThres(S(0.35));
    for (std::size_t i = 0; i < scene.poses.size(); ++i)
      for (bool octree_first : {true, false})
        for (bool approximate : {false, true})
        {
          fcl::CollisionRequest<S> request(std::numeric_limits<std::size_t>::max(), false, 50, true, approximate);
          fcl::CollisionResult<S> rs, fcl;
          collideBoth(scene, scene.poses[i], octree_first, request, rs, fcl);
          EXPECT_EQ(contactKeys(rs, scene.octree.get()), contactKeys(fcl, scene.octree.get()))
              << "pose " << i << " threshold " << occupied;
          EXPECT_EQ(costKeys(rs), costKeys(fcl)) << "pose " << i << " threshold " << occupied << " approximate "
                                                 << approximate << " octree first " << octree_first;
        }
  }
}

TYPED_TEST(OcTreeTraversalTest, DistanceAndSignedDistanceAreFCLs)
{
  using S = TypeParam;
  const Scene<S> scene("OcTreeDistanceIsFCLs");
  const fcl::Transform3<S> id = fcl::Transform3<S>::Identity();
  int apart = 0, signed_checked = 0;
  for (std::size_t i = 0; i < scene.poses.size(); ++i)
    for (bool octree_first : {true, false})
    {
      const fcl::Transform3<S>& tf = scene.poses[i];
      fcl::DistanceRequest<S> request(true);
      fcl::DistanceResult<S> rs, fcl;
      const S d_rs = octree_first ? fcl_rs::distance<S>(scene.octree.get(), id, scene.rs.get(), tf, request, rs)
                                  : fcl_rs::distance<S>(scene.rs.get(), tf, scene.octree.get(), id, request, rs);
      const S d_fcl = octree_first ? fcl::distance<S>(scene.octree.get(), id, scene.obbrss.get(), tf, request, fcl)
                                   : fcl::distance<S>(scene.obbrss.get(), tf, scene.octree.get(), id, request, fcl);
      if (d_fcl > 0)
      {
        ++apart;
        // The same box-triangle distance of the nearest cell and triangle.
        EXPECT_NEAR(d_rs, d_fcl, 16 * std::numeric_limits<S>::epsilon()) << "pose " << i;
        EXPECT_EQ(rs.o1, fcl.o1);
        EXPECT_NEAR((rs.nearest_points[0] - fcl.nearest_points[0]).norm(), 0, S(1e-3)) << "pose " << i;
        EXPECT_NEAR((rs.nearest_points[1] - fcl.nearest_points[1]).norm(), 0, S(1e-3)) << "pose " << i;
      }
      else
        EXPECT_LE(d_rs, 0) << "pose " << i;

      // Signed: minus the deepest penetration of all contacts (FCL's own fallback takes the first contact its
      // traversal meets; fcl_rs::distance searches them all, as for meshes).
      fcl::DistanceRequest<S> signed_request(false);
      signed_request.enable_signed_distance = true;
      fcl::DistanceResult<S> signed_rs;
      if (octree_first)
        fcl_rs::distance<S>(scene.octree.get(), id, scene.rs.get(), tf, signed_request, signed_rs);
      else
        fcl_rs::distance<S>(scene.rs.get(), tf, scene.octree.get(), id, signed_request, signed_rs);
      fcl::CollisionRequest<S> contacts(std::numeric_limits<std::size_t>::max(), true);
      fcl::CollisionResult<S> all;
      fcl::collide<S>(scene.octree.get(), id, scene.obbrss.get(), tf, contacts, all);
      if (d_fcl > 0)
        EXPECT_NEAR(signed_rs.min_distance, d_fcl, 16 * std::numeric_limits<S>::epsilon()) << "pose " << i;
      else if (all.isCollision())
      {
        EXPECT_EQ(signed_rs.min_distance, -deepest(all)) << "pose " << i;
        ++signed_checked;
      }
    }
  EXPECT_GT(apart, 8);
  EXPECT_GT(signed_checked, 8);
}

TYPED_TEST(OcTreeTraversalTest, EmptyOcTreeNeitherCollidesNorHasADistance)
{
  using S = TypeParam;
  const fcl::OcTree<S> empty(std::make_shared<octomap::OcTree>(0.1));
  const auto mesh = buildModel<RS<S>>(makeBox<S>(1, 1, 1));
  const fcl::Transform3<S> id = fcl::Transform3<S>::Identity();
  fcl::CollisionRequest<S> request;
  fcl::CollisionResult<S> result;
  EXPECT_EQ(fcl_rs::collide<S>(&empty, id, mesh.get(), id, request, result), 0u);
  fcl::DistanceResult<S> distance;
  fcl_rs::distance<S>(mesh.get(), id, &empty, id, fcl::DistanceRequest<S>(), distance);
  EXPECT_EQ(distance.min_distance, std::numeric_limits<S>::max());
}

}  // namespace
}  // namespace fcl_rs
