// fcl::continuousCollide<float>, declared in fcl_rs/fcl_float.h: FCL's conservative advancement and naive sampling
// for every BV and shape pair, instantiated once here instead of in each caller of fcl_rs::continuousCollide.
#include "fcl_rs/fcl_float.h"

namespace fcl {

template float continuousCollide(const CollisionGeometry<float>* o1, const MotionBase<float>* motion1,
                                 const CollisionGeometry<float>* o2, const MotionBase<float>* motion2,
                                 const ContinuousCollisionRequest<float>& request,
                                 ContinuousCollisionResult<float>& result);

}  // namespace fcl
