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

#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_shape_distance_traversal_node.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/moved_frames.h"
#include "fcl_rs/traversal/per_query_table.h"

namespace fcl_rs {

/// The distance traversal's lower bound on the distance between RS volumes b1 and b2 (b2 mapped into b1's
/// coordinates by x1 = R x2 + T). The gap between two convex sets along any direction, over the direction's
/// length, is a lower bound on their distance, so the bound is the largest such gap over a few directions,
/// cheapest first, returning as soon as it reaches `enough` (the traversal prunes the pair then, whatever the
/// bound): first the principal boxes (which contain the polytopes) along their six face normals, a few dozen
/// flops; then the polytopes' exact supports along the line c through the two box centres. Supports are
/// positively homogeneous, so that gap is measured along c itself and divided by |c| once (no unit vector).
/// Gaps are reduced by their rounding error, so the result never exceeds the true distance: measured along c,
/// every error of a unit direction's gap is scaled by |c| and then divided by it again, and the quotient adds
/// a few ulps of the gap, which is at most |c| (well inside pairRoundingBound's margin).
/// Most bounds only order a pair that is split anyway (docs/kernel.md): a second exact direction (the line
/// through the extreme vertices found along c, tighter on about half the pairs) and fcl_rs::distance (all 18
/// slab directions of both volumes) both cost more CPU time than the BV and triangle tests they save.
/// moved2 = detail::MovedFrame(R, T, b2) (the overload below builds it; traversals move each node once).
template <typename S>
S distanceLowerBound(const detail::MovedFrame<S>& moved2, const RS<S>& b1, const RS<S>& b2,
                     S enough = std::numeric_limits<S>::max())
{
  if (b1.empty() || b2.empty()) return std::numeric_limits<S>::max();
  using V = fcl::Vector3<S>;
  const detail::PairFrame<S> f(moved2, b1);
  const fcl::Matrix3<S>& M = f.M;
  // Principal boxes: half extents, and the vector from b1's box centre to b2's in b1's frame (c) and b2's (c2).
  const V& h1 = f.box1.h;
  const V& h2 = f.box2.h;
  const V c = f.centre2 - f.box1.c;
  const V c2 = M.transpose() * c;
  const fcl::Matrix3<S> A = M.cwiseAbs();
  // Box gaps along b1's axes (b2's box reaches h2 . |row i of M| along axis i) and b2's axes.
  const V gaps1 = c.cwiseAbs() - h1 - A * h2;
  const V gaps2 = c2.cwiseAbs() - A.transpose() * h1 - h2;
  const S boxes = std::max(gaps1.maxCoeff(), gaps2.maxCoeff()) - f.tol;
  if (boxes >= enough) return boxes;
  const S squared_length = c.squaredNorm();
  if (!(squared_length > 0)) return std::max(boxes, S(0));
  // The polytopes, exactly, along c: b2's lowest point minus b1's highest, times |c|.
  const S along = c.dot(f.t()) - detail::SupportCorner<S>(b2, V(-c2)).max() - detail::SupportCorner<S>(b1, c).max();
  return std::max({boxes, along / std::sqrt(squared_length) - f.tol, S(0)});
}

/// distanceLowerBound for b2 mapped into b1's coordinates by x1 = R x2 + T.
template <typename S>
S distanceLowerBound(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2,
                     S enough = std::numeric_limits<S>::max())
{
  return distanceLowerBound(detail::MovedFrame<S>(R, T, b2), b1, b2, enough);
}

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

/// Runs the mesh-mesh distance traversal of node (preprocess, descent, postprocess), best first: the pair with
/// the smallest lower bound is split next (the larger node, as FCL's descent), both children bounded, and the
/// search ends when the smallest bound left cannot improve the result, so every pair split has a bound below the
/// final distance. FCL's ordered depth-first descent splits every pair whose bound is below the distance found
/// when it reaches it, which in the subtrees searched first is still far above the final distance
/// (fcl_rs_bench_distance: 1.0-1.5x the BV tests and 1.2-1.7x the triangle tests, docs/kernel.md). The nearer
/// child is split at once when no waiting pair is nearer, which spares most heap operations. A child pair of two
/// leaves is measured at once instead of bounded. As in collideTrees, a node of model2 has its frame moved into
/// model1's coordinates once per query, not once per bound.
template <typename S>
void distanceTrees(MeshDistanceTraversalNodeRS<S>& node)
{
  using Node = MeshDistanceTraversalNodeRS<S>;
  const fcl::BVHModel<RS<S>>& model1 = *node.model1;
  const fcl::BVHModel<RS<S>>& model2 = *node.model2;
  struct Pair
  {
    int b1, b2;
    S bound;
  };
  const fcl::Matrix3<S> R = node.tf.linear();
  const fcl::Vector3<S> T = node.tf.translation();
  detail::MovedFrames<S> moved(R, T, model2);
  // model2's vertices in model1's coordinates, each moved (as FCL's triangle distance moves them) when first used.
  using V = fcl::Vector3<S>;
  detail::PerQueryTable<V> moved_vertices(std::size_t(std::max(model2.num_vertices, 0)));
  const auto movedVertex = [&](int i) -> const V& {
    return moved_vertices.get(std::size_t(i), [&] { return V(node.tf * node.vertices2[i]); });
  };
  // A pair of leaves is bounded by its triangles' distance itself, which is exact and cheaper than an RS bound
  // (docs/kernel.md): it is measured at once, and the pair is never visited again. A gap along the line through
  // the triangles' centroids first skips pairs that cannot improve the result (15-52 % of them in
  // fcl_rs_bench_distance).
  const auto bound = [&](int b1, int b2) {
    if (!isLeaf(model1.getBV(b1)) || !isLeaf(model2.getBV(b2)))
      return node.Node::BVTesting(b1, b2, moved(b2));
    const int id1 = primitiveId(model1.getBV(b1)), id2 = primitiveId(model2.getBV(b2));
    const auto p_vertices = triangleVertices(node.vertices1, node.tri_indices1[id1]);
    const V* p = p_vertices.data();
    const std::array<std::size_t, 3> t2 = vertexIds(node.tri_indices2[id2]);
    const V q[3] = {movedVertex(int(t2[0])), movedVertex(int(t2[1])), movedVertex(int(t2[2]))};
    if (!leafCannotImprove(p, q, node.result->min_distance))
    {
      if (node.enable_statistics) node.num_leaf_tests++;
      V P, Q;
      const S d = fcl::detail::TriangleDistance<S>::triDistance(p, q, P, Q);
      if (node.request.enable_nearest_points)
        node.result->update(d, node.model1, node.model2, id1, id2, P, Q);
      else
        node.result->update(d, node.model1, node.model2, id1, id2);
    }
    return std::numeric_limits<S>::max();
  };
  // A min-heap on bound; ties pop in no particular order.
  std::vector<Pair> waiting;
  waiting.reserve(128);
  const auto farther = [](const Pair& x, const Pair& y) { return x.bound > y.bound; };
  const auto wait = [&](const Pair& p) {
    if (node.Node::canStop(p.bound)) return;
    waiting.push_back(p);
    std::push_heap(waiting.begin(), waiting.end(), farther);
  };
  node.Node::preprocess();
  Pair pair{0, 0, S(0)};
  for (;;)
  {
    const fcl::BVNode<RS<S>>& n1 = model1.getBV(pair.b1);
    const fcl::BVNode<RS<S>>& n2 = model2.getBV(pair.b2);
    const bool leaf1 = isLeaf(n1), leaf2 = isLeaf(n2);
    if (leaf1 && leaf2)
      node.Node::leafTesting(pair.b1, pair.b2);  // two single-triangle models
    else
    {
      Pair a{pair.b1, pair.b2, S(0)}, c = a;
      if (leaf2 || (!leaf1 && n1.bv.size() > n2.bv.size()))
      {
        a.b1 = leftChild(n1);
        c.b1 = rightChild(n1);
      }
      else
      {
        a.b2 = leftChild(n2);
        c.b2 = rightChild(n2);
      }
      a.bound = bound(a.b1, a.b2);
      c.bound = bound(c.b1, c.b2);
      if (c.bound < a.bound) std::swap(a, c);
      wait(c);
      if (!node.Node::canStop(a.bound) && (waiting.empty() || !(waiting.front().bound < a.bound)))
      {
        pair = a;
        continue;
      }
      wait(a);
    }
    // The nearest waiting pair; if it cannot improve the result, no pair left can.
    if (waiting.empty()) break;
    std::pop_heap(waiting.begin(), waiting.end(), farther);
    pair = waiting.back();
    waiting.pop_back();
    if (node.Node::canStop(pair.bound)) break;
  }
  node.Node::postprocess();
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

private:
  RS<S> bv_;
  detail::MovedFrame<S> moved_;  ///< bv_'s frame, moved once per query
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

private:
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
  if (model1.getModelType() != fcl::BVH_MODEL_TRIANGLES) return false;
  node.request = request;
  node.result = &result;
  node.model1 = &model1;
  node.tf1 = tf1;
  node.model2 = &model2;
  node.tf2 = tf2;
  node.nsolver = nsolver;
  node.vertices = model1.vertices;
  node.tri_indices = model1.tri_indices;
  node.rel_err = request.rel_err;
  node.abs_err = request.abs_err;
  node.bound.reset(new ShapeDistanceBound<S, Shape>(model2, tf1.inverse(Eigen::Isometry) * tf2));
  node.leaf.emplace(model2, tf1, tf2);
  return true;
}

}  // namespace fcl_rs

#endif
