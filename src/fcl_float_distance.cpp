// fcl::distance<float>, declared in fcl_rs/fcl_float.h (its signed-distance fallback calls the fcl::collide<float>
// of src/fcl_float_collide.cpp).
#include "fcl_rs/fcl_float.h"

namespace fcl {

template float distance(const CollisionObject<float>* o1, const CollisionObject<float>* o2,
                        const DistanceRequest<float>& request, DistanceResult<float>& result);
template float distance(const CollisionGeometry<float>* o1, const Transform3<float>& tf1,
                        const CollisionGeometry<float>* o2, const Transform3<float>& tf2,
                        const DistanceRequest<float>& request, DistanceResult<float>& result);

}  // namespace fcl
