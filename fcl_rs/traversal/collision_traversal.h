// Local-frame traversal nodes for RS trees: mesh-mesh (B expressed in A's frame) and mesh-shape.
#ifndef FCL_RS_TRAVERSAL_H
#define FCL_RS_TRAVERSAL_H

#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/descent.h"
#include "fcl_rs/traversal/mesh_mesh_descent.h"
#include "fcl_rs/traversal/moved_frames.h"
#include "fcl_rs/traversal/shape_switch.h"

namespace fcl_rs {

/// Mesh-mesh collision with both trees kept in their meshes' frames: a BV test maps model2's node
/// into model1's frame through (R, T) = tf1^-1 tf2; nothing is copied or refitted per query.
template <typename S>
class MeshCollisionTraversalNodeRS : public fcl::detail::MeshCollisionTraversalNode<RS<S>>
{
public:
  MeshCollisionTraversalNodeRS() : R(fcl::Matrix3<S>::Identity()), T(fcl::Vector3<S>::Zero()) {}

  bool BVTesting(int b1, int b2) const override
  {
    if (this->enable_statistics) this->num_bv_tests++;
    return !overlap(R, T, this->model1->getBV(b1).bv, this->model2->getBV(b2).bv, test, world_offsets);
  }

  /// BVTesting with model2's node frame already moved: moved2 = detail::BoxedFrame(R, T, model2's node b2).
  bool BVTesting(int b1, int b2, const detail::BoxedFrame<S>& moved2) const
  {
    if (this->enable_statistics) this->num_bv_tests++;
    return !detail::overlap(moved2, this->model1->getBV(b1).bv, this->model2->getBV(b2).bv, test);
  }

  /// BVTesting of model1's leaf b1 against model2's inner node b2 (moved2 = detail::MovedFrame of b2): the leaf's
  /// triangle against b2's nine slabs (detail::triangleOverlap).
  bool leafTriangleTesting(int b1, int b2, const detail::MovedFrame<S>& moved2) const
  {
    if (this->enable_statistics) this->num_bv_tests++;
    const fcl::BVNode<RS<S>>& leaf = this->model1->getBV(b1);
    const auto p = triangleVertices(this->vertices1, this->tri_indices1[primitiveId(leaf)]);
    return !detail::triangleOverlap(p.data(), leaf.bv, moved2, this->model2->getBV(b2).bv);
  }

  /// BVTesting of model1's inner node b1 against model2's leaf b2: b1's nine slabs against the leaf's triangle.
  bool leafTriangleTesting(int b1, int b2) const
  {
    if (this->enable_statistics) this->num_bv_tests++;
    const fcl::BVNode<RS<S>>& leaf = this->model2->getBV(b2);
    const auto q = triangleVertices(this->vertices2, this->tri_indices2[primitiveId(leaf)]);
    return !detail::triangleOverlap(this->model1->getBV(b1).bv, R, T, q.data(), leaf.bv, world_offsets);
  }

  void leafTesting(int b1, int b2) const override
  {
    meshTriangleLeafTesting(
        b1, b2, this->model1, this->model2, this->vertices1, this->vertices2, this->tri_indices1,
        this->tri_indices2, R, T, this->tf1, this->tf2, this->enable_statistics, this->cost_density,
        this->num_leaf_tests, this->request, *this->result);
  }

  fcl::Matrix3<S> R;
  fcl::Vector3<S> T;
  OverlapTest test = kDefaultOverlapTest;
  S world_offsets = 0;  ///< |t1|_1 + |t2|_1: the overlap test covers the world frame's rounding, as the leaf test does
};

/// Sets up node for model1 at tf1 against model2 at tf2; false unless both are triangle meshes.
template <typename S>
bool initialize(MeshCollisionTraversalNodeRS<S>& node, const fcl::BVHModel<RS<S>>& model1,
                const fcl::Transform3<S>& tf1, const fcl::BVHModel<RS<S>>& model2, const fcl::Transform3<S>& tf2,
                const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  node.world_offsets = tf1.translation().template lpNorm<1>() + tf2.translation().template lpNorm<1>();
  return fcl::detail::setupMeshCollisionOrientedNode(node, model1, tf1, model2, tf2, request, result);
}

/// A leaf and an inner node go to leafTriangleTesting rather than the RS test when the leaf's size() (squared
/// diagonal) is at most this many times the inner node's: its box at most twice as long. The leaf's triangle on
/// the inner node's nine slabs costs about 40 % of an RS test and is tighter there, but it skips the leaf's own
/// slabs against the inner node's box, which decide most pairs of a large triangle and a small node (a large flat
/// environment against a robot; docs/kernel.md).
constexpr int kTriangleTestMaxSizeRatio = 4;

namespace detail {

/// The descent policy of mesh-mesh collision (descendDepthFirst).
/// Two leaves go straight to the triangle test, with no RS test first: the leaf test opens with a certified
/// plane rejection that costs less than an RS test and rejects most of what the RS test would, so the RS test
/// of a leaf pair mostly duplicated it (docs/kernel.md). Unlike FCL's recursion, a visited leaf pair therefore
/// counts as a leaf test, not as a BV test. A leaf and an inner node at least half its diagonal test the leaf's
/// triangle against the inner node's nine slabs (leafTriangleTesting, kTriangleTestMaxSizeRatio).
/// A node of model2 usually meets several nodes of model1, so its frame is moved into model1's coordinates
/// once per query (MovedFrames), not once per test.
/// Child order: FCL's (left first) unless the request stops after a few contacts; then the child whose origin
/// (the mean of its points) is nearer the other node's goes first. Contacts cluster where the meshes
/// interpenetrate, so that reaches the first one with 13-59 % fewer BV tests on the benchmark pairs
/// (docs/kernel.md); an exhaustive request visits every overlapping pair in any order, and ordering would cost
/// it about 3 %.
template <typename S>
class MeshCollisionDescent : public MeshMeshDescent<S>
{
public:
  using Node = MeshCollisionTraversalNodeRS<S>;
  using Base = MeshMeshDescent<S>;
  using typename Base::Pair;
  using typename Base::Visit;

  explicit MeshCollisionDescent(Node& node)
    : Base(*node.model1, *node.model2), node_(node), moved_(node.R, node.T, *node.model2, node.world_offsets),
      nearer_first_(visitsNearerFirst(node.request))
  {
  }
  bool leafTest(const Visit& v)
  {
    node_.Node::leafTesting(v.b1, v.b2);
    return node_.request.isSatisfied(*node_.result);
  }
  bool nodeApart(const Visit& v)
  {
    // (Written out: a helper for the size rule costs 1-3 % more instructions, gcc 12.)
    constexpr S ratio = kTriangleTestMaxSizeRatio;
    return v.leaf1 && v.n1.bv.size() <= ratio * v.n2.bv.size()   ? node_.leafTriangleTesting(v.b1, v.b2, moved_(v.b2))
           : v.leaf2 && v.n2.bv.size() <= ratio * v.n1.bv.size() ? node_.leafTriangleTesting(v.b1, v.b2)
                                                                  : node_.Node::BVTesting(v.b1, v.b2, moved_(v.b2));
  }
  int children(const Visit& v, bool first, Pair* out)
  {
    if (first)
    {
      int near = leftChild(v.n1), far = rightChild(v.n1);
      if (nearer_first_)
      {
        const fcl::Vector3<S>& c2 = moved_(v.b2).origin;
        if ((this->model1_.getBV(far).bv.origin - c2).squaredNorm() <
            (this->model1_.getBV(near).bv.origin - c2).squaredNorm())
          std::swap(near, far);
      }
      out[0] = Pair{near, v.b2};
      out[1] = Pair{far, v.b2};
    }
    else
    {
      int near = leftChild(v.n2), far = rightChild(v.n2);
      if (nearer_first_)
      {
        const fcl::Vector3<S>& c1 = v.n1.bv.origin;
        if ((moved_(far).origin - c1).squaredNorm() < (moved_(near).origin - c1).squaredNorm()) std::swap(near, far);
      }
      out[0] = Pair{v.b1, near};
      out[1] = Pair{v.b1, far};
    }
    return 2;
  }

private:
  Node& node_;
  MovedFrames<S, BoxedFrame<S>> moved_;
  bool nearer_first_;
};

}  // namespace detail

/// Runs the mesh-mesh traversal of node on the descent engine (detail::descendDepthFirst, FCL's order: split the
/// larger node, stop once the request is satisfied) with direct calls: FCL's generic recursion makes five virtual
/// calls per visited pair, which costs about as much as an RS test. detail::MeshCollisionDescent says what is
/// tested and in which order.
template <typename S>
void collideTrees(MeshCollisionTraversalNodeRS<S>& node)
{
  detail::MeshCollisionDescent<S> descent(node);
  detail::descendDepthFirst(descent, {0, 0});
}

/// How a shape is tested against the mesh's nodes: its RS in its own frame, moved into the mesh's frame once per
/// query (BoxedFrame, as a mesh-mesh traversal moves the second tree's nodes), neither refitted nor placed. Planes,
/// halfspaces, spheres, boxes, capsules and cylinders have specialisations below that read the shape itself.
template <typename S, typename Shape>
class ShapeBound
{
public:
  /// With the shape's own-frame RS from ownFrameRS's per-thread cache where it has one (an ellipsoid), else fitted
  /// here.
  ShapeBound(const Shape& shape, const fcl::Transform3<S>& shape_in_mesh) : ShapeBound(fitted(shape), shape_in_mesh) {}
  /// From the shape's RS fitted in its own frame (fcl::computeBV with the identity), for a shape queried many
  /// times.
  ShapeBound(const RS<S>& bv_in_shape, const fcl::Transform3<S>& shape_in_mesh)
    : bv_(bv_in_shape), moved_(shape_in_mesh.linear(), shape_in_mesh.translation(), bv_)
  {
  }
  /// node.overlap(bv_) with bv_ at shape_in_mesh.
  bool overlaps(const RS<S>& node) const { return detail::overlap(moved_, node, bv_, kDefaultOverlapTest); }
  /// Widens the test's rounding offsets by TriangleShapeLeaf::boundOffsets, so that it never prunes a triangle the
  /// leaf test reports.
  void coverLeaves(S offsets) { moved_.offsets += offsets; }

private:
  static RS<S> fitted(const Shape& shape)
  {
    if constexpr (detail::HasShapeKey<Shape>::value)
      return ownFrameRS(shape);
    else
    {
      RS<S> bv;
      fcl::computeBV(shape, fcl::Transform3<S>::Identity(), bv);
      return bv;
    }
  }

  RS<S> bv_;
  detail::BoxedFrame<S> moved_;
};

/// Halfspaces and planes are unbounded: exact support tests (PlaneGap) instead of a huge slab volume.
template <typename S>
class ShapeBound<S, fcl::Halfspace<S>> : public detail::PlaneGap<fcl::Halfspace<S>>
{
public:
  using detail::PlaneGap<fcl::Halfspace<S>>::PlaneGap;
  bool overlaps(const RS<S>& node) const { return this->gap(node) <= 0; }
};

template <typename S>
class ShapeBound<S, fcl::Plane<S>> : public detail::PlaneGap<fcl::Plane<S>>
{
public:
  using detail::PlaneGap<fcl::Plane<S>>::PlaneGap;
  bool overlaps(const RS<S>& node) const { return this->gap(node) <= 0; }
};

/// A sphere is tested exactly against a node's principal box and diagonal slabs: cheaper than an RS test of
/// the sphere's volume and tighter (the sphere itself, not a polytope around it).
template <typename S>
class ShapeBound<S, fcl::Sphere<S>>
{
public:
  ShapeBound(const fcl::Sphere<S>& shape, const fcl::Transform3<S>& shape_in_mesh)
    : centre_(shape_in_mesh.translation()), radius_(shape.radius), offset_(centre_.template lpNorm<1>())
  {
  }
  bool overlaps(const RS<S>& node) const
  {
    if (node.empty()) return false;
    const fcl::Vector3<S> y = node.toFrame(centre_);
    const detail::Box<S> box(node);
    // As a pair test's: the centre's and the node's offsets, both extents, and the centre's distance from the
    // node's frame origin, which the stored frame's departure from orthonormality scales.
    const S tol = detail::pairRoundingBound<S>(node.origin.template lpNorm<1>() + offset_, box.reach() + radius_,
                                               y.template lpNorm<1>());
    const fcl::Vector3<S> outside = ((y - box.c).cwiseAbs() - box.h).cwiseMax(S(0));
    const S reach = radius_ + tol;
    if (outside.squaredNorm() > reach * reach) return false;
    for (int k = 3; k < kNumSlabs; ++k)
    {
      const S v = projectOnSlab(y, k);
      if (v + reach < S(node.lo[k]) || v - reach > S(node.hi[k])) return false;
    }
    return true;
  }

  /// As ShapeBound's: the leaf test's tolerance terms join the offsets.
  void coverLeaves(S offsets) { offset_ += offsets; }

private:
  fcl::Vector3<S> centre_;  ///< in the mesh's frame
  S radius_;
  S offset_;  ///< |centre_|_1
};

namespace detail {

/// The support radius of a box, capsule or cylinder (its own frame: centred at the origin, axis along z) along
/// directions given, one per lane, by their dots x, y, z with the shape's axes (signs ignored), for directions of
/// length `norm`; and its support along each of its own axes (`own`, lanes 0-2).
template <typename Shape>
struct CentredSupport;

template <typename S>
struct CentredSupport<fcl::Box<S>>
{
  explicit CentredSupport(const fcl::Box<S>& box)
    : own(float(box.side[0] / 2), float(box.side[1] / 2), float(box.side[2] / 2), 0.0f)
  {
  }
  Lanes operator()(const Lanes& x, const Lanes& y, const Lanes& z, float) const
  {
    return x.abs() * own[0] + y.abs() * own[1] + z.abs() * own[2];
  }
  Lanes own;
};

template <typename S>
struct CentredSupport<fcl::Capsule<S>>
{
  explicit CentredSupport(const fcl::Capsule<S>& capsule)
    : half_length(float(capsule.lz / 2)), radius(float(capsule.radius)),
      own(radius, radius, half_length + radius, 0.0f)
  {
  }
  Lanes operator()(const Lanes&, const Lanes&, const Lanes& z, float norm) const
  {
    return z.abs() * half_length + radius * norm;
  }
  float half_length, radius;
  Lanes own;
};

template <typename S>
struct CentredSupport<fcl::Cylinder<S>>
{
  explicit CentredSupport(const fcl::Cylinder<S>& cylinder)
    : half_length(float(cylinder.lz / 2)), radius(float(cylinder.radius)), own(radius, radius, half_length, 0.0f)
  {
  }
  /// The disc's part from the direction's component across the axis, (x, y), not from sqrt(norm^2 - z^2), which
  /// loses all precision where the direction is nearly along the axis.
  Lanes operator()(const Lanes& x, const Lanes& y, const Lanes& z, float) const
  {
    return z.abs() * half_length + radius * (x * x + y * y).sqrt();
  }
  float half_length, radius;
  Lanes own;
};

/// A box, capsule or cylinder tested against a node as the boxed test (boxedOverlap) tests two volumes, with the
/// shape's exact support in place of the second volume's principal box: the node's nine slabs against the shape's
/// support along them, the shape's three axes against the node's principal box. No volume is fitted or moved for
/// the shape, its slabs are never tested (a box's own volume has no diagonal cuts), and the node's slabs see the
/// shape itself, not a polytope around it. The arithmetic and so the rounding bound are the boxed test's: the
/// shape's support along a unit direction is at most its reach (the largest of `own`) times the L1 norm of the
/// direction's dots with its axes, as a box's is, and its axes and sizes are rounded to float as a stored volume's
/// are (to nearest, half a float ulp of the reach, far inside the bound's storage term).
template <typename S, typename Shape>
class SupportBound
{
public:
  SupportBound(const Shape& shape, const fcl::Transform3<S>& shape_in_mesh)
    : support_(shape), centre_(shape_in_mesh.translation()), offsets_(centre_.template lpNorm<1>()),
      reach_(S(support_.own.template head<3>().maxCoeff()))
  {
    const fcl::Matrix3<S>& axes = shape_in_mesh.linear();
    for (int k = 0; k < 3; ++k)
      axis_rows_[k] = Lanes(float(axes(k, 0)), float(axes(k, 1)), float(axes(k, 2)), 0.0f);
  }
  /// Flattened, as boxedOverlap is inlined by force: so that the node's side stays in registers and the parts of
  /// BoxedDiagonals this test never reads are not computed.
  __attribute__((flatten)) bool overlaps(const RS<S>& node) const
  {
    const BoxedAxes<S> a(axis_rows_, node);
    const fcl::Vector3<S> delta = centre_ - a.origin;  // in S: both may be far from the model origin
    const Lanes centre = float(delta[0]) * a.a_rows[0] + float(delta[1]) * a.a_rows[1] + float(delta[2]) * a.a_rows[2];
    const Lanes d = centre - a.c1;  // from the node's box centre to the shape's centre, the node's frame
    const float tol = storedPairRoundingBound<S>(offsets_ + a.origin_norm, a.reach + reach_,
                                                 S(d.abs().template head<3>().sum()), delta.template lpNorm<1>());
    // Along the node's axis i the shape reaches its support of (M_i0, M_i1, M_i2), lane i of w[0], w[1], w[2].
    const Lanes gap1 = d.abs() - support_(a.w[0], a.w[1], a.w[2], 1.0f) - a.h1;
    if (gap1.template head<3>().maxCoeff() > tol) return false;
    const Lanes e = -(d[0] * a.m[0] + d[1] * a.m[1] + d[2] * a.m[2]);  // to the node's box centre, the shape's frame
    const Lanes& h1 = a.h1;
    const Lanes gap2 = e.abs() - (a.m[0].abs() * h1[0] + a.m[1].abs() * h1[1] + a.m[2].abs() * h1[2]) - support_.own;
    if (gap2.template head<3>().maxCoeff() > tol) return false;
    // The node's diagonals, sqrt(2) times (its directions u_i +- u_j, of length sqrt(2)), as boxedOverlap's; unused
    // lanes give 0 - 0 - a radius, never above the tolerance.
    const BoxedDiagonals<S> dg(a, node);
    Lanes centre_diagonal[2];
    diagonalLanes(centre, centre_diagonal[0], centre_diagonal[1]);
    Lanes worst = Lanes::Constant(-std::numeric_limits<float>::max());
    for (int h = 0; h < 2; ++h)
    {
      const Lanes radius = support_(dg.w_diagonal[0][h], dg.w_diagonal[1][h], dg.w_diagonal[2][h], float(M_SQRT2));
      worst = worst.max((centre_diagonal[h] - dg.mid1[h]).abs() - dg.half1[h] - radius);
    }
    return !(worst.maxCoeff() > float(M_SQRT2) * tol);
  }

  /// As ShapeBound's: the leaf test's tolerance terms join the offsets.
  void coverLeaves(S offsets) { offsets_ += offsets; }

private:
  CentredSupport<Shape> support_;
  Lanes axis_rows_[3];      ///< rows of the shape's rotation in the mesh's frame, as BoxedFrame::axis_rows
  fcl::Vector3<S> centre_;  ///< in the mesh's frame
  S offsets_;               ///< |centre_|_1 (+ the leaf's offsets)
  S reach_;
};

}  // namespace detail

template <typename S>
class ShapeBound<S, fcl::Box<S>> : public detail::SupportBound<S, fcl::Box<S>>
{
public:
  using detail::SupportBound<S, fcl::Box<S>>::SupportBound;
};

template <typename S>
class ShapeBound<S, fcl::Capsule<S>> : public detail::SupportBound<S, fcl::Capsule<S>>
{
public:
  using detail::SupportBound<S, fcl::Capsule<S>>::SupportBound;
};

template <typename S>
class ShapeBound<S, fcl::Cylinder<S>> : public detail::SupportBound<S, fcl::Cylinder<S>>
{
public:
  using detail::SupportBound<S, fcl::Cylinder<S>>::SupportBound;
};

/// Mesh-shape collision in the mesh's frame: the shape is bounded once per query in that frame;
/// leaves use the exact triangle-shape test (narrowphase/triangle_shape.h), FCL's solver only for contact details.
template <typename Shape, typename NarrowPhaseSolver>
class MeshShapeCollisionTraversalNodeRS
  : public fcl::detail::MeshShapeCollisionTraversalNode<RS<typename Shape::S>, Shape, NarrowPhaseSolver>
{
public:
  using S = typename Shape::S;

  bool BVTesting(int b1, int) const override
  {
    if (this->enable_statistics) this->num_bv_tests++;
    return !bound->overlaps(this->model1->getBV(b1).bv);
  }

  void leafTesting(int b1, int) const override
  {
    if (this->enable_statistics) this->num_leaf_tests++;
    meshShapeLeafTesting(*leaf, primitiveId(this->model1->getBV(b1)), this->model1, *this->model2, this->vertices,
                         this->tri_indices, this->tf1, this->tf2, this->nsolver, this->cost_density, this->request,
                         *this->result);
  }

  using Leaf = TriangleShapeLeaf<Shape>;
  /// Held by value: a query that visits one or two nodes would otherwise spend a good part of its time in the
  /// allocator.
  std::optional<ShapeBound<S, Shape>> bound;
  std::optional<Leaf> leaf;
};

/// Sets up node for the mesh model1 at tf1 against the shape model2 at tf2; false unless model1 is a triangle
/// mesh. bound: model2's bound in model1's frame when the caller made it (a shape queried many times is fitted
/// once, ShapeBound's RS constructor), or none to fit it here.
template <typename Shape, typename NarrowPhaseSolver>
bool initialize(MeshShapeCollisionTraversalNodeRS<Shape, NarrowPhaseSolver>& node,
                const fcl::BVHModel<RS<typename Shape::S>>& model1, const fcl::Transform3<typename Shape::S>& tf1,
                const Shape& model2, const fcl::Transform3<typename Shape::S>& tf2,
                const NarrowPhaseSolver* nsolver, const fcl::CollisionRequest<typename Shape::S>& request,
                fcl::CollisionResult<typename Shape::S>& result,
                std::optional<ShapeBound<typename Shape::S, Shape>> bound = std::nullopt)
{
  if (!detail::setUpMeshShapeNode(node, model1, tf1, model2, tf2, nsolver, request, result)) return false;
  node.cost_density = model1.cost_density * model2.cost_density;
  node.leaf.emplace(model2, tf1, tf2);
  if (bound)
    node.bound.emplace(std::move(*bound));
  else
    node.bound.emplace(model2, tf1.inverse(Eigen::Isometry) * tf2);
  node.bound->coverLeaves(detail::leafBoundOffsets(model1, *node.leaf));
  return true;
}

namespace detail {

/// The descent policy of mesh-shape collision (descendDepthFirst): a leaf is tested against the shape's bound
/// before the leaf test, as in FCL's recursion, unless the leaf test opens with a cheaper rejection of its own
/// (TriangleShapeLeaf::kRejectsCheaply: the triangle's extent along the shape's axes and normal). Child order as
/// MeshCollisionDescent's: FCL's unless the request stops after a few contacts; then the child whose origin is
/// nearer the shape's goes first.
template <typename Node>
class MeshShapeCollisionDescent : public MeshShapeDescent<Node>
{
public:
  using typename MeshShapeDescent<Node>::Pair;
  using typename MeshShapeDescent<Node>::Visit;
  using S = typename Node::S;

  explicit MeshShapeCollisionDescent(Node& node)
    : MeshShapeDescent<Node>(node), nearer_first_(visitsNearerFirst(node.request))
  {
    if (nearer_first_) shape_ = node.tf1.inverse(Eigen::Isometry) * node.tf2.translation();
  }
  bool leafTest(const Visit& v)
  {
    if constexpr (!Node::Leaf::kRejectsCheaply)
      if (this->node_.Node::BVTesting(v.b1, 0)) return false;
    this->node_.Node::leafTesting(v.b1, 0);
    return this->node_.request.isSatisfied(*this->node_.result);
  }
  bool nodeApart(const Visit& v) { return this->node_.Node::BVTesting(v.b1, 0); }
  int children(const Visit& v, bool first, Pair* out) const
  {
    const int n = MeshShapeDescent<Node>::children(v, first, out);
    const auto& model = *this->node_.model1;
    if (nearer_first_ && (model.getBV(out[1].b1).bv.origin - shape_).squaredNorm() <
                             (model.getBV(out[0].b1).bv.origin - shape_).squaredNorm())
      std::swap(out[0], out[1]);
    return n;
  }

private:
  bool nearer_first_;
  fcl::Vector3<S> shape_;  ///< the shape's origin in the mesh's frame, when nearer_first_
};

}  // namespace detail

/// Runs the mesh-shape traversal of node on the descent engine (detail::MeshShapeCollisionDescent) with direct
/// calls, as collideTrees does for two meshes; FCL's recursion makes five virtual calls per visited node.
template <typename Shape, typename NarrowPhaseSolver>
void collideMeshShape(MeshShapeCollisionTraversalNodeRS<Shape, NarrowPhaseSolver>& node)
{
  detail::MeshShapeCollisionDescent<MeshShapeCollisionTraversalNodeRS<Shape, NarrowPhaseSolver>> descent(node);
  detail::descendDepthFirst(descent, {0});
}

/// Mesh-shape collision of a shape queried at many poses (a robot's link shapes, a planning scene's obstacles):
/// bv_in_shape is its RS fitted once in its own frame (fcl::computeBV with the identity), moved into the mesh's
/// frame per query (ShapeBound) rather than refitted. The mesh's root is tested against it before the traversal
/// is set up: most shapes that pass a caller's cheaper culling (balls, boxes) are still apart from the root, and a
/// query that visits one node should not pay the traversal's set-up. The root test covers the leaf test's
/// tolerance, as the traversal's bound does, so it prunes nothing fcl_rs::collide would report. The answer is
/// fcl_rs::collide's for the same request; result gets its contacts.
template <typename Shape, typename NarrowPhaseSolver>
bool collidePlacedShape(const fcl::BVHModel<RS<typename Shape::S>>& mesh, const fcl::Transform3<typename Shape::S>& tf_mesh,
                        const Shape& shape, const RS<typename Shape::S>& bv_in_shape,
                        const fcl::Transform3<typename Shape::S>& tf_shape, const NarrowPhaseSolver& solver,
                        const fcl::CollisionRequest<typename Shape::S>& request,
                        fcl::CollisionResult<typename Shape::S>& result)
{
  using S = typename Shape::S;
  const fcl::Transform3<S> shape_in_mesh = tf_mesh.inverse(Eigen::Isometry) * tf_shape;
  const S offsets = detail::leafBoundOffsets(mesh, TriangleShapeLeaf<Shape>(shape, tf_mesh, tf_shape));
  const fcl::Matrix3<S> R = shape_in_mesh.linear();
  const fcl::Vector3<S> T = shape_in_mesh.translation();
  if (!overlap(R, T, mesh.getBV(0).bv, bv_in_shape, kDefaultOverlapTest, offsets))
    return false;
  MeshShapeCollisionTraversalNodeRS<Shape, NarrowPhaseSolver> node;
  if constexpr (std::is_constructible_v<ShapeBound<S, Shape>, const RS<S>&, const fcl::Transform3<S>&>)
    initialize(node, mesh, tf_mesh, shape, tf_shape, &solver, request, result,
               std::optional<ShapeBound<S, Shape>>(std::in_place, bv_in_shape, shape_in_mesh));
  else  // a bound that reads the shape itself (ShapeBound's specialisations) needs no fitted volume
    initialize(node, mesh, tf_mesh, shape, tf_shape, &solver, request, result);
  collideMeshShape(node);
  return result.isCollision();
}

}  // namespace fcl_rs

#endif
