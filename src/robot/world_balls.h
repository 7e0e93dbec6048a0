// Balls placed in the robot's root frame: the culling volumes of the self-collision checker's links and of the
// environment's links and obstacles, with one rounding pad.
#ifndef FCL_RS_SRC_ROBOT_WORLD_BALLS_H
#define FCL_RS_SRC_ROBOT_WORLD_BALLS_H

#include <fcl/common/types.h>

namespace fcl_rs {
namespace detail {

/// A ball in the root frame whose radius (reach) is grown by placeBall's rounding pad.
template <typename S>
struct WorldSphere
{
  fcl::Vector3<S> centre = fcl::Vector3<S>::Zero();
  S reach = 0;
};

/// The ball of `center` and `radius` in a body's frame, placed at the body's pose. The pad, 1e-5 of the radius and
/// of the centre's 1-norm (at least its distance from the root; no square root), covers the rounding of moving the
/// centres and of comparing their distance, so the gap between two placed balls never exceeds the gap between the
/// geometries they hold.
template <typename S>
WorldSphere<S> placeBall(const fcl::Transform3<S>& pose, const fcl::Vector3<S>& center, S radius)
{
  const fcl::Vector3<S> centre = pose * center;
  return {centre, radius + S(1e-5) * (radius + centre.template lpNorm<1>())};
}

/// The distance between two placed balls: never more than the geometries'.
template <typename S>
S sphereGap(const WorldSphere<S>& a, const WorldSphere<S>& b)
{
  return (a.centre - b.centre).norm() - a.reach - b.reach;
}

/// sphereGap(a, b) > 0, without the square root.
template <typename S>
bool spheresApart(const WorldSphere<S>& a, const WorldSphere<S>& b)
{
  const S reach = a.reach + b.reach;
  return (a.centre - b.centre).squaredNorm() > reach * reach;
}

}  // namespace detail
}  // namespace fcl_rs

#endif
