// The one switch from a geometry's node type to its primitive shape type, and what every mesh-shape traversal
// shares (collision and distance): the node's set-up, the bounds' cover of the leaf test, the plane and halfspace
// bound, and the descent's pairs.
#ifndef FCL_RS_SHAPE_SWITCH_H
#define FCL_RS_SHAPE_SWITCH_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

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
#include <fcl/geometry/shape/triangle_p.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/node_links.h"

namespace fcl_rs {
namespace detail {

/// f(shape) with geometry cast to its primitive shape type (fcl::Box<S>, ..., fcl::TriangleP<S>), or otherwise()
/// for any other node type (meshes, octrees). Both return the same type. Every entry point that handles shapes by type goes through
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
    case fcl::GEOM_TRIANGLE: return f(static_cast<const fcl::TriangleP<S>&>(geometry));
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

/// What a node bound must add to its rounding offsets so that it never prunes a triangle of model1 that leaf (a
/// TriangleShapeLeaf) reports as meeting the shape: leaf.boundOffsets for model1's points, which lie within
/// |origin|_1 + 2 reach of its frame's origin (reach: along the root's own axes).
template <typename S, typename Leaf>
S leafBoundOffsets(const fcl::BVHModel<RS<S>>& model1, const Leaf& leaf)
{
  const RS<S>& root = model1.getBV(0).bv;
  return leaf.boundOffsets(root.origin.template lpNorm<1>() + 2 * Box<S>(root).reach());
}

/// How far an RS node lies from a plane n . x = d or a halfspace n . x <= d (Shape, |n| = 1), both unbounded and
/// so bounded by no volume: the node's lowest height n . x - d by its exact support along -n (and, for a plane,
/// the plane's height above the node's highest point), less the pair kernel's rounding bound with the plane as
/// b1 without extent. gap(node) > 0 proves the node that far from the shape (collision prunes it, distance
/// bounds it by the gap); <= 0, it may meet it. In the mesh's frame (shape_in_mesh).
template <typename Shape>
class PlaneGap
{
public:
  using S = typename Shape::S;
  PlaneGap(const Shape& shape, const fcl::Transform3<S>& shape_in_mesh) : shape_(fcl::transform(shape, shape_in_mesh))
  {
  }
  S gap(const RS<S>& node) const
  {
    if (node.empty()) return std::numeric_limits<S>::max();
    const fcl::Vector3<S> n = node.axes().transpose() * shape_.n;
    const S at_origin = shape_.n.dot(node.origin) - shape_.d;
    S gap = at_origin - node.support(-n);
    // A node above the plane is not also below it: the second support only where the first leaves it unproven.
    if constexpr (std::is_same_v<Shape, fcl::Plane<S>>)
      if (gap <= 0) gap = std::max(gap, -at_origin - node.support(n));
    return gap - pairRoundingBound<S>(node.origin.template lpNorm<1>() + std::abs(shape_.d) + offsets_,
                                      Box<S>(node).reach());
  }
  /// Widens the rounding offsets by leafBoundOffsets, so that a node with a triangle the leaf test reports never
  /// has a positive gap.
  void coverLeaves(S offsets) { offsets_ = offsets; }

private:
  Shape shape_;
  S offsets_ = 0;
};

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
