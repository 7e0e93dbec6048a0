// FCL's own trees the tests compare RS against, built by one compiled file (tests/fcl_trees.cpp) instead of in
// every test.
#ifndef FCL_RS_TESTS_FCL_TREES_H
#define FCL_RS_TESTS_FCL_TREES_H

#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>

#include "fcl_rs/bvh/build_model.h"

namespace fcl_rs {
namespace test {

template <typename S>
using KDOP16 = fcl::KDOP<S, 16>;
template <typename S>
using KDOP18 = fcl::KDOP<S, 18>;
template <typename S>
using KDOP24 = fcl::KDOP<S, 24>;

}  // namespace test
}  // namespace fcl_rs

// KIND one of FCL's tree types: its BVHModel members and buildModel.
#define FCL_RS_TEST_FCL_TREE(KIND, BV) FCL_RS_BVH_MODEL_MEMBERS(KIND, BV) FCL_RS_BUILD_MODEL_FUNCTIONS(KIND, BV)

// KIND each of FCL's tree types for float and double.
#define FCL_RS_TEST_FCL_TREES(KIND, S)                                                                              \
  FCL_RS_TEST_FCL_TREE(KIND, fcl::AABB<S>)                                                                          \
  FCL_RS_TEST_FCL_TREE(KIND, fcl::OBB<S>)                                                                           \
  FCL_RS_TEST_FCL_TREE(KIND, fcl::RSS<S>)                                                                           \
  FCL_RS_TEST_FCL_TREE(KIND, fcl::OBBRSS<S>)                                                                        \
  FCL_RS_TEST_FCL_TREE(KIND, fcl::kIOS<S>)                                                                          \
  FCL_RS_TEST_FCL_TREE(KIND, fcl_rs::test::KDOP16<S>)                                                               \
  FCL_RS_TEST_FCL_TREE(KIND, fcl_rs::test::KDOP18<S>)                                                               \
  FCL_RS_TEST_FCL_TREE(KIND, fcl_rs::test::KDOP24<S>)

FCL_RS_TEST_FCL_TREES(extern template, float)
FCL_RS_TEST_FCL_TREES(extern template, double)

#endif
