// What the robot layer's environment shares with the self-collision checker: the links' balls, placed once per
// configuration for both the environment's culling and the self check.
#ifndef FCL_RS_SRC_ROBOT_SELF_COLLISION_INTERNALS_H
#define FCL_RS_SRC_ROBOT_SELF_COLLISION_INTERNALS_H

#include <vector>

#include "fcl_rs/robot/self_collision.h"
#include "world_balls.h"

namespace fcl_rs {
namespace detail {

template <typename S>
struct SelfCollisionInternals
{
  /// SelfCollision::queryPoses with the links' balls already placed: spheres[i] is placeBall(poses[i], ball) of
  /// SelfCollision::linkSphere(i) for every link with geometry. Thread-safe as queryPoses.
  static SelfCheckResult<S> queryPlaced(const SelfCollision<S>& self, const std::vector<fcl::Transform3<S>>& poses,
                                        const std::vector<WorldSphere<S>>& spheres, const SelfCheckRequest& request);
};

extern template struct SelfCollisionInternals<float>;
extern template struct SelfCollisionInternals<double>;

}  // namespace detail
}  // namespace fcl_rs

#endif
