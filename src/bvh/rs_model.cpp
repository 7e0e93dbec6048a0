// RS trees compiled once: fcl::BVHModel<RS> (declared extern at the end of fcl_rs/bv/rs_fit.h) and building them
// (fcl_rs/bvh/build_model.h).
#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/build_model.h"

namespace fcl {

template class BVHModel<fcl_rs::RS<float>>;
template class BVHModel<fcl_rs::RS<double>>;

}  // namespace fcl

namespace fcl_rs {

#define FCL_RS_INSTANTIATE_BUILD_MODEL(S)                                                                   \
  template std::shared_ptr<fcl::detail::BVSplitterBase<RS<S>>> defaultSplitter<RS<S>>();                    \
  template std::shared_ptr<fcl::BVHModel<RS<S>>> buildModel<RS<S>>(                                         \
      const std::vector<fcl::Vector3<S>>&, const std::vector<fcl::Triangle>&,                               \
      std::shared_ptr<fcl::detail::BVSplitterBase<RS<S>>>);
FCL_RS_INSTANTIATE_BUILD_MODEL(float)
FCL_RS_INSTANTIATE_BUILD_MODEL(double)
#undef FCL_RS_INSTANTIATE_BUILD_MODEL

}  // namespace fcl_rs
