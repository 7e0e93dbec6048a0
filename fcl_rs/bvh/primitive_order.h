// Which triangles each node of a built tree holds (FCL keeps the permutation private).
#ifndef FCL_RS_BVH_PRIMITIVE_ORDER_H
#define FCL_RS_BVH_PRIMITIVE_ORDER_H

#include <stdexcept>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bvh/node_links.h"

namespace fcl_rs {

/// The triangles of a built tree in the tree's primitive order: node k's triangles are
/// order[first_primitive .. first_primitive + num_primitives) of node k. (FCL keeps this permutation
/// private; each leaf gives back its entry.) Throws std::invalid_argument unless model is a built
/// triangle mesh.
namespace detail {

template <typename BV>
void requireBuiltTriangleTree(const fcl::BVHModel<BV>& model)
{
  if (model.getModelType() != fcl::BVH_MODEL_TRIANGLES || model.getNumBVs() == 0 ||
      (model.build_state != fcl::BVH_BUILD_STATE_PROCESSED && model.build_state != fcl::BVH_BUILD_STATE_UPDATED))
    throw std::invalid_argument("fcl_rs: the model is not a built triangle-mesh tree");
}

}  // namespace detail

template <typename BV>
std::vector<int> primitiveOrder(const fcl::BVHModel<BV>& model)
{
  detail::requireBuiltTriangleTree(model);
  std::vector<int> order(std::size_t(model.num_tris), -1);
  for (int k = 0; k < model.getNumBVs(); ++k)
  {
    const auto& node = model.getBV(k);
    if (isLeaf(node)) order.at(std::size_t(node.first_primitive)) = primitiveId(node);
  }
  return order;
}

}  // namespace fcl_rs

#endif
