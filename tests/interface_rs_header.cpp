// rs.h alone must bring RS's FCL specialisations (rs_fit.h): a translation unit that builds a BVHModel<RS>
// without them compiles FCL's generic fit and split rules instead, silently, and breaks the ODR.
#include "fcl_rs/bv/rs.h"

#ifndef FCL_RS_RS_FIT_H
#error "fcl_rs/bv/rs.h must include fcl_rs/bv/rs_fit.h"
#endif
