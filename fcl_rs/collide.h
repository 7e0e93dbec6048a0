// Drop-in fcl_rs::collide: RS mesh pairs take the local-frame RS path, every other pair goes to fcl::collide.
#ifndef FCL_RS_COLLIDE_H
#define FCL_RS_COLLIDE_H

#include <cstddef>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>

#include "fcl_rs/rs.h"

namespace fcl_rs {

/// Same overloads and meaning as fcl::collide. Pairs with a BVHModel<RS<S>> (mesh-mesh, and mesh
/// against Box, Sphere, Ellipsoid, Capsule, Cone, Cylinder, Convex, Plane or Halfspace in either
/// order) are handled here; every other pair is passed to fcl::collide unchanged.
/// FCL's dispatch table cannot reach RS (it is hidden inside libfcl.so), so calling fcl::collide
/// on an RS model would silently report "no collision"; this function never does. An RS mesh
/// against anything it cannot handle (another BV type's mesh, an octree, a TriangleP, a point
/// cloud) throws std::invalid_argument naming the pair.
template <typename S>
std::size_t collide(const fcl::CollisionObject<S>* o1, const fcl::CollisionObject<S>* o2,
                    const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result);

template <typename S>
std::size_t collide(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                    const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result);

/// Work done by one mesh-mesh query.
struct QueryStats
{
  int num_bv_tests = 0;    ///< bounding-volume overlap tests
  int num_leaf_tests = 0;  ///< triangle-triangle tests
};

/// Mesh-mesh collision for any BV type with statistics. RS, OBB, RSS, OBBRSS and kIOS run in the
/// meshes' local frames (relative transform, no copy); AABB and KDOP16/18/24 cannot, so both models
/// are copied, moved to the world frame and rebuilt, exactly as fcl::collide does for them (pass
/// identity transforms and pre-transformed models to count a world-frame tree's tests alone).
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

#define FCL_RS_DECLARE_COLLIDE(S)                                                                            \
  extern template std::size_t collide<S>(const fcl::CollisionObject<S>*, const fcl::CollisionObject<S>*,     \
                                         const fcl::CollisionRequest<S>&, fcl::CollisionResult<S>&);         \
  extern template std::size_t collide<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,       \
                                         const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,       \
                                         const fcl::CollisionRequest<S>&, fcl::CollisionResult<S>&);
FCL_RS_DECLARE_COLLIDE(float)
FCL_RS_DECLARE_COLLIDE(double)
#undef FCL_RS_DECLARE_COLLIDE

}  // namespace fcl_rs

#endif
