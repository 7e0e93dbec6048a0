// SRDF <disable_collisions> pairs: the link pairs a self-collision check skips.
#ifndef FCL_RS_SRDF_H
#define FCL_RS_SRDF_H

#include <string>
#include <vector>

#include "fcl_rs/robot/robot_model.h"

namespace fcl_rs {

/// One <disable_collisions link1="..." link2="..." reason="..."/> element.
struct DisabledCollision
{
  std::string link1, link2;
  std::string reason;  ///< free text ("Adjacent", "Never", ...); may be empty
  std::string source;  ///< where it was read, "FILE:LINE", for error messages; may be empty
};

/// Reads every <disable_collisions> element under the SRDF's <robot> root with tinyxml2; other elements
/// (groups, states, end effectors) are ignored. Throws std::runtime_error naming the file and line when the
/// file cannot be read, is not well-formed XML, has no <robot> root, an element lacks link1 or link2, or
/// names a link the robot does not have.
std::vector<DisabledCollision> loadDisabledCollisions(const std::string& srdf_path, const RobotModel& robot);

}  // namespace fcl_rs

#endif
