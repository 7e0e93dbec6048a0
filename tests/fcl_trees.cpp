// FCL's tree types built once for the tests (fcl_trees.h).
#include "fcl_trees.h"

FCL_RS_TEST_FCL_TREES(template, float)
FCL_RS_TEST_FCL_TREES(template, double)
