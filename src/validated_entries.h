// fcl_rs::collide and fcl_rs::distance without their validation, for callers whose input is validated already:
// the batches (which validate each pose array and the request once) and distance's signed-distance fallback.
#ifndef FCL_RS_SRC_VALIDATED_ENTRIES_H
#define FCL_RS_SRC_VALIDATED_ENTRIES_H

#include <cstddef>

#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

namespace fcl_rs {
namespace detail {

/// fcl_rs::collide for rigid tf1, tf2 (fcl_rs::isRigidTransform) and a valid request (requireValidRequest).
template <typename S>
std::size_t collideValidated(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                             const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                             const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result);

/// fcl_rs::distance for rigid tf1, tf2 and a valid request.
template <typename S>
S distanceValidated(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                    const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result);

}  // namespace detail
}  // namespace fcl_rs

#endif
