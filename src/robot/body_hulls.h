// What the robot library makes body hulls (BodyHull, fcl_rs/robot/self_collision.h) of, shared by the self-collision
// checker (link elements) and the environment (obstacle shapes).
#ifndef FCL_RS_SRC_ROBOT_BODY_HULLS_H
#define FCL_RS_SRC_ROBOT_BODY_HULLS_H

#include <algorithm>
#include <vector>

#include <fcl/common/types.h>

#include "fcl_rs/robot/self_collision.h"

namespace fcl_rs {
namespace detail {

/// The eight corners of a box of half extents `half` about the origin.
inline std::vector<fcl::Vector3d> boxCorners(const fcl::Vector3d& half)
{
  std::vector<fcl::Vector3d> corners;
  for (int corner = 0; corner < 8; ++corner)
    corners.emplace_back(corner & 1 ? half[0] : -half[0], corner & 2 ? half[1] : -half[1],
                         corner & 4 ? half[2] : -half[2]);
  return corners;
}

/// The largest |point| + radius of a hull: its rounding margin's scale (BodyHull::reach).
template <typename S>
double hullReach(const BodyHull<S>& hull)
{
  double reach = 0;
  for (const fcl::Vector3d& point : hull.points.points()) reach = std::max(reach, point.norm() + hull.radius);
  return reach;
}

}  // namespace detail
}  // namespace fcl_rs

#endif
