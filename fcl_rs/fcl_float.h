// fcl::collide, fcl::distance and fcl::continuousCollide for float, compiled once in the fcl_rs library
// (src/fcl_float_collide.cpp, src/fcl_float_distance.cpp, src/fcl_float_continuous.cpp; not in a double-only build,
// CMake option FCL_RS_FLOAT). libfcl.so ships them for
// double only; for float, every translation unit calling them (directly, through fcl_rs's fallbacks or through
// FCL's broadphase callbacks) would otherwise instantiate FCL's whole narrow phase again: every BV and shape pair
// for both GJK solvers, minutes of compile time per file under the sanitizers. continuousCollide only on motions:
// FCL 0.7's overloads on transforms cannot be instantiated for float (its motions declare integrate(double), which
// does not override MotionBase<float>::integrate(float)).
#ifndef FCL_RS_FCL_FLOAT_H
#define FCL_RS_FCL_FLOAT_H

#include <cstddef>

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/continuous_collision.h>
#include <fcl/narrowphase/distance.h>

namespace fcl {

extern template std::size_t collide(const CollisionObject<float>* o1, const CollisionObject<float>* o2,
                                    const CollisionRequest<float>& request, CollisionResult<float>& result);
extern template std::size_t collide(const CollisionGeometry<float>* o1, const Transform3<float>& tf1,
                                    const CollisionGeometry<float>* o2, const Transform3<float>& tf2,
                                    const CollisionRequest<float>& request, CollisionResult<float>& result);
extern template float distance(const CollisionObject<float>* o1, const CollisionObject<float>* o2,
                               const DistanceRequest<float>& request, DistanceResult<float>& result);
extern template float distance(const CollisionGeometry<float>* o1, const Transform3<float>& tf1,
                               const CollisionGeometry<float>* o2, const Transform3<float>& tf2,
                               const DistanceRequest<float>& request, DistanceResult<float>& result);

extern template float continuousCollide(const CollisionGeometry<float>* o1, const MotionBase<float>* motion1,
                                        const CollisionGeometry<float>* o2, const MotionBase<float>* motion2,
                                        const ContinuousCollisionRequest<float>& request,
                                        ContinuousCollisionResult<float>& result);

}  // namespace fcl

#endif
