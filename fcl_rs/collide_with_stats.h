// Mesh-mesh collision for any BV type with BV-test and triangle-test counts (benchmarks, tests, tuning).
#ifndef FCL_RS_COLLIDE_WITH_STATS_H
#define FCL_RS_COLLIDE_WITH_STATS_H

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>

#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

/// Work done by one mesh-mesh query.
struct QueryStats
{
  int num_bv_tests = 0;    ///< bounding-volume overlap tests
  int num_leaf_tests = 0;  ///< triangle-triangle tests
  /// Node pairs the traversal reached: FCL's recursion runs a BV test on each, RS trees send a pair of two
  /// leaves to the triangle test without one. The volumes' tightness compares across BV types on this count.
  int num_node_pairs = 0;
};

/// Mesh-mesh collision for any BV type with statistics. RS, OBB, RSS, OBBRSS and kIOS run in the
/// meshes' local frames (relative transform, no copy); AABB and KDOP16/18/24 cannot, so both models
/// are copied, moved to the world frame and rebuilt, exactly as fcl::collide does for them (pass
/// identity transforms and pre-transformed models to count a world-frame tree's tests alone). Poses and the
/// request are validated as fcl_rs::collide validates them.
template <typename BV>
QueryStats collideWithStats(const fcl::BVHModel<BV>& model1, const fcl::Transform3<typename BV::S>& tf1,
                            const fcl::BVHModel<BV>& model2, const fcl::Transform3<typename BV::S>& tf2,
                            const fcl::CollisionRequest<typename BV::S>& request,
                            fcl::CollisionResult<typename BV::S>& result);

/// collideWithStats for RS trees with a chosen overlap test (the other overloads use kDefaultOverlapTest).
template <typename S>
QueryStats collideWithStats(const fcl::BVHModel<RS<S>>& model1, const fcl::Transform3<S>& tf1,
                            const fcl::BVHModel<RS<S>>& model2, const fcl::Transform3<S>& tf2,
                            const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result,
                            OverlapTest test);

}  // namespace fcl_rs

#endif
