// fcl_rs::collideWithStats: one mesh-mesh query on the fastest path FCL offers each BV type, with counts.
#include <memory>

#include <fcl/narrowphase/detail/traversal/collision_node.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>

#include "scalars.h"
#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/traversal/collision_traversal.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {
namespace {

constexpr const char* kApi = "fcl_rs::collideWithStats";

template <typename S>
void requireValidQuery(const fcl::Transform3<S>& tf1, const fcl::Transform3<S>& tf2,
                       const fcl::CollisionRequest<S>& request)
{
  requireRigidTransform(tf1, kApi, "tf1");
  requireRigidTransform(tf2, kApi, "tf2");
  requireValidRequest(request, kApi);
}

/// The local-frame traversal node of each BV type that has one.
template <typename BV>
struct LocalFrameNode { using type = void; };
template <typename S>
struct LocalFrameNode<RS<S>> { using type = MeshCollisionTraversalNodeRS<S>; };
template <typename S>
struct LocalFrameNode<fcl::OBB<S>> { using type = fcl::detail::MeshCollisionTraversalNodeOBB<S>; };
template <typename S>
struct LocalFrameNode<fcl::RSS<S>> { using type = fcl::detail::MeshCollisionTraversalNodeRSS<S>; };
template <typename S>
struct LocalFrameNode<fcl::kIOS<S>> { using type = fcl::detail::MeshCollisionTraversalNodekIOS<S>; };
template <typename S>
struct LocalFrameNode<fcl::OBBRSS<S>> { using type = fcl::detail::MeshCollisionTraversalNodeOBBRSS<S>; };

template <typename Node>
QueryStats run(Node& node)
{
  node.enable_statistics = true;
  fcl::detail::collide(&node);
  return QueryStats{node.num_bv_tests, node.num_leaf_tests, node.num_bv_tests};
}

template <typename S>
QueryStats run(MeshCollisionTraversalNodeRS<S>& node)
{
  node.enable_statistics = true;
  collideTrees(node);
  return QueryStats{node.num_bv_tests, node.num_leaf_tests, node.num_bv_tests + node.num_leaf_tests};
}

}  // namespace

template <typename BV>
QueryStats collideWithStats(const fcl::BVHModel<BV>& model1, const fcl::Transform3<typename BV::S>& tf1,
                            const fcl::BVHModel<BV>& model2, const fcl::Transform3<typename BV::S>& tf2,
                            const fcl::CollisionRequest<typename BV::S>& request,
                            fcl::CollisionResult<typename BV::S>& result)
{
  requireValidQuery(tf1, tf2, request);
  using Node = typename LocalFrameNode<BV>::type;
  if constexpr (!std::is_void<Node>::value)
  {
    Node node;
    if (!initialize(node, model1, tf1, model2, tf2, request, result))
      throw std::invalid_argument("fcl_rs::collideWithStats: both models must be triangle meshes");
    return run(node);
  }
  else
  {
    // Fixed-axis volumes: FCL's generic path moves copies of both meshes to the world frame and rebuilds.
    // BVHModel's copy constructor shares the original's splitter and fitter, which keep per-build state, so
    // concurrent queries on one model would race; each copy gets its own (FCL's default mean split).
    fcl::BVHModel<BV> copy1(model1), copy2(model2);
    for (fcl::BVHModel<BV>* copy : {&copy1, &copy2})
    {
      copy->bv_splitter = std::make_shared<fcl::detail::BVSplitter<BV>>(fcl::detail::SPLIT_METHOD_MEAN);
      copy->bv_fitter = std::make_shared<fcl::detail::BVFitter<BV>>();
    }
    fcl::Transform3<typename BV::S> t1 = tf1, t2 = tf2;
    fcl::detail::MeshCollisionTraversalNode<BV> node;
    if (!fcl::detail::initialize(node, copy1, t1, copy2, t2, request, result))
      throw std::invalid_argument("fcl_rs::collideWithStats: both models must be triangle meshes");
    return run(node);
  }
}

template <typename S>
QueryStats collideWithStats(const fcl::BVHModel<RS<S>>& model1, const fcl::Transform3<S>& tf1,
                            const fcl::BVHModel<RS<S>>& model2, const fcl::Transform3<S>& tf2,
                            const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result,
                            OverlapTest test)
{
  requireValidQuery(tf1, tf2, request);
  MeshCollisionTraversalNodeRS<S> node;
  if (!initialize(node, model1, tf1, model2, tf2, request, result))
    throw std::invalid_argument("fcl_rs::collideWithStats: both models must be triangle meshes");
  node.test = test;
  return run(node);
}

#define FCL_RS_INSTANTIATE_STATS(BV)                                                                          \
  template QueryStats collideWithStats<BV>(const fcl::BVHModel<BV>&, const fcl::Transform3<BV::S>&,           \
                                           const fcl::BVHModel<BV>&, const fcl::Transform3<BV::S>&,           \
                                           const fcl::CollisionRequest<BV::S>&, fcl::CollisionResult<BV::S>&);
#define FCL_RS_INSTANTIATE_STATS_ALL(S)             \
  FCL_RS_INSTANTIATE_STATS(RS<S>)                   \
  FCL_RS_INSTANTIATE_STATS(fcl::AABB<S>)            \
  FCL_RS_INSTANTIATE_STATS(fcl::OBB<S>)             \
  FCL_RS_INSTANTIATE_STATS(fcl::RSS<S>)             \
  FCL_RS_INSTANTIATE_STATS(fcl::OBBRSS<S>)          \
  FCL_RS_INSTANTIATE_STATS(fcl::kIOS<S>)            \
  FCL_RS_INSTANTIATE_STATS(KDOP16<S>)               \
  FCL_RS_INSTANTIATE_STATS(KDOP18<S>)               \
  FCL_RS_INSTANTIATE_STATS(KDOP24<S>)

template <typename S> using KDOP16 = fcl::KDOP<S, 16>;
template <typename S> using KDOP18 = fcl::KDOP<S, 18>;
template <typename S> using KDOP24 = fcl::KDOP<S, 24>;
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_STATS_ALL)

#define FCL_RS_INSTANTIATE_RS_STATS(S)                                                                           \
  template QueryStats collideWithStats<S>(const fcl::BVHModel<RS<S>>&, const fcl::Transform3<S>&,               \
                                          const fcl::BVHModel<RS<S>>&, const fcl::Transform3<S>&,               \
                                          const fcl::CollisionRequest<S>&, fcl::CollisionResult<S>&, OverlapTest);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_RS_STATS)

}  // namespace fcl_rs
