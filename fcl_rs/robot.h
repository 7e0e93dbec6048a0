// Umbrella header of fcl_rs::robot: URDF robots, forward kinematics, SRDF pairs and self-collision checks.
#ifndef FCL_RS_ROBOT_H
#define FCL_RS_ROBOT_H

#include "fcl_rs/robot_model.h"
#include "fcl_rs/kinematics.h"
#include "fcl_rs/srdf.h"
#include "fcl_rs/self_collision.h"

#endif
