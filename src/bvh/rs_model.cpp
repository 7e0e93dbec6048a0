// RS trees compiled once: fcl::BVHModel<RS>'s heavy members and buildModel<RS> (declared extern at the ends of
// fcl_rs/bv/rs_fit.h and fcl_rs/bvh/build_model.h).
#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/build_model.h"

#include "../scalars.h"

#define FCL_RS_INSTANTIATE_RS_MODEL(S)                     \
  FCL_RS_BVH_MODEL_MEMBERS(template, fcl_rs::RS<S>)        \
  FCL_RS_BUILD_MODEL_FUNCTIONS(template, fcl_rs::RS<S>)
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_RS_MODEL)
#undef FCL_RS_INSTANTIATE_RS_MODEL
