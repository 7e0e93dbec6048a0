// Broadphase callbacks for RS objects: FCL's default callbacks with fcl_rs::collide / fcl_rs::distance inside.
#ifndef FCL_RS_BROADPHASE_H
#define FCL_RS_BROADPHASE_H

#include <cassert>

#include <fcl/broadphase/default_broadphase_callbacks.h>

#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/fcl_float.h"

namespace fcl_rs {

/// FCL's callback data under fcl_rs's name as well: moving a broadphase caller to RS is a change of namespace.
template <typename S>
using DefaultCollisionData = fcl::DefaultCollisionData<S>;
template <typename S>
using DefaultDistanceData = fcl::DefaultDistanceData<S>;

/// fcl::DefaultCollisionFunction with fcl_rs::collide: pass it, with a DefaultCollisionData<S>, to any FCL
/// broadphase manager. The managers themselves only use object AABBs, which RS models provide (after moving
/// a model's vertices, call its computeLocalAABB() and its objects' computeAABB(), as for any FCL mesh).
template <typename S>
bool DefaultCollisionFunction(fcl::CollisionObject<S>* o1, fcl::CollisionObject<S>* o2, void* data)
{
  assert(data != nullptr);
  auto* collision_data = static_cast<fcl::DefaultCollisionData<S>*>(data);
  const fcl::CollisionRequest<S>& request = collision_data->request;
  fcl::CollisionResult<S>& result = collision_data->result;
  if (collision_data->done) return true;
  fcl_rs::collide(o1, o2, request, result);
  if (!request.enable_cost && result.isCollision() && result.numContacts() >= request.num_max_contacts)
    collision_data->done = true;
  return collision_data->done;
}

/// fcl::DefaultDistanceFunction with fcl_rs::distance, for a DefaultDistanceData<S>.
template <typename S>
bool DefaultDistanceFunction(fcl::CollisionObject<S>* o1, fcl::CollisionObject<S>* o2, void* data, S& dist)
{
  assert(data != nullptr);
  auto* distance_data = static_cast<fcl::DefaultDistanceData<S>*>(data);
  const fcl::DistanceRequest<S>& request = distance_data->request;
  fcl::DistanceResult<S>& result = distance_data->result;
  if (distance_data->done)
  {
    dist = result.min_distance;
    return true;
  }
  fcl_rs::distance(o1, o2, request, result);
  dist = result.min_distance;
  if (dist <= 0) return true;  // in collision or in touch: nothing can be closer
  return distance_data->done;
}

}  // namespace fcl_rs

#endif
