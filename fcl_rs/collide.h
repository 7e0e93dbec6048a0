// Drop-in fcl_rs::collide: RS mesh pairs take the local-frame RS path, every other pair goes to fcl::collide.
#ifndef FCL_RS_COLLIDE_H
#define FCL_RS_COLLIDE_H

#include <cstddef>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>

#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

/// Same overloads and meaning as fcl::collide. Pairs with a BVHModel<RS<S>> (mesh-mesh, and mesh
/// against Box, Sphere, Ellipsoid, Capsule, Cone, Cylinder, Convex, Plane, Halfspace, TriangleP or an fcl::OcTree
/// in either order) are handled here; every other pair is passed to fcl::collide unchanged.
/// FCL's dispatch table cannot reach RS (it is hidden inside libfcl.so), so calling fcl::collide
/// on an RS model would silently report "no collision"; this function never does. An RS mesh
/// against anything it cannot handle (another BV type's mesh) throws std::invalid_argument naming the pair. So does bad input, for every pair, before any test
/// (fcl_rs/validate.h): a pose that is not a rigid transform (NaN or infinite entries, a rotation that is not
/// orthonormal, a reflection), naming tf1, tf2 or o1->getTransform(), o2->getTransform(); an invalid request
/// field (num_max_contacts 0, gjk_tolerance, cached_gjk_guess), naming the field.
template <typename S>
std::size_t collide(const fcl::CollisionObject<S>* o1, const fcl::CollisionObject<S>* o2,
                    const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result);

template <typename S>
std::size_t collide(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                    const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result);

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
