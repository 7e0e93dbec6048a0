// The scalar types the libraries are compiled for: double, and float unless the build leaves it out (option
// FCL_RS_FLOAT in CMakeLists.txt; the main job's build does: its benchmark needs double only, and FCL's narrow
// phase for float is a large part of the core's compile time). FCL_RS_FOR_EACH_SCALAR(M) expands M(S) once per
// type, so each file's explicit instantiations name the list once.
#ifndef FCL_RS_SRC_SCALARS_H
#define FCL_RS_SRC_SCALARS_H

#include "fcl_rs/version.h"

#if FCL_RS_FLOAT
#define FCL_RS_FOR_EACH_SCALAR(M) M(float) M(double)
#else
#define FCL_RS_FOR_EACH_SCALAR(M) M(double)
#endif

#endif
