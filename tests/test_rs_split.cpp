// SurfaceAreaSplitter: trees built with it contain their triangles, answer queries exactly like the
// brute-force oracle and FCL's mean split, need fewer BV tests, and survive degenerate meshes.
#include <array>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace {

using fcl_rs::RS;
using fcl_rs::TriangleMesh;

/// buildModel's RS tree, which must be split by surface area.
template <typename S>
std::shared_ptr<fcl::BVHModel<RS<S>>> buildSurfaceArea(const TriangleMesh<S>& mesh)
{
  auto model = fcl_rs::buildModel<RS<S>>(mesh);
  EXPECT_NE(dynamic_cast<const fcl_rs::SurfaceAreaSplitter<S>*>(model->bv_splitter.get()), nullptr)
      << "buildModel's RS trees are split by surface area";
  return model;
}

/// Every node contains every vertex of its triangles; leaves hold one triangle each.
template <typename S>
void expectNodesContainTheirTriangles(const fcl::BVHModel<RS<S>>& model, const std::string& what)
{
  const std::vector<int> order = fcl_rs::primitiveOrder(model);
  int missing = 0;
  for (int k = 0; k < model.getNumBVs(); ++k)
  {
    const auto& node = model.getBV(k);
    if (node.isLeaf()) {
      EXPECT_EQ(node.num_primitives, 1) << what << " leaf " << k;
    }
    for (int i = node.first_primitive; i < node.first_primitive + node.num_primitives; ++i)
      for (int c = 0; c < 3; ++c)
        missing += !node.bv.contain(model.vertices[model.tri_indices[order[std::size_t(i)]][c]]);
  }
  EXPECT_EQ(missing, 0) << what << ": vertices outside their nodes";
}

template <typename S>
class SurfaceAreaSplits : public ::testing::Test
{
};
TYPED_TEST_SUITE(SurfaceAreaSplits, fcl_rs::test::Scalars);

TYPED_TEST(SurfaceAreaSplits, QueriesMatchBruteForceWithFewerBVTests)
{
  using S = TypeParam;
  const auto sphere = fcl_rs::makeSphere<S>(1, 16, 32);
  const auto torus = fcl_rs::makeTorus<S>(1, S(0.3), 32, 16);
  const auto sphere_sah = buildSurfaceArea(sphere), torus_sah = buildSurfaceArea(torus);
  const auto sphere_mean = fcl_rs::buildModel<RS<S>>(sphere, fcl::detail::SPLIT_METHOD_MEAN),
             torus_mean = fcl_rs::buildModel<RS<S>>(torus, fcl::detail::SPLIT_METHOD_MEAN);
  expectNodesContainTheirTriangles(*sphere_sah, "sphere");
  expectNodesContainTheirTriangles(*torus_sah, "torus");

  auto rng = fcl_rs::test::seededRng("surface area splits");
  fcl::CollisionRequest<S> request(1000000, false);
  request.enable_cost = false;
  long tests_sah = 0, tests_mean = 0;
  int colliding = 0;
  for (int pose = 0; pose < 40; ++pose)
  {
    const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
    const fcl::Transform3<S> tf2 = tf1 * fcl_rs::test::randomPose<S>(rng, S(2));
    const auto truth = fcl_rs::test::bruteForcePairs(sphere, tf1, torus, tf2);
    colliding += !truth.empty();
    fcl::CollisionResult<S> sah, mean;
    const fcl_rs::QueryStats stats_sah = fcl_rs::collideWithStats(*sphere_sah, tf1, *torus_sah, tf2, request, sah);
    const fcl_rs::QueryStats stats_mean = fcl_rs::collideWithStats(*sphere_mean, tf1, *torus_mean, tf2, request, mean);
    EXPECT_EQ(fcl_rs::test::contactPairs(sah), truth) << "pose #" << pose;
    EXPECT_EQ(fcl_rs::test::contactPairs(mean), truth) << "pose #" << pose;
    tests_sah += stats_sah.num_bv_tests;
    tests_mean += stats_mean.num_bv_tests;
  }
  EXPECT_GE(colliding, 10);
  EXPECT_LE(colliding, 35);
  std::cout << "[split] BV tests, surface area / mean split: " << tests_sah << " / " << tests_mean << "\n";
  EXPECT_LT(tests_sah, tests_mean);
}

TYPED_TEST(SurfaceAreaSplits, DegenerateMeshesBuildAndContainTheirTriangles)
{
  using S = TypeParam;
  std::vector<std::pair<std::string, TriangleMesh<S>>> meshes;
  {
    TriangleMesh<S> point;  // every triangle on one point
    point.vertices.assign(3, fcl::Vector3<S>(S(1e6), S(-2), S(3)));
    for (int i = 0; i < 20; ++i) point.triangles.emplace_back(0, 1, 2);
    meshes.emplace_back("one point", point);
  }
  {
    TriangleMesh<S> needle;  // collinear points
    for (int i = 0; i < 40; ++i) needle.vertices.emplace_back(S(i) / 7, S(2) * S(i) / 7, S(-1) * S(i) / 7);
    for (int i = 0; i + 2 < 40; ++i) needle.triangles.emplace_back(i, i + 1, i + 2);
    meshes.emplace_back("needle", needle);
  }
  {
    TriangleMesh<S> plate;  // coplanar, far from the origin, tiny
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) plate.vertices.emplace_back(S(1e3) + S(x) * S(1e-4), S(y) * S(1e-4), S(1e3));
    for (int y = 0; y + 1 < 8; ++y)
      for (int x = 0; x + 1 < 8; ++x)
      {
        plate.triangles.emplace_back(y * 8 + x, y * 8 + x + 1, (y + 1) * 8 + x);
        plate.triangles.emplace_back(y * 8 + x + 1, (y + 1) * 8 + x + 1, (y + 1) * 8 + x);
      }
    meshes.emplace_back("plate", plate);
  }
  meshes.emplace_back("cube", fcl_rs::makeBox<S>(1, 1, 1));
  for (const auto& [name, mesh] : meshes)
  {
    const auto model = buildSurfaceArea(mesh);
    EXPECT_EQ(model->num_tris, int(mesh.triangles.size())) << name;
    expectNodesContainTheirTriangles(*model, name);
    // The mesh against itself at the same pose: every triangle touches itself.
    fcl::CollisionRequest<S> request(1000000, false);
    fcl::CollisionResult<S> result;
    fcl_rs::collide(model.get(), fcl::Transform3<S>::Identity(), model.get(), fcl::Transform3<S>::Identity(), request,
                    result);
    const auto truth = fcl_rs::test::bruteForcePairs(mesh, fcl::Transform3<S>::Identity(), mesh,
                                                      fcl::Transform3<S>::Identity());
    EXPECT_FALSE(truth.empty()) << name;
    EXPECT_EQ(fcl_rs::test::contactPairs(result), truth) << name;
  }
}

/// fcl_rs's inline node links and triangle reads give what FCL's out-of-line accessors give, on FCL's own OBB
/// trees too.
template <typename BV>
void expectNodeLinksMatchFcl(const fcl::BVHModel<BV>& model, const std::string& what)
{
  int leaves = 0;
  for (int k = 0; k < model.getNumBVs(); ++k)
  {
    const fcl::BVNodeBase& node = model.getBV(k);
    ASSERT_EQ(fcl_rs::isLeaf(node), node.isLeaf()) << what << " node " << k;
    if (node.isLeaf())
    {
      ++leaves;
      EXPECT_EQ(fcl_rs::primitiveId(node), node.primitiveId()) << what << " node " << k;
      continue;
    }
    EXPECT_EQ(fcl_rs::leftChild(node), node.leftChild()) << what << " node " << k;
    EXPECT_EQ(fcl_rs::rightChild(node), node.rightChild()) << what << " node " << k;
  }
  EXPECT_EQ(leaves, model.num_tris) << what;
  for (int i = 0; i < model.num_tris; ++i)
  {
    const fcl::Triangle& t = model.tri_indices[i];
    const std::array<std::size_t, 3> ids = fcl_rs::vertexIds(t);
    const auto vertices = fcl_rs::triangleVertices(model.vertices, t);
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_EQ(ids[std::size_t(c)], t[c]) << what << " triangle " << i;
      EXPECT_EQ(vertices[std::size_t(c)], model.vertices[t[c]]) << what << " triangle " << i;
    }
  }
}

TYPED_TEST(SurfaceAreaSplits, NodeLinksReadWhatFclsAccessorsReturn)
{
  using S = TypeParam;
  const TriangleMesh<S> torus = fcl_rs::makeTorus<S>(S(1), S(0.25));
  expectNodeLinksMatchFcl(*buildSurfaceArea(torus), "RS torus");
  expectNodeLinksMatchFcl(*fcl_rs::buildModel<fcl::OBB<S>>(torus), "OBB torus");
}

}  // namespace
