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

/// fcl_rs::distance of an RS mesh and an RS mesh, box, sphere, cylinder or capsule, without a descent
/// (distanceAlong in traversal/distance_traversal.h), given `direction` (world frame, from o1 towards o2) nearly
/// normal to their gap: true when the result is what distanceValidated gives, to the bit; false, leaving a result
/// distanceValidated completes to the same answer, for other pairs, for requests with rel_err, abs_err or signed
/// distances, and when the direction leaves too many triangles to measure.
template <typename S>
bool distanceAlong(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                   const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                   const fcl::Vector3<double>& direction, const fcl::DistanceRequest<S>& request,
                   fcl::DistanceResult<S>& result);

}  // namespace detail
}  // namespace fcl_rs

#endif
