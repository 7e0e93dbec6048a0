// Umbrella header of fcl_rs::robot: URDF robots, forward kinematics, SRDF pairs, self-collision checks and
// environments (obstacles, motion checks).
#ifndef FCL_RS_ROBOT_H
#define FCL_RS_ROBOT_H

#include "fcl_rs/robot/robot_model.h"
#include "fcl_rs/robot/kinematics.h"
#include "fcl_rs/robot/srdf.h"
#include "fcl_rs/robot/self_collision.h"
#include "fcl_rs/robot/environment.h"

#endif
