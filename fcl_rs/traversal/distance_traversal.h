// Local-frame distance traversal nodes for RS trees: mesh-mesh (B expressed in A's frame) and mesh-shape.
#ifndef FCL_RS_DISTANCE_TRAVERSAL_H
#define FCL_RS_DISTANCE_TRAVERSAL_H

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_shape_distance_traversal_node.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/descent.h"
#include "fcl_rs/traversal/mesh_mesh_descent.h"
#include "fcl_rs/traversal/moved_frames.h"
#include "fcl_rs/traversal/per_query_table.h"
#include "fcl_rs/traversal/shape_switch.h"

namespace fcl_rs {

/// True when triangles p and q (same coordinates) are at least `distance` apart along the line through their
/// centroids, so that their distance cannot improve a result of `distance`: for any vector d, the gap between
/// the triangles' projections on d, over |d|, is at most their distance. Compared squared (no square root), after
/// subtracting the dot products' rounding (<= 3u |d|_1 max|v|_inf each, doubled) and with 16u of margin on the
/// squares, so that a pair is skipped only when its exact distance is at least `distance`.
template <typename S>
bool leafCannotImprove(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q[3], S distance)
{
  const fcl::Vector3<S> d = (q[0] + q[1] + q[2]) - (p[0] + p[1] + p[2]);
  const S reach = std::max(largestCoordinate(p), largestCoordinate(q));
  const S gap = std::min({d.dot(q[0]), d.dot(q[1]), d.dot(q[2])}) - std::max({d.dot(p[0]), d.dot(p[1]), d.dot(p[2])}) -
                12 * std::numeric_limits<S>::epsilon() * d.template lpNorm<1>() * reach;
  return gap > 0 && gap * gap >= (1 + 16 * std::numeric_limits<S>::epsilon()) * distance * distance * d.squaredNorm();
}

/// Mesh-mesh distance in model1's frame, as FCL's MeshDistanceTraversalNodeRSS: a BV test bounds the
/// distance of model2's node mapped by tf = tf1^-1 tf2; triangle distances and nearest points are in
/// model1's frame until postprocess() moves the points to the world frame.
template <typename S>
class MeshDistanceTraversalNodeRS : public fcl::detail::MeshDistanceTraversalNode<RS<S>>
{
public:
  void preprocess() override
  {
    start_distance_ = this->result->min_distance;
    // Seeds the result with the first triangle pair so that pruning starts from a finite distance.
    fcl::detail::distancePreprocessOrientedNode(this->model1, this->model2, this->vertices1, this->vertices2,
                                                this->tri_indices1, this->tri_indices2, 0, 0, tf, this->request,
                                                *this->result);
  }

  /// Moves the nearest points to the world frame if this query found them. FCL's version decides by
  /// result.o1/o2 == model1/model2, which, in a result shared by several queries (the broadphase callbacks), moves
  /// an earlier query's world points again when two objects share these two geometries.
  void postprocess() override
  {
    if (this->request.enable_nearest_points && this->result->min_distance < start_distance_)
    {
      this->result->nearest_points[0] = this->tf1 * this->result->nearest_points[0];
      this->result->nearest_points[1] = this->tf1 * this->result->nearest_points[1];
    }
  }

  S BVTesting(int b1, int b2) const override
  {
    if (this->enable_statistics) this->num_bv_tests++;
    return distanceLowerBound<S>(tf.linear(), tf.translation(), this->model1->getBV(b1).bv,
                                 this->model2->getBV(b2).bv, this->result->min_distance);
  }

  /// BVTesting with model2's node frame already moved: moved2 = detail::MovedFrame(tf, model2's node b2).
  S BVTesting(int b1, int b2, const detail::MovedFrame<S>& moved2) const
  {
    if (this->enable_statistics) this->num_bv_tests++;
    return distanceLowerBound<S>(moved2, this->model1->getBV(b1).bv, this->model2->getBV(b2).bv,
                                 this->result->min_distance);
  }

  void leafTesting(int b1, int b2) const override
  {
    fcl::detail::meshDistanceOrientedNodeLeafTesting(b1, b2, this->model1, this->model2, this->vertices1,
                                                     this->vertices2, this->tri_indices1, this->tri_indices2, tf,
                                                     this->enable_statistics, this->num_leaf_tests, this->request,
                                                     *this->result);
  }

  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();

private:
  S start_distance_ = 0;
};

namespace detail {

/// The mesh-mesh leaf: triangle id1 of model1 (vertices tri1) and triangle id2 of model2 (vertices tri2, moved into
/// model1's frame by node.tf as V(node.tf * v)) measured by FCL's triangle distance, the result updated. Every
/// mesh-mesh distance measures its triangle pairs here, so a pair gives the same value whichever search reaches it.
template <typename S>
void measureTrianglePair(MeshDistanceTraversalNodeRS<S>& node, int id1, int id2, const fcl::Vector3<S> tri1[3],
                         const fcl::Vector3<S> tri2[3])
{
  if (node.enable_statistics) node.num_leaf_tests++;
  fcl::Vector3<S> P, Q;
  const S d = fcl::detail::TriangleDistance<S>::triDistance(tri1, tri2, P, Q);
  if (node.request.enable_nearest_points)
    node.result->update(d, node.model1, node.model2, id1, id2, P, Q);
  else
    node.result->update(d, node.model1, node.model2, id1, id2);
}

/// The descent policy of mesh-mesh distance (descendBestFirst). A pair of leaves is bounded by its triangles'
/// distance itself, which is exact and cheaper than an RS bound (docs/kernel.md): it is measured at once, and the
/// pair is never visited again. A gap along the line through the triangles' centroids first skips pairs that
/// cannot improve the result (15-52 % of them in fcl_rs_bench_distance). As in mesh-mesh collision, a node of
/// model2 has its frame moved into model1's coordinates once per query, not once per bound, and so has each of
/// model2's vertices (as FCL's triangle distance moves them) when first used.
template <typename S>
class MeshDistanceDescent : public MeshMeshDescent<S>
{
public:
  using Node = MeshDistanceTraversalNodeRS<S>;
  using Base = MeshMeshDescent<S>;
  using typename Base::Pair;
  using typename Base::Visit;
  using typename Base::BVNode;
  using V = fcl::Vector3<S>;

  explicit MeshDistanceDescent(Node& node)
    : Base(*node.model1, *node.model2), node_(node), R_(node.tf.linear()), T_(node.tf.translation()),
      moved_(R_, T_, *node.model2), moved_vertices_(std::size_t(std::max(node.model2->num_vertices, 0)))
  {
  }
  int children(const Visit& v, bool first, Pair* out) const
  {
    out[0] = first ? Pair{leftChild(v.n1), v.b2} : Pair{v.b1, leftChild(v.n2)};
    out[1] = first ? Pair{rightChild(v.n1), v.b2} : Pair{v.b1, rightChild(v.n2)};
    return 2;
  }
  bool canStop(S bound) const { return node_.Node::canStop(bound); }
  void leafTest(const Visit& v) { node_.Node::leafTesting(v.b1, v.b2); }  // two single-triangle models
  S bound(const Pair& p)
  {
    const BVNode& n1 = this->model1_.getBV(p.b1);
    const BVNode& n2 = this->model2_.getBV(p.b2);
    if (!isLeaf(n1) || !isLeaf(n2)) return node_.Node::BVTesting(p.b1, p.b2, moved_(p.b2));
    const int id1 = primitiveId(n1), id2 = primitiveId(n2);
    const auto p_vertices = triangleVertices(node_.vertices1, node_.tri_indices1[id1]);
    const V* tri1 = p_vertices.data();
    const std::array<std::size_t, 3> t2 = vertexIds(node_.tri_indices2[id2]);
    const V tri2[3] = {movedVertex(int(t2[0])), movedVertex(int(t2[1])), movedVertex(int(t2[2]))};
    if (!leafCannotImprove(tri1, tri2, node_.result->min_distance)) measureTrianglePair(node_, id1, id2, tri1, tri2);
    return std::numeric_limits<S>::max();
  }

private:
  const V& movedVertex(int i)
  {
    return moved_vertices_.get(std::size_t(i), [&] { return V(node_.tf * node_.vertices2[i]); });
  }

  Node& node_;
  const fcl::Matrix3<S> R_;
  const fcl::Vector3<S> T_;
  MovedFrames<S> moved_;
  PerQueryTable<V> moved_vertices_;
};

}  // namespace detail

/// Runs the mesh-mesh distance traversal of node (preprocess, descent, postprocess) on the descent engine, best
/// first (detail::descendBestFirst; fcl_rs_bench_distance: FCL's ordered depth-first descent makes 1.0-1.5x the
/// BV tests and 1.2-1.7x the triangle tests, docs/kernel.md).
template <typename S>
void distanceTrees(MeshDistanceTraversalNodeRS<S>& node)
{
  detail::MeshDistanceDescent<S> descent(node);
  node.MeshDistanceTraversalNodeRS<S>::preprocess();
  detail::descendBestFirst<detail::MeshDistanceDescent<S>, S>(descent, {0, 0});
  node.MeshDistanceTraversalNodeRS<S>::postprocess();
}

/// Sets up node for model1 at tf1 against model2 at tf2; false unless both are triangle meshes.
/// Unlike FCL's oriented nodes (whose constructor reads rel_err and abs_err from a default request, so
/// both are always 0), the request's rel_err and abs_err are honoured.
template <typename S>
bool initialize(MeshDistanceTraversalNodeRS<S>& node, const fcl::BVHModel<RS<S>>& model1,
                const fcl::Transform3<S>& tf1, const fcl::BVHModel<RS<S>>& model2, const fcl::Transform3<S>& tf2,
                const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  if (!fcl::detail::setupMeshDistanceOrientedNode(node, model1, tf1, model2, tf2, request, result)) return false;
  node.rel_err = request.rel_err;
  node.abs_err = request.abs_err;
  return true;
}

/// Lower bound on the distance from a mesh node to a shape: the shape's RS is fitted once per query in
/// the mesh's frame, then each node costs one RS-RS bound.
template <typename S, typename Shape>
class ShapeDistanceBound
{
public:
  ShapeDistanceBound(const Shape& shape, const fcl::Transform3<S>& shape_in_mesh)
  {
    fcl::computeBV(shape, shape_in_mesh, bv_);
    moved_ = detail::MovedFrame<S>(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero(), bv_);
  }
  S distance(const RS<S>& node, S enough) const { return distanceLowerBound<S>(moved_, node, bv_, enough); }
  /// Widens the bound's rounding offsets by detail::leafBoundOffsets: a node with a triangle the leaf test reports
  /// as meeting (-1) is never pruned by a bound above 0, so the distance is negative exactly when collide reports.
  void coverLeaves(S offsets)
  {
    moved_ = detail::MovedFrame<S>(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero(), bv_, offsets);
  }

private:
  RS<S> bv_;
  detail::MovedFrame<S> moved_;  ///< bv_'s frame, moved once per query
};

/// Planes and halfspaces have no bounded volume: the node's gap to the shape along its normal (detail::PlaneGap).
template <typename S>
class ShapeDistanceBound<S, fcl::Halfspace<S>> : public detail::PlaneGap<fcl::Halfspace<S>>
{
public:
  using detail::PlaneGap<fcl::Halfspace<S>>::PlaneGap;
  S distance(const RS<S>& node, S) const { return std::max(S(0), this->gap(node)); }
};

template <typename S>
class ShapeDistanceBound<S, fcl::Plane<S>> : public detail::PlaneGap<fcl::Plane<S>>
{
public:
  using detail::PlaneGap<fcl::Plane<S>>::PlaneGap;
  S distance(const RS<S>& node, S) const { return std::max(S(0), this->gap(node)); }
};

/// Mesh-shape distance as FCL's MeshShapeDistanceTraversalNodeRSS, but with the shape bounded in the
/// mesh's frame; leaves use the exact triangle-shape distance (narrowphase/triangle_shape.h), nearest points in the
/// world frame, -1 for a triangle that meets the shape (FCL's convention for its mesh-shape leaves).
template <typename Shape, typename NarrowPhaseSolver>
class MeshShapeDistanceTraversalNodeRS
  : public fcl::detail::MeshShapeDistanceTraversalNode<RS<typename Shape::S>, Shape, NarrowPhaseSolver>
{
public:
  using S = typename Shape::S;

  /// Seeds the result with triangle 0, as FCL's distancePreprocessOrientedNode.
  void preprocess() override { triangleDistance(0); }

  void postprocess() override {}

  S BVTesting(int b1, int) const override
  {
    if (this->enable_statistics) this->num_bv_tests++;
    return bound->distance(this->model1->getBV(b1).bv, this->result->min_distance);
  }

  void leafTesting(int b1, int) const override
  {
    if (this->enable_statistics) this->num_leaf_tests++;
    triangleDistance(primitiveId(this->model1->getBV(b1)));
  }

  std::unique_ptr<ShapeDistanceBound<S, Shape>> bound;

  std::optional<TriangleShapeLeaf<Shape>> leaf;

  /// The leaf: triangle primitive_id measured, the result updated.
  /// A triangle that meets the shape reports -1 (FCL's convention for its shape-triangle distances), except
  /// against a sphere without enable_signed_distance: 0, what FCL's sphere-triangle distance leaves in practice
  /// (it writes nothing there) and its mesh-mesh distance reports while colliding.
  void triangleDistance(int primitive_id) const
  {
    constexpr bool sphere = std::is_same<Shape, fcl::Sphere<S>>::value;
    const auto t = triangleVertices(this->vertices, this->tri_indices[primitive_id]);
    fcl::Vector3<S> on_mesh, on_shape;
    S d = leaf->distance(t.data(), on_mesh, on_shape);
    if (d < 0 && sphere && !this->request.enable_signed_distance) d = 0;
    this->result->update(d, this->model1, this->model2, primitive_id, fcl::DistanceResult<S>::NONE, on_mesh, on_shape);
  }
};

/// Sets up node for the mesh model1 at tf1 against model2 at tf2; false unless model1 is a triangle mesh.
/// rel_err and abs_err come from the request (FCL's mesh-shape nodes fix both at 0).
template <typename Shape, typename NarrowPhaseSolver>
bool initialize(MeshShapeDistanceTraversalNodeRS<Shape, NarrowPhaseSolver>& node,
                const fcl::BVHModel<RS<typename Shape::S>>& model1, const fcl::Transform3<typename Shape::S>& tf1,
                const Shape& model2, const fcl::Transform3<typename Shape::S>& tf2, const NarrowPhaseSolver* nsolver,
                const fcl::DistanceRequest<typename Shape::S>& request,
                fcl::DistanceResult<typename Shape::S>& result)
{
  using S = typename Shape::S;
  if (!detail::setUpMeshShapeNode(node, model1, tf1, model2, tf2, nsolver, request, result)) return false;
  node.rel_err = request.rel_err;
  node.abs_err = request.abs_err;
  node.bound.reset(new ShapeDistanceBound<S, Shape>(model2, tf1.inverse(Eigen::Isometry) * tf2));
  node.leaf.emplace(model2, tf1, tf2);
  node.bound->coverLeaves(detail::leafBoundOffsets(model1, *node.leaf));
  return true;
}

namespace detail {

/// The descent policy of mesh-shape distance (descendBestFirst): a leaf is bounded like any node and measured
/// when the descent reaches it (a triangle-shape distance costs far more than a bound).
template <typename Node>
class MeshShapeDistanceDescent : public MeshShapeDescent<Node>
{
public:
  using S = typename Node::S;
  using typename MeshShapeDescent<Node>::Pair;
  using typename MeshShapeDescent<Node>::Visit;
  using MeshShapeDescent<Node>::MeshShapeDescent;

  bool canStop(S bound) const { return this->node_.Node::canStop(bound); }
  void leafTest(const Visit& v) { this->node_.Node::leafTesting(v.b1, 0); }
  S bound(const Pair& p) { return this->node_.Node::BVTesting(p.b1, 0); }
};

}  // namespace detail

/// Runs the mesh-shape distance traversal of node (preprocess, descent, postprocess) on the descent engine, best
/// first as distanceTrees.
template <typename Shape, typename NarrowPhaseSolver>
void distanceMeshShape(MeshShapeDistanceTraversalNodeRS<Shape, NarrowPhaseSolver>& node)
{
  using Node = MeshShapeDistanceTraversalNodeRS<Shape, NarrowPhaseSolver>;
  detail::MeshShapeDistanceDescent<Node> descent(node);
  node.Node::preprocess();
  detail::descendBestFirst<detail::MeshShapeDistanceDescent<Node>, typename Shape::S>(descent, {0},
                                                                                      detail::DescentConfig{64});
  node.Node::postprocess();
}

// Distance along a separating direction. Best first, a search that already holds a direction n nearly normal to
// the gap of a pair (GJK on the elements' convex hulls gives one) can measure the pair without a descent: the
// gap between two triangles' projections on a unit n bounds their distance from below, so a triangle pair whose
// projections are farther apart than the answer cannot be the nearest. When n separates the pair by nearly its
// distance (convex meshes, or convex where they are nearest), the pairs left are the few triangles about the
// nearest features, measured with the traversals' own leaves: the minimum is the traversal's to the bit.

namespace detail {

/// Per triangle of model, the largest projection of its vertices on n (model's frame), into `highest`; returns
/// the largest over the model.
template <typename S>
double highestAlong(const fcl::BVHModel<RS<S>>& model, const Eigen::Vector3d& n, std::vector<double>& highest)
{
  highest.resize(std::size_t(model.num_tris));
  double top = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < model.num_tris; ++i)
  {
    const std::array<std::size_t, 3> ids = vertexIds(model.tri_indices[i]);
    const double h = std::max({n.dot(model.vertices[ids[0]].template cast<double>()),
                               n.dot(model.vertices[ids[1]].template cast<double>()),
                               n.dot(model.vertices[ids[2]].template cast<double>())});
    highest[std::size_t(i)] = h;
    top = std::max(top, h);
  }
  return top;
}

/// A bound on |v| for every vertex v of model, from its root volume (frame coordinates within its magnitude).
template <typename S>
double modelReach(const fcl::BVHModel<RS<S>>& model)
{
  const RS<S>& root = model.getBV(0).bv;
  return double(root.origin.norm()) + 2 * double(root.magnitude());
}

/// The smallest projection on n of a shape in its own frame, for the shapes whose support is closed form.
template <typename S>
std::optional<double> lowestAlong(const fcl::Box<S>& b, const Eigen::Vector3d& n)
{
  return -0.5 * b.side.template cast<double>().dot(n.cwiseAbs());
}
template <typename S>
std::optional<double> lowestAlong(const fcl::Sphere<S>& s, const Eigen::Vector3d& n)
{
  return -double(s.radius) * n.norm();
}
template <typename S>
std::optional<double> lowestAlong(const fcl::Cylinder<S>& c, const Eigen::Vector3d& n)
{
  return -(double(c.radius) * std::hypot(n.x(), n.y()) + 0.5 * double(c.lz) * std::abs(n.z()));
}
template <typename S>
std::optional<double> lowestAlong(const fcl::Capsule<S>& c, const Eigen::Vector3d& n)
{
  return -(double(c.radius) * n.norm() + 0.5 * double(c.lz) * std::abs(n.z()));
}
template <typename Shape>
std::optional<double> lowestAlong(const Shape&, const Eigen::Vector3d&)
{
  return std::nullopt;
}

/// The axis-aligned box of a triangle's vertices (in double: exact), for a cheap lower bound on a distance.
struct TriangleBox
{
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  TriangleBox() = default;
  template <typename Scalar>
  explicit TriangleBox(const Eigen::Matrix<Scalar, 3, 1> t[3])
    : lo(t[0].template cast<double>().cwiseMin(t[1].template cast<double>()).cwiseMin(t[2].template cast<double>())),
      hi(t[0].template cast<double>().cwiseMax(t[1].template cast<double>()).cwiseMax(t[2].template cast<double>()))
  {
  }
  /// The distance between the two boxes (rounded to nearest: within an ulp or two of the exact one).
  double gap(const TriangleBox& other) const
  {
    return (lo - other.hi).cwiseMax(other.lo - hi).cwiseMax(0.0).norm();
  }
};

/// Scratch of the slab searches, per thread: a query allocates nothing once its thread has run one.
struct SlabScratch
{
  std::vector<double> highest1, highest2;
  std::vector<int> candidates1, candidates2;
};
inline SlabScratch& slabScratch()
{
  static thread_local SlabScratch scratch;
  return scratch;
}

}  // namespace detail

/// Most triangle pairs (mesh-mesh) or triangles (mesh-shape) a slab search measures before it gives up.
constexpr int kSlabMaxMeasured = 256;

/// distanceTrees(node) without the descent, when `direction` (model1's frame, from model1 towards model2) leaves
/// few triangle pairs within the answer of each other along it (see above). True: node.result holds what
/// distanceTrees would give, to the bit (with its nearest points, still in model1's frame). False: more than
/// kSlabMaxMeasured pairs remain; node.result may have been lowered by measured pairs, which leaves the
/// traversal's answer unchanged.
///
/// Pairs are measured in two passes at most. A pass with threshold t measures every pair whose projections come
/// within t + margin; every other pair's exact distance exceeds t + margin, so FCL's triangle distance (points on
/// the triangles to a few ulps of S; model2's vertices moved in S, projections in double: the margin is 256 ulps
/// of S and 64 of double of the coordinates' scale) measures it above t. Once the answer is at most t it is the
/// minimum over all pairs. The first pass takes t just above the gap along n (the distance itself for convex
/// meshes and a converged direction), capped by the distance held; the second, if needed, the answer of the first.
template <typename S>
bool distanceAlong(MeshDistanceTraversalNodeRS<S>& node, const Eigen::Vector3d& direction)
{
  using V = fcl::Vector3<S>;
  const double length = direction.norm();
  if (!(length > 0) || !std::isfinite(length)) return false;
  const Eigen::Vector3d n = direction / length;
  const fcl::BVHModel<RS<S>>& m1 = *node.model1;
  const fcl::BVHModel<RS<S>>& m2 = *node.model2;
  detail::SlabScratch& scratch = detail::slabScratch();
  const Eigen::Matrix3d R = node.tf.linear().template cast<double>();
  const Eigen::Vector3d T = node.tf.translation().template cast<double>();
  // model1's triangles' highest projections; model2's lowest, as offset2 - highest2 (its highest on -n).
  const double top1 = detail::highestAlong(m1, n, scratch.highest1);
  const double offset2 = n.dot(T);
  const double bottom2 = offset2 - detail::highestAlong(m2, Eigen::Vector3d(-(R.transpose() * n)), scratch.highest2);
  const double reach = std::max(detail::modelReach(m1), detail::modelReach(m2) + T.norm());
  const double margin = (256 * double(std::numeric_limits<S>::epsilon()) + 64 * std::numeric_limits<double>::epsilon()) * reach;
  S threshold = std::min(node.result->min_distance, S(std::max(bottom2 - top1, 0.0) + 1e-6 * reach));
  V moved[kSlabMaxMeasured][3];
  detail::TriangleBox boxes2[kSlabMaxMeasured];
  for (;;)
  {
    const double within = double(threshold) + margin;
    scratch.candidates1.clear();
    scratch.candidates2.clear();
    for (int i = 0; i < m1.num_tris; ++i)
      if (scratch.highest1[std::size_t(i)] >= bottom2 - within) scratch.candidates1.push_back(i);
    for (int j = 0; j < m2.num_tris; ++j)
      if (offset2 - scratch.highest2[std::size_t(j)] <= top1 + within) scratch.candidates2.push_back(j);
    if (scratch.candidates1.empty()) return true;  // no pair within the distance held
    if (scratch.candidates1.size() * scratch.candidates2.size() > std::size_t(kSlabMaxMeasured)) return false;
    // Nearest along n first, so that the boxes' gaps below skip most of the others.
    std::sort(scratch.candidates1.begin(), scratch.candidates1.end(),
              [&](int x, int y) { return scratch.highest1[std::size_t(x)] > scratch.highest1[std::size_t(y)]; });
    std::sort(scratch.candidates2.begin(), scratch.candidates2.end(),
              [&](int x, int y) { return scratch.highest2[std::size_t(x)] > scratch.highest2[std::size_t(y)]; });
    for (std::size_t k = 0; k < scratch.candidates2.size(); ++k)
    {
      const std::array<std::size_t, 3> ids = vertexIds(node.tri_indices2[scratch.candidates2[k]]);
      for (int c = 0; c < 3; ++c) moved[k][c] = V(node.tf * node.vertices2[ids[std::size_t(c)]]);
      boxes2[k] = detail::TriangleBox(moved[k]);
    }
    for (const int i : scratch.candidates1)
    {
      const std::array<V, 3> tri1 = triangleVertices(node.vertices1, node.tri_indices1[i]);
      const detail::TriangleBox box1(tri1.data());
      for (std::size_t k = 0; k < scratch.candidates2.size(); ++k)
      {
        const int j = scratch.candidates2[k];
        // The gap along n, then the gap of the triangles' boxes: both at most the pair's distance.
        if (offset2 - scratch.highest2[std::size_t(j)] - scratch.highest1[std::size_t(i)] <= within &&
            box1.gap(boxes2[k]) <= double(node.result->min_distance) + margin)
          detail::measureTrianglePair(node, i, j, tri1.data(), moved[k]);
      }
    }
    if (!(node.result->min_distance > threshold)) return true;
    threshold = node.result->min_distance;  // the second pass measures every pair that can be below it
  }
}

/// distanceMeshShape(node) without the descent, as distanceAlong for meshes: `direction` in the shape's frame,
/// from the mesh towards the shape. The leaf measures in double in the shape's frame: the margin is 256 ulps of
/// double of the coordinates' scale and the leaf's tolerance (a triangle beyond it does not meet the shape).
/// False for shapes without a closed-form support (lowestAlong) and when more than kSlabMaxMeasured triangles
/// remain.
template <typename Shape, typename NarrowPhaseSolver>
bool distanceAlong(MeshShapeDistanceTraversalNodeRS<Shape, NarrowPhaseSolver>& node, const Eigen::Vector3d& direction)
{
  using S = typename Shape::S;
  const double length = direction.norm();
  if (!(length > 0) || !std::isfinite(length)) return false;
  const Eigen::Vector3d n = direction / length;
  const std::optional<double> bottom = detail::lowestAlong(*node.model2, n);
  if (!bottom) return false;
  const fcl::BVHModel<RS<S>>& mesh = *node.model1;
  detail::SlabScratch& scratch = detail::slabScratch();
  const Eigen::Isometry3d& to_shape = node.leaf->meshToShape();
  const double offset = n.dot(to_shape.translation());
  const double top = offset + detail::highestAlong(mesh, Eigen::Vector3d(to_shape.linear().transpose() * n), scratch.highest1);
  const double mesh_reach = detail::modelReach(mesh);
  const double reach = std::max(mesh_reach + to_shape.translation().norm(), node.leaf->geometry().reach());
  const double margin = 256 * std::numeric_limits<double>::epsilon() * reach + double(node.leaf->tolerance(S(mesh_reach)));
  S threshold = std::min(node.result->min_distance, S(std::max(*bottom - top, 0.0) + 1e-6 * reach));
  detail::TriangleBox shape_box;
  for (int k = 0; k < 3; ++k)
  {
    shape_box.lo[k] = *detail::lowestAlong(*node.model2, Eigen::Vector3d::Unit(k));
    shape_box.hi[k] = -*detail::lowestAlong(*node.model2, Eigen::Vector3d(-Eigen::Vector3d::Unit(k)));
  }
  for (;;)
  {
    const double within = double(threshold) + margin;
    scratch.candidates1.clear();
    for (int i = 0; i < mesh.num_tris; ++i)
      if (offset + scratch.highest1[std::size_t(i)] >= *bottom - within) scratch.candidates1.push_back(i);
    if (scratch.candidates1.size() > std::size_t(kSlabMaxMeasured)) return false;
    // Nearest along n first, so that the boxes' gaps below skip most of the others.
    std::sort(scratch.candidates1.begin(), scratch.candidates1.end(),
              [&](int x, int y) { return scratch.highest1[std::size_t(x)] > scratch.highest1[std::size_t(y)]; });
    for (const int i : scratch.candidates1)
    {
      const std::array<fcl::Vector3<S>, 3> p = triangleVertices(node.vertices, node.tri_indices[i]);
      triangle_shape::Vec t[3];
      // The gap of the moved triangle's box and the shape's: at most their distance.
      if (detail::TriangleBox(node.leaf->moved(p.data(), t)).gap(shape_box) <= double(node.result->min_distance) + margin)
        node.triangleDistance(i);
    }
    if (!(node.result->min_distance > threshold)) return true;
    threshold = node.result->min_distance;
  }
}

}  // namespace fcl_rs

#endif
