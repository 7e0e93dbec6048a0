// The one switch from a geometry's node type to its primitive shape type, and what every mesh-shape traversal
// shares (collision and distance): the node's set-up and the descent's pairs.
#ifndef FCL_RS_SHAPE_SWITCH_H
#define FCL_RS_SHAPE_SWITCH_H

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/node_links.h"

namespace fcl_rs {
namespace detail {

/// f(shape) with geometry cast to its primitive shape type (fcl::Box<S>, ...), or otherwise() for any other node
/// type (meshes, octrees). Both return the same type. Every entry point that handles shapes by type goes through
/// this switch, so that a new shape type is one case here.
template <typename S, typename F, typename Otherwise>
decltype(auto) withShape(const fcl::CollisionGeometry<S>& geometry, F&& f, Otherwise&& otherwise)
{
  switch (geometry.getNodeType())
  {
    case fcl::GEOM_BOX: return f(static_cast<const fcl::Box<S>&>(geometry));
    case fcl::GEOM_SPHERE: return f(static_cast<const fcl::Sphere<S>&>(geometry));
    case fcl::GEOM_ELLIPSOID: return f(static_cast<const fcl::Ellipsoid<S>&>(geometry));
    case fcl::GEOM_CAPSULE: return f(static_cast<const fcl::Capsule<S>&>(geometry));
    case fcl::GEOM_CONE: return f(static_cast<const fcl::Cone<S>&>(geometry));
    case fcl::GEOM_CYLINDER: return f(static_cast<const fcl::Cylinder<S>&>(geometry));
    case fcl::GEOM_CONVEX: return f(static_cast<const fcl::Convex<S>&>(geometry));
    case fcl::GEOM_PLANE: return f(static_cast<const fcl::Plane<S>&>(geometry));
    case fcl::GEOM_HALFSPACE: return f(static_cast<const fcl::Halfspace<S>&>(geometry));
    default: return otherwise();
  }
}

/// The fields every mesh-shape node (FCL's BVHShape{Collision,Distance}TraversalNode and ours) takes from a query:
/// model1 the mesh at tf1, model2 the shape at tf2. False unless model1 is a triangle mesh.
template <typename Node, typename Shape, typename Solver, typename Request, typename Result>
bool setUpMeshShapeNode(Node& node, const fcl::BVHModel<RS<typename Shape::S>>& model1,
                        const fcl::Transform3<typename Shape::S>& tf1, const Shape& model2,
                        const fcl::Transform3<typename Shape::S>& tf2, const Solver* nsolver, const Request& request,
                        Result& result)
{
  if (model1.getModelType() != fcl::BVH_MODEL_TRIANGLES) return false;
  node.model1 = &model1;
  node.tf1 = tf1;
  node.model2 = &model2;
  node.tf2 = tf2;
  node.nsolver = nsolver;
  node.vertices = model1.vertices;
  node.tri_indices = model1.tri_indices;
  node.request = request;
  node.result = &result;
  return true;
}

/// What the descent policies of a mesh (first) and a shape (a single leaf, second) share: the mesh's node is
/// always the one split, left child first (FCL's order).
template <typename Node>
class MeshShapeDescent
{
public:
  using S = typename Node::S;
  using BVNode = fcl::BVNode<RS<S>>;
  struct Pair
  {
    int b1;
  };
  struct Visit
  {
    int b1;
    const BVNode& n1;
    bool leaf1;
    static constexpr bool leaf2 = true;
  };
  static constexpr int kMaxChildren = 2;

  explicit MeshShapeDescent(Node& node) : node_(node) {}
  Visit visit(const Pair& p) const
  {
    const BVNode& n = node_.model1->getBV(p.b1);
    return Visit{p.b1, n, isLeaf(n)};
  }
  S size1(const Visit&) const { return 0; }  // never asked: the shape is a leaf
  S size2(const Visit&) const { return 0; }
  int children(const Visit& v, bool, Pair* out) const
  {
    out[0] = Pair{leftChild(v.n1)};
    out[1] = Pair{rightChild(v.n1)};
    return 2;
  }

protected:
  Node& node_;
};

}  // namespace detail
}  // namespace fcl_rs

#endif
