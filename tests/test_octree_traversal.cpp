// RS meshes against fcl::OcTree (fcl_rs/traversal/octree_traversal.h through fcl_rs::collide and
// fcl_rs::distance), both argument orders, float and double, on seeded poses about an octree sampled from a
// generated mesh's surface: contacts and distances against a brute force (every occupied leaf cell's box against
// every triangle with the mesh-shape leaf test, TriangleShapeLeaf), and against FCL's OBBRSS mesh on the same
// octree, which differs only at grazing pairs (FCL's leaf is GJK).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <iterator>
#include <iterator>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <fcl/geometry/octree/octree.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/mesh/surface_octree.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/octree_traversal.h"
#include "octree_cells.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

using test::LeafCell;
using test::seededRng;

/// An octree of a torus's surface (radii 1 and 0.3, cells of 0.1) and a small ellipsoid mesh with RS and OBBRSS
/// trees, posed about the torus so that about half the poses collide.
template <typename S>
struct Scene
{
  std::shared_ptr<octomap::OcTree> map;
  std::shared_ptr<fcl::OcTree<S>> octree;
  TriangleMesh<S> body;
  std::shared_ptr<fcl::BVHModel<RS<S>>> rs;
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> obbrss;
  std::vector<fcl::Transform3<S>> poses;
  fcl::Transform3<S> tf_octree;

  Scene(const char* seed_name, int num_poses)
  {
    map = surfaceOcTree(makeTorus<double>(1.0, 0.3, 24, 12), 0.1);
    octree = std::make_shared<fcl::OcTree<S>>(map);
    body = makeEllipsoid<S>(S(0.35), S(0.2), S(0.12), 6, 10);
    rs = buildModel<RS<S>>(body);
    obbrss = buildModel<fcl::OBBRSS<S>>(body);
    auto rng = seededRng(seed_name);
    // The octree posed too: its cells are boxes at the octree's pose in every leaf test.
    tf_octree = test::randomPose<S>(rng, S(0.5));
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), radial(0.2, 1.8), height(-0.7, 0.7);
    for (int i = 0; i < num_poses; ++i)
    {
      fcl::Transform3<S> tf = test::randomPose<S>(rng, S(0));
      const double a = angle(rng), r = radial(rng);
      tf.translation() = tf_octree * fcl::Vector3<S>(S(r * std::cos(a)), S(r * std::sin(a)), S(height(rng)));
      poses.push_back(tf);
    }
  }

  std::vector<LeafCell<S>> leaves() const { return test::leafCells(*octree); }
};

template <typename S>
class OcTreeTraversalTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(OcTreeTraversalTest, test::Scalars);

using ContactKey = std::pair<int, int>;  // (cell, triangle) as FCL numbers them

/// The cell's box at the octree's pose and the mesh-shape leaf test of it against the mesh at tf.
template <typename S>
TriangleShapeLeaf<fcl::Box<S>> cellLeaf(const LeafCell<S>& cell, const fcl::Transform3<S>& tf_octree,
                                        const fcl::Transform3<S>& tf, fcl::Box<S>& box, fcl::Transform3<S>& box_tf)
{
  fcl::constructBox(cell.box, tf_octree, box, box_tf);
  return TriangleShapeLeaf<fcl::Box<S>>(box, tf, box_tf);
}

/// A triangle's bounding ball in the world frame, computed once per pose for the brute forces below.
struct Ball
{
  Eigen::Vector3d centre;
  double radius;
};

template <typename S>
std::vector<Ball> triangleBalls(const TriangleMesh<S>& mesh, const fcl::Transform3<S>& tf)
{
  std::vector<Ball> balls;
  for (const auto& tri : mesh.triangles)
  {
    const Eigen::Vector3d a = (tf * mesh.vertices[tri[0]]).template cast<double>(),
                          b = (tf * mesh.vertices[tri[1]]).template cast<double>(),
                          c = (tf * mesh.vertices[tri[2]]).template cast<double>();
    const Eigen::Vector3d centre = (a + b + c) / 3;
    balls.push_back({centre, std::max({(a - centre).norm(), (b - centre).norm(), (c - centre).norm()})});
  }
  return balls;
}

/// Whether the box's and the triangle's bounding spheres are apart by more than `margin`: the brute forces skip only
/// such pairs (with a margin above the leaf test's tolerance, which is large for float and the octree's large
/// unknown cells).
template <typename S>
bool spheresApart(const fcl::Box<S>& box, const fcl::Transform3<S>& box_tf, const Ball& triangle, double margin)
{
  const double r_box = box.side.template cast<double>().norm() / 2;
  return (box_tf.translation().template cast<double>() - triangle.centre).norm() > triangle.radius + r_box + margin;
}

template <typename S>
std::array<fcl::Vector3<S>, 3> trianglePoints(const TriangleMesh<S>& mesh, std::size_t t)
{
  const auto& tri = mesh.triangles[t];
  return {mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]};
}

/// Brute force: every occupied leaf cell against every triangle (an occupied mesh), with the leaf test.
template <typename S>
std::set<ContactKey> bruteForceContacts(const Scene<S>& scene, const std::vector<LeafCell<S>>& leaves,
                                        const fcl::Transform3<S>& tf)
{
  const std::vector<Ball> balls = triangleBalls(scene.body, tf);
  std::set<ContactKey> keys;
  for (const LeafCell<S>& cell : leaves)
  {
    if (!cell.node || !scene.octree->isNodeOccupied(cell.node)) continue;
    fcl::Box<S> box;
    fcl::Transform3<S> box_tf;
    const auto leaf = cellLeaf(cell, scene.tf_octree, tf, box, box_tf);
    for (std::size_t t = 0; t < balls.size(); ++t)
    {
      const auto p = trianglePoints(scene.body, t);
      if (spheresApart(box, box_tf, balls[t], 1e-3 + 2 * double(leaf.tolerance(p.data())))) continue;
      if (leaf.meets(p.data())) keys.emplace(int(cell.node - scene.octree->getRoot()), int(t));
    }
  }
  return keys;
}

/// Brute force: the smallest leaf distance of an occupied leaf cell and a triangle.
template <typename S>
S bruteForceDistance(const Scene<S>& scene, const std::vector<LeafCell<S>>& leaves, const fcl::Transform3<S>& tf)
{
  const std::vector<Ball> balls = triangleBalls(scene.body, tf);
  S best = std::numeric_limits<S>::max();
  for (const LeafCell<S>& cell : leaves)
  {
    if (!cell.node || !scene.octree->isNodeOccupied(cell.node)) continue;
    fcl::Box<S> box;
    fcl::Transform3<S> box_tf;
    const auto leaf = cellLeaf(cell, scene.tf_octree, tf, box, box_tf);
    for (std::size_t t = 0; t < balls.size(); ++t)
    {
      if (best < std::numeric_limits<S>::max() && spheresApart(box, box_tf, balls[t], double(best))) continue;
      const auto p = trianglePoints(scene.body, t);
      fcl::Vector3<S> on_mesh, on_shape;
      best = std::min(best, leaf.distance(p.data(), on_mesh, on_shape));
    }
  }
  return best;
}

template <typename S>
std::map<ContactKey, fcl::Contact<S>> contactsByKey(const fcl::CollisionResult<S>& result,
                                                   const fcl::CollisionGeometry<S>* octree)
{
  std::map<ContactKey, fcl::Contact<S>> contacts;
  for (std::size_t i = 0; i < result.numContacts(); ++i)
  {
    const fcl::Contact<S>& c = result.getContact(i);
    EXPECT_EQ(c.o1, octree);  // FCL names the octree first in either argument order
    contacts.emplace(ContactKey(c.b1, c.b2), c);
  }
  return contacts;
}

template <typename S>
std::set<ContactKey> keysOf(const std::map<ContactKey, fcl::Contact<S>>& contacts)
{
  std::set<ContactKey> keys;
  for (const auto& kv : contacts) keys.insert(kv.first);
  return keys;
}

/// fcl_rs::collide on the RS mesh and fcl::collide on the OBBRSS mesh, octree first or second.
template <typename S>
void collideBoth(const Scene<S>& scene, const fcl::Transform3<S>& tf, bool octree_first,
                 const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& rs, fcl::CollisionResult<S>& fcl)
{
  const fcl::Transform3<S>& to = scene.tf_octree;
  if (octree_first)
  {
    fcl_rs::collide<S>(scene.octree.get(), to, scene.rs.get(), tf, request, rs);
    fcl::collide<S>(scene.octree.get(), to, scene.obbrss.get(), tf, request, fcl);
  }
  else
  {
    fcl_rs::collide<S>(scene.rs.get(), tf, scene.octree.get(), to, request, rs);
    fcl::collide<S>(scene.obbrss.get(), tf, scene.octree.get(), to, request, fcl);
  }
}

/// A pair one leaf test reports and the other does not must graze: its leaf distance is within GJK's tolerance.
template <typename S>
void expectGrazing(const Scene<S>& scene, const std::vector<LeafCell<S>>& leaves, const fcl::Transform3<S>& tf,
                   const ContactKey& key)
{
  for (const LeafCell<S>& cell : leaves)
    if (cell.node && int(cell.node - scene.octree->getRoot()) == key.first)
    {
      fcl::Box<S> box;
      fcl::Transform3<S> box_tf;
      const auto leaf = cellLeaf(cell, scene.tf_octree, tf, box, box_tf);
      const auto& tri = scene.body.triangles[std::size_t(key.second)];
      const fcl::Vector3<S> p[3] = {scene.body.vertices[tri[0]], scene.body.vertices[tri[1]],
                                    scene.body.vertices[tri[2]]};
      triangle_shape::Vec t[3];
      const double d = leaf.geometry().closest(leaf.moved(p, t)).distance;
      EXPECT_LT(std::abs(d), 1e-4) << "cell " << key.first << " triangle " << key.second;
      return;
    }
  ADD_FAILURE() << "no cell " << key.first;
}

TYPED_TEST(OcTreeTraversalTest, ContactsAreBruteForceAndFCLsInBothOrders)
{
  using S = TypeParam;
  const Scene<S> scene("OcTreeContacts", 10);
  const auto leaves = scene.leaves();
  int colliding = 0;
  for (std::size_t i = 0; i < scene.poses.size(); ++i)
  {
    const fcl::Transform3<S>& tf = scene.poses[i];
    const std::set<ContactKey> expected = bruteForceContacts(scene, leaves, tf);
    colliding += !expected.empty();
    for (bool octree_first : {true, false})
    {
      for (bool geometry : {false, true})
      {
        fcl::CollisionRequest<S> all(std::numeric_limits<std::size_t>::max(), geometry);
        fcl::CollisionResult<S> rs, fcl;
        collideBoth(scene, tf, octree_first, all, rs, fcl);
        const auto rs_contacts = contactsByKey(rs, scene.octree.get());
        const auto fcl_contacts = contactsByKey(fcl, scene.octree.get());
        ASSERT_EQ(keysOf(rs_contacts), expected) << "pose " << i << " octree first " << octree_first;
        for (const auto& [key, contact] : fcl_contacts)
        {
          const auto found = rs_contacts.find(key);
          if (found == rs_contacts.end())
          {
            expectGrazing(scene, leaves, tf, key);
            continue;
          }
          if (!geometry) continue;
          // The same solver call of the same box and triangle: FCL's contact to the bit.
          EXPECT_EQ(found->second.penetration_depth, contact.penetration_depth) << "pose " << i;
          EXPECT_EQ(found->second.normal, contact.normal) << "pose " << i;
          EXPECT_EQ(found->second.pos, contact.pos) << "pose " << i;
        }
        for (const auto& kv : rs_contacts)
          if (!fcl_contacts.count(kv.first)) expectGrazing(scene, leaves, tf, kv.first);
      }
      // num_max_contacts: the first contact, and at most three, each one the brute force's.
      for (std::size_t most : {std::size_t(1), std::size_t(3)})
      {
        fcl::CollisionRequest<S> request(most, false);
        fcl::CollisionResult<S> rs, fcl;
        collideBoth(scene, tf, octree_first, request, rs, fcl);
        EXPECT_EQ(rs.numContacts(), std::min(most, expected.size())) << "pose " << i;
        for (const ContactKey& key : keysOf(contactsByKey(rs, scene.octree.get())))
          EXPECT_TRUE(expected.count(key)) << "pose " << i;
      }
    }
  }
  EXPECT_GT(colliding, 2);
  EXPECT_LT(colliding, int(scene.poses.size()) - 2);
}

using CostKey = std::vector<double>;  // the overlap box's corners and the cost density

template <typename S>
CostKey costKey(const fcl::CostSource<S>& c)
{
  return {c.aabb_min[0], c.aabb_min[1], c.aabb_min[2], c.aabb_max[0], c.aabb_max[1], c.aabb_max[2], c.cost_density};
}

template <typename S>
std::set<CostKey> costKeys(fcl::CollisionResult<S>& result)
{
  std::vector<fcl::CostSource<S>> sources;
  result.getCostSources(sources);
  std::set<CostKey> keys;
  for (const auto& c : sources) keys.insert(costKey(c));
  return keys;
}

/// Brute-force cost sources, and the leaf distance of the cell and triangle of each (and of each grazing pair).
struct BruteForceCost
{
  std::set<CostKey> keys;  // a set, as CollisionResult's: equal sources count once
  std::map<CostKey, double> distance;
};

/// Brute force of FCL's exact cost (an occupied mesh, cost requested): every cell FCL's traversal can reach that
/// is not free (a leaf node that is not free, or an unknown child of a parent that is not free) against every
/// triangle the leaf test meets, FCL's cost source each: the overlap of the cell's and the triangle's world boxes,
/// the cell's occupancy (the occupancy threshold for unknown space) times the mesh's cost density.
template <typename S>
BruteForceCost bruteForceCost(const Scene<S>& scene, const std::vector<LeafCell<S>>& leaves,
                              const fcl::Transform3<S>& tf)
{
  const std::vector<Ball> balls = triangleBalls(scene.body, tf);
  BruteForceCost out;
  const fcl::OcTree<S>& octree = *scene.octree;
  for (const LeafCell<S>& cell : leaves)
  {
    if (cell.node ? octree.isNodeFree(cell.node) : octree.isNodeFree(cell.parent)) continue;
    const S occupancy = cell.node ? S(cell.node->getOccupancy()) : octree.getOccupancyThres();
    fcl::Box<S> box;
    fcl::Transform3<S> box_tf;
    const auto leaf = cellLeaf(cell, scene.tf_octree, tf, box, box_tf);
    fcl::AABB<S> cell_box;
    fcl::computeBV(box, box_tf, cell_box);
    for (std::size_t i = 0; i < balls.size(); ++i)
    {
      const auto p = trianglePoints(scene.body, i);
      if (spheresApart(box, box_tf, balls[i], 1e-3 + 2 * double(leaf.tolerance(p.data())))) continue;
      triangle_shape::Vec t[3];
      const double d = leaf.geometry().closest(leaf.moved(p.data(), t)).distance;
      const bool meets = leaf.meets(p.data());
      if (!meets && !(d < 1e-4)) continue;
      fcl::AABB<S> overlap;
      cell_box.overlap(fcl::AABB<S>(tf * p[0], tf * p[1], tf * p[2]), overlap);
      const CostKey key = costKey(fcl::CostSource<S>(overlap, occupancy * scene.rs->cost_density));
      if (meets) out.keys.insert(key);
      const auto at = out.distance.emplace(key, d).first;
      at->second = std::min(at->second, d);
    }
  }
  return out;
}

/// Whether two cost sources are the same to a few ulps of S (the brute force computes the same world boxes as
/// the traversal, but float results of Eigen's transforms may differ in the last bit between translation units).
template <typename S>
bool sameCost(const CostKey& a, const CostKey& b)
{
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i] - b[i]) > 4 * std::numeric_limits<S>::epsilon() * (1 + std::abs(a[i]))) return false;
  return true;
}

/// The sources of `a` that `b` does not hold (sameCost).
template <typename S>
std::vector<CostKey> costsMissing(const std::set<CostKey>& a, const std::set<CostKey>& b)
{
  std::vector<CostKey> missing;
  for (const CostKey& x : a)
    if (std::none_of(b.begin(), b.end(), [&](const CostKey& y) { return sameCost<S>(x, y); })) missing.push_back(x);
  return missing;
}

/// RS's cost sources are the brute force's; FCL's differ from them only by pairs that graze (leaf distance within
/// GJK's tolerance either way).
template <typename S>
void expectCosts(const std::set<CostKey>& rs, const std::set<CostKey>& fcl, const BruteForceCost& brute)
{
  EXPECT_TRUE(costsMissing<S>(rs, brute.keys).empty() && costsMissing<S>(brute.keys, rs).empty())
      << ::testing::PrintToString(costsMissing<S>(rs, brute.keys)) << " "
      << ::testing::PrintToString(costsMissing<S>(brute.keys, rs));
  for (const auto& differences : {costsMissing<S>(fcl, brute.keys), costsMissing<S>(brute.keys, fcl)})
    for (const CostKey& key : differences)
    {
      const auto found = std::find_if(brute.distance.begin(), brute.distance.end(),
                                      [&](const auto& kv) { return sameCost<S>(kv.first, key); });
      ASSERT_NE(found, brute.distance.end()) << "a cost source of no grazing pair: " << ::testing::PrintToString(key);
      EXPECT_LT(found->second, 1e-4);
    }
}

// Occupancy thresholds and cost as FCL defines them: some cells made uncertain (between the free and the
// occupied threshold) and some free, the octree's thresholds moved; contacts and exact cost sources (unknown
// space included) are FCL's; the approximate cost is FCL's octree against the box of the RS tree's root.
TYPED_TEST(OcTreeTraversalTest, ThresholdsAndCostSourcesAreFCLs)
{
  using S = TypeParam;
  Scene<S> scene("OcTreeThresholdsAndCost", 5);
  // Every third leaf uncertain (probability 0.6), every seventh free (0.3).
  int k = 0;
  for (auto it = scene.map->begin_leafs(); it != scene.map->end_leafs(); ++it, ++k)
  {
    if (k % 3 == 0) scene.map->setNodeValue(it.getKey(), octomap::logodds(0.6f));
    if (k % 7 == 0) scene.map->setNodeValue(it.getKey(), octomap::logodds(0.3f));
  }
  scene.map->updateInnerOccupancy();
  int with_cost = 0;
  for (double occupied : {0.7, 0.55})
  {
    scene.octree->setOccupancyThres(S(occupied));
    scene.octree->setFreeThres(S(0.35));
    const auto leaves = scene.leaves();
    for (std::size_t i = 0; i < scene.poses.size(); ++i)
    {
      const std::set<ContactKey> expected = bruteForceContacts(scene, leaves, scene.poses[i]);
      const BruteForceCost expected_cost = bruteForceCost(scene, leaves, scene.poses[i]);
      for (bool octree_first : {true, false})
      {
        fcl::CollisionRequest<S> request(std::numeric_limits<std::size_t>::max(), false,
                                         std::numeric_limits<std::size_t>::max(), true, false);
        fcl::CollisionResult<S> rs, fcl;
        collideBoth(scene, scene.poses[i], octree_first, request, rs, fcl);
        EXPECT_EQ(keysOf(contactsByKey(rs, scene.octree.get())), expected)
            << "pose " << i << " threshold " << occupied;
        expectCosts<S>(costKeys(rs), costKeys(fcl), expected_cost);
        with_cost += rs.numCostSources() > 0;

        fcl::CollisionRequest<S> approximate(request);
        approximate.use_approximate_cost = true;
        fcl::CollisionResult<S> rs_approximate;
        if (octree_first)
          fcl_rs::collide<S>(scene.octree.get(), scene.tf_octree, scene.rs.get(), scene.poses[i], approximate,
                             rs_approximate);
        else
          fcl_rs::collide<S>(scene.rs.get(), scene.poses[i], scene.octree.get(), scene.tf_octree, approximate,
                             rs_approximate);
        EXPECT_EQ(keysOf(contactsByKey(rs_approximate, scene.octree.get())), expected) << "pose " << i;
        // FCL's approximate cost: the octree against the box of the mesh's root (here the RS root's box).
        fcl::Box<S> box;
        fcl::Transform3<S> box_tf;
        constructBox(scene.rs->getBV(0).bv, scene.poses[i], box, box_tf);
        box.cost_density = scene.rs->cost_density;
        // (fcl::collide refuses a request for no contacts; FCL's driver calls the octree-box test directly. With
        // cost requested, the number of contacts asked for does not change the cost sources.)
        const fcl::CollisionRequest<S> only_cost(std::max<std::size_t>(1, rs_approximate.numContacts()), false,
                                                 std::numeric_limits<std::size_t>::max(), true, false);
        fcl::CollisionResult<S> box_cost;
        fcl::collide<S>(&box, box_tf, scene.octree.get(), scene.tf_octree, only_cost, box_cost);
        EXPECT_TRUE(costsMissing<S>(costKeys(rs_approximate), costKeys(box_cost)).empty() &&
                    costsMissing<S>(costKeys(box_cost), costKeys(rs_approximate)).empty())
            << "pose " << i;
      }
    }
  }
  EXPECT_GT(with_cost, 2);
}

TYPED_TEST(OcTreeTraversalTest, DistanceIsBruteForceAndFCLsAndSignedDistanceTheDeepestContact)
{
  using S = TypeParam;
  const Scene<S> scene("OcTreeDistance", 10);
  const auto leaves = scene.leaves();
  const fcl::Transform3<S>& to = scene.tf_octree;
  int apart = 0, signed_checked = 0;
  for (std::size_t i = 0; i < scene.poses.size(); ++i)
  {
    const fcl::Transform3<S>& tf = scene.poses[i];
    const S expected = bruteForceDistance(scene, leaves, tf);
    for (bool octree_first : {true, false})
    {
      fcl::DistanceRequest<S> request(true);
      fcl::DistanceResult<S> rs, fcl;
      const S d_rs = octree_first ? fcl_rs::distance<S>(scene.octree.get(), to, scene.rs.get(), tf, request, rs)
                                  : fcl_rs::distance<S>(scene.rs.get(), tf, scene.octree.get(), to, request, rs);
      const S d_fcl = octree_first ? fcl::distance<S>(scene.octree.get(), to, scene.obbrss.get(), tf, request, fcl)
                                   : fcl::distance<S>(scene.obbrss.get(), tf, scene.octree.get(), to, request, fcl);
      EXPECT_EQ(d_rs, expected) << "pose " << i;
      EXPECT_EQ(rs.min_distance, d_rs);
      EXPECT_EQ(rs.o1, scene.octree.get());  // the octree first in either order, as FCL's
      EXPECT_EQ(rs.o2, scene.rs.get());
      if (expected > 0)
      {
        ++apart;
        // FCL's leaf is GJK on the same box and triangle, to its tolerance.
        EXPECT_NEAR(d_rs, d_fcl, S(1e-4)) << "pose " << i;
        EXPECT_NEAR((rs.nearest_points[0] - rs.nearest_points[1]).norm(), d_rs, S(1e-5)) << "pose " << i;
        EXPECT_NEAR((rs.nearest_points[0] - fcl.nearest_points[0]).norm(), 0, S(2e-2)) << "pose " << i;
        // With a relative error (as the environment's motion checks ask, 0.25): never below the distance, and
        // divided by 1 + rel_err never above it, so that the quotient is a lower bound.
        fcl::DistanceRequest<S> approximate;
        approximate.rel_err = S(0.25);
        fcl::DistanceResult<S> rough;
        const S d_rough = fcl_rs::distance<S>(scene.rs.get(), tf, scene.octree.get(), to, approximate, rough);
        EXPECT_GE(d_rough, expected) << "pose " << i;
        EXPECT_LE(d_rough / S(1.25), expected) << "pose " << i;
      }
      else
        EXPECT_LE(d_fcl, S(1e-4)) << "pose " << i;

      // Signed: minus the deepest penetration of all of fcl_rs::collide's contacts (docs/distance.md).
      fcl::DistanceRequest<S> signed_request(false);
      signed_request.enable_signed_distance = true;
      fcl::DistanceResult<S> signed_rs;
      if (octree_first)
        fcl_rs::distance<S>(scene.octree.get(), to, scene.rs.get(), tf, signed_request, signed_rs);
      else
        fcl_rs::distance<S>(scene.rs.get(), tf, scene.octree.get(), to, signed_request, signed_rs);
      if (expected > 0)
      {
        EXPECT_EQ(signed_rs.min_distance, expected) << "pose " << i;
        continue;
      }
      fcl::CollisionRequest<S> contacts(std::numeric_limits<std::size_t>::max(), true);
      fcl::CollisionResult<S> all;
      fcl_rs::collide<S>(scene.octree.get(), to, scene.rs.get(), tf, contacts, all);
      ASSERT_TRUE(all.isCollision()) << "pose " << i;
      S deepest = 0;
      for (std::size_t c = 0; c < all.numContacts(); ++c)
        deepest = std::max(deepest, std::abs(all.getContact(c).penetration_depth));
      EXPECT_EQ(signed_rs.min_distance, -deepest) << "pose " << i;
      EXPECT_LT(signed_rs.min_distance, 0) << "pose " << i;
      ++signed_checked;
    }
  }
  EXPECT_GT(apart, 2);
  EXPECT_GT(signed_checked, 2);
}

// The traversal's inline occupancy tests against FCL's at every float next to each threshold, on thresholds a
// user may set (including 0 and 1, whose log-odds are infinite, and NaN, which no node meets), and on seeded values.
TYPED_TEST(OcTreeTraversalTest, OccupancyTestsAreFCLsAtAndAroundEveryThreshold)
{
  using S = TypeParam;
  fcl::OcTree<S> octree(std::make_shared<octomap::OcTree>(0.1));
  const float inf = std::numeric_limits<float>::infinity();
  auto rng = seededRng("OccupancyTests");
  std::uniform_real_distribution<float> log_odds(-8, 8);
  const double thresholds[] = {0.5, 0.7, 0.3, 0.97, 0.12, 1e-6, 0.0, 1.0, 1 - 1e-9, 0.5000001,
                               std::numeric_limits<double>::quiet_NaN()};
  int checked = 0;
  for (double occupied : thresholds)
    for (double free : thresholds)
    {
      octree.setOccupancyThres(S(occupied));
      octree.setFreeThres(S(free));
      const detail::OcTreeOccupancy<S> occupancy(octree);
      std::vector<float> values = {0.0f, -0.0f, inf, -inf, std::numeric_limits<float>::quiet_NaN(),
                                   std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
      for (double p : {occupied, free})
      {
        float l = float(octomap::logodds(p));
        for (int step = 0; step < 6; ++step) l = std::nextafter(l, -inf);
        for (int step = 0; step < 12; ++step, l = std::nextafter(l, inf)) values.push_back(l);
      }
      for (int i = 0; i < 50; ++i) values.push_back(log_odds(rng));
      octomap::OcTreeNode node;
      for (float l : values)
      {
        node.setLogOdds(l);
        ASSERT_EQ(occupancy.occupied(&node), octree.isNodeOccupied(&node)) << occupied << " " << free << " " << l;
        ASSERT_EQ(occupancy.free(&node), octree.isNodeFree(&node)) << occupied << " " << free << " " << l;
        ASSERT_EQ(occupancy.uncertain(&node), octree.isNodeUncertain(&node)) << occupied << " " << free << " " << l;
        ++checked;
      }
    }
  EXPECT_EQ(checked, 11 * 11 * (7 + 2 * 12 + 50));
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
  EXPECT_EQ(fcl_rs::collide<S>(mesh.get(), id, &empty, id, request, result), 0u);
  fcl::DistanceResult<S> distance;
  fcl_rs::distance<S>(mesh.get(), id, &empty, id, fcl::DistanceRequest<S>(), distance);
  EXPECT_EQ(distance.min_distance, std::numeric_limits<S>::max());
}

}  // namespace
}  // namespace fcl_rs
