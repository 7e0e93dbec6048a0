// What the descent policies of two RS meshes share (collision and distance): their pairs of nodes, the visit of a
// pair and the split rule's sizes.
#ifndef FCL_RS_MESH_MESH_DESCENT_H
#define FCL_RS_MESH_MESH_DESCENT_H

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/node_links.h"

namespace fcl_rs {
namespace detail {

/// The base of a mesh-mesh descent policy (descent.h): model1's node b1 against model2's node b2.
template <typename S>
class MeshMeshDescent
{
public:
  using BVNode = fcl::BVNode<RS<S>>;
  struct Pair
  {
    int b1, b2;
  };
  struct Visit
  {
    int b1, b2;
    const BVNode& n1;
    const BVNode& n2;
    bool leaf1, leaf2;
  };
  static constexpr int kMaxChildren = 2;

  MeshMeshDescent(const fcl::BVHModel<RS<S>>& model1, const fcl::BVHModel<RS<S>>& model2)
    : model1_(model1), model2_(model2)
  {
  }
  Visit visit(const Pair& p) const
  {
    const BVNode& n1 = model1_.getBV(p.b1);
    const BVNode& n2 = model2_.getBV(p.b2);
    return Visit{p.b1, p.b2, n1, n2, isLeaf(n1), isLeaf(n2)};
  }
  S size1(const Visit& v) const { return v.n1.bv.size(); }
  S size2(const Visit& v) const { return v.n2.bv.size(); }

protected:
  const fcl::BVHModel<RS<S>>& model1_;
  const fcl::BVHModel<RS<S>>& model2_;
};

}  // namespace detail
}  // namespace fcl_rs

#endif
