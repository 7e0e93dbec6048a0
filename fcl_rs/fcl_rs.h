// Umbrella header: the RS bounding volume, its fitting and FCL glue, traversal and drop-in API.
#ifndef FCL_RS_FCL_RS_H
#define FCL_RS_FCL_RS_H

#include "fcl_rs/directions.h"
#include "fcl_rs/rs.h"
#include "fcl_rs/rs_fit.h"
#include "fcl_rs/rs_split.h"
#include "fcl_rs/frame_fit.h"
#include "fcl_rs/traversal.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/distance_traversal.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/broadphase.h"
#include "fcl_rs/continuous_collision.h"
#include "fcl_rs/mesh_io.h"
#include "fcl_rs/shapes.h"
#include "fcl_rs/version.h"

#endif
