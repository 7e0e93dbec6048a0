// Umbrella header of the core library fcl_rs::fcl_rs: the RS bounding volume, tree building, traversal and the
// drop-in API. Frame fits (fcl_rs/bvh/frame_fit.h, library fcl_rs::hull) and robots (fcl_rs/robot.h, library
// fcl_rs::robot) are optional parts with their own headers.
#ifndef FCL_RS_FCL_RS_H
#define FCL_RS_FCL_RS_H

#include "fcl_rs/bv/directions.h"
#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/bvh/primitive_order.h"
#include "fcl_rs/bvh/refit_model.h"
#include "fcl_rs/bvh/surface_area_splitter.h"
#include "fcl_rs/mesh/load_mesh.h"
#include "fcl_rs/mesh/shapes.h"
#include "fcl_rs/mesh/triangle_mesh.h"
#include "fcl_rs/traversal/collision_traversal.h"
#include "fcl_rs/traversal/distance_traversal.h"
#include "fcl_rs/validate.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/fcl_float.h"
#include "fcl_rs/broadphase.h"
#include "fcl_rs/continuous_collision.h"
#include "fcl_rs/solid.h"
#include "fcl_rs/version.h"

#endif
