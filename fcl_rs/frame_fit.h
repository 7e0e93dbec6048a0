// Frame fits for RS tree nodes (vertex PCA, area-weighted triangle PCA, convex-hull surface PCA) and refitting a tree with one.
#ifndef FCL_RS_FRAME_FIT_H
#define FCL_RS_FRAME_FIT_H

#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/pca.h"
#include "fcl_rs/rs.h"

namespace fcl_rs {

/// How the principal frame of an RS node is fitted to the node's triangles. Whatever the frame, the
/// nine slabs are then fitted to every vertex, so each node contains its triangles.
enum class FrameFit
{
  kVertices,      ///< PCA of the vertices, three per triangle (the paper; what BVHModel::endModel builds)
  kTriangleArea,  ///< PCA of the triangles' surfaces weighted by area (independent of the tessellation)
  kConvexHull,    ///< PCA of the surface of the triangles' convex hull, weighted by area (Gottschalk's fit)
};

/// "vertices", "area" or "hull".
inline const char* frameFitName(FrameFit fit)
{
  switch (fit)
  {
    case FrameFit::kVertices: return "vertices";
    case FrameFit::kTriangleArea: return "area";
    case FrameFit::kConvexHull: return "hull";
  }
  return "unknown";
}

/// Convex hull of a point set, computed by qhull in double precision.
struct ConvexHull
{
  /// The hull's vertices (input points, unchanged). For a hull that is not solid (fewer than four
  /// points, or all of them coplanar up to qhull's precision): every distinct input point.
  std::vector<Eigen::Vector3d> vertices;
  /// Boundary triangles, as indices into vertices; empty when the hull is not solid.
  std::vector<std::array<int, 3>> triangles;
  double volume = 0;

  bool solid() const { return !triangles.empty(); }
};

/// Convex hull of points. Throws std::domain_error when a point is not finite.
ConvexHull convexHull(std::vector<Eigen::Vector3d> points);

/// Principal frame of the surface of n triangles, corner c of triangle i given by corner_at(i, c): each
/// triangle weighs by its area, spread evenly over it, so the frame does not depend on how a surface is
/// cut into triangles. Covariance about the area centroid, in two passes (as principalFrame). Triangles
/// of zero area weigh nothing; when all do, the frame of the corners (principalFrame).
template <typename S, typename CornerAt>
PrincipalFrame<S> areaWeightedFrame(int n, CornerAt corner_at)
{
  if (n <= 0) throw std::invalid_argument("fcl_rs::areaWeightedFrame: no triangles to fit");
  const auto corner = [&](int i, int c) -> Eigen::Vector3d { return corner_at(i, c).template cast<double>(); };
  double area = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = corner(i, 0), q = corner(i, 1), r = corner(i, 2);
    const double a = (q - p).cross(r - p).norm() / 2;
    area += a;
    mean += a * (p + q + r) / 3;
  }
  if (!(area > 0)) return principalFrame<S>(3 * n, [&](int k) { return corner_at(k / 3, k % 3); });
  mean /= area;

  // A triangle (p, q, r) of area a and centroid m has second moment a/12 (9 m m^T + p p^T + q q^T + r r^T).
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = corner(i, 0) - mean, q = corner(i, 1) - mean, r = corner(i, 2) - mean;
    const Eigen::Vector3d m = (p + q + r) / 3;
    const double a = (q - p).cross(r - p).norm() / 2;
    C.noalias() += (a / 12) * (9 * m * m.transpose() + p * p.transpose() + q * q.transpose() + r * r.transpose());
  }
  return principalFrameOfCovariance<S>(C / area, mean);
}

/// Principal frame of a solid hull's surface (areaWeightedFrame of its triangles).
template <typename S>
PrincipalFrame<S> hullSurfaceFrame(const ConvexHull& hull)
{
  if (!hull.solid()) throw std::invalid_argument("fcl_rs::hullSurfaceFrame: the hull is not solid");
  return areaWeightedFrame<S>(int(hull.triangles.size()), [&](int i, int c) -> const Eigen::Vector3d& {
    return hull.vertices[std::size_t(hull.triangles[std::size_t(i)][std::size_t(c)])];
  });
}

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
    if (node.isLeaf()) order.at(std::size_t(node.first_primitive)) = node.primitiveId();
  }
  return order;
}

/// Calls visit(k, hull) for every node k of a built triangle-mesh tree with the convex hull of the
/// vertices of its triangles (both vertex arrays after a motion update), children before parents. A
/// parent's hull is computed from its children's hull vertices only.
template <typename BV, typename Visit>
void forEachNodeHull(const fcl::BVHModel<BV>& model, Visit visit)
{
  detail::requireBuiltTriangleTree(model);
  const int num_nodes = model.getNumBVs();
  std::vector<std::vector<Eigen::Vector3d>> pending(static_cast<std::size_t>(num_nodes));
  // FCL numbers children after their parent, so a backward pass sees children first.
  for (int k = num_nodes - 1; k >= 0; --k)
  {
    const auto& node = model.getBV(k);
    std::vector<Eigen::Vector3d> points;
    if (node.isLeaf())
    {
      const fcl::Triangle& t = model.tri_indices[node.primitiveId()];
      for (const auto* v : {model.vertices, model.prev_vertices})
        if (v)
          for (int c = 0; c < 3; ++c) points.push_back(v[t[c]].template cast<double>());
    }
    else
    {
      const int l = node.leftChild(), r = node.rightChild();
      if (l <= k || r <= k) throw std::logic_error("fcl_rs::forEachNodeHull: a child precedes its parent");
      points = std::move(pending[std::size_t(l)]);
      points.insert(points.end(), pending[std::size_t(r)].begin(), pending[std::size_t(r)].end());
      pending[std::size_t(l)] = {};
      pending[std::size_t(r)] = {};
    }
    ConvexHull hull = convexHull(std::move(points));
    visit(k, hull);
    pending[std::size_t(k)] = std::move(hull.vertices);
  }
}

/// Principal frame of n triangles (corner c of triangle i given by corner_at(i, c)) by the chosen fit.
/// kConvexHull uses `hull` when given (it must be the hull of the corners) and computes it otherwise;
/// where the hull is not solid (a single triangle, a flat patch) it takes the area-weighted frame.
template <typename S, typename CornerAt>
PrincipalFrame<S> triangleFrame(int n, CornerAt corner_at, FrameFit fit, const ConvexHull* hull = nullptr)
{
  switch (fit)
  {
    case FrameFit::kVertices:
      return principalFrame<S>(3 * n, [&](int k) { return corner_at(k / 3, k % 3); });
    case FrameFit::kConvexHull:
    {
      ConvexHull own;
      if (!hull)
      {
        std::vector<Eigen::Vector3d> points;
        for (int i = 0; i < n; ++i)
          for (int c = 0; c < 3; ++c) points.push_back(corner_at(i, c).template cast<double>());
        own = convexHull(std::move(points));
        hull = &own;
      }
      if (hull->solid()) return hullSurfaceFrame<S>(*hull);
      return areaWeightedFrame<S>(n, corner_at);
    }
    case FrameFit::kTriangleArea:
      break;
  }
  return areaWeightedFrame<S>(n, corner_at);
}

/// RS of n triangles in the frame the chosen fit gives (see triangleFrame); contains every corner.
/// kVertices is fitPoints of the corners, exactly as the tree builder fits a node.
template <typename S, typename CornerAt>
RS<S> fitTriangles(int n, CornerAt corner_at, FrameFit fit, const ConvexHull* hull = nullptr)
{
  if (fit == FrameFit::kVertices) return fitPoints<S>(3 * n, [&](int k) { return corner_at(k / 3, k % 3); });
  const PrincipalFrame<S> frame = triangleFrame<S>(n, corner_at, fit, hull);
  RS<S> bv(frame.axis, frame.mean);
  bv.expandPoints(3 * n, [&](int k) { return corner_at(k / 3, k % 3); });
  return bv;
}

/// Replaces the RS of every node of a built tree by fitTriangles of the node's own triangles (of both
/// vertex arrays after a motion update, as FCL's own fits); the tree's shape is kept, and every node
/// contains every vertex of its triangles. kVertices gives the frames BVHModel::endModel fits (up to rounding).
/// Throws std::invalid_argument unless model is a built triangle mesh.
template <typename S>
void refitFrames(fcl::BVHModel<RS<S>>& model, FrameFit fit)
{
  const std::vector<int> order = primitiveOrder(model);
  std::vector<const fcl::Vector3<S>*> corners;
  const auto fitNode = [&](int k, const ConvexHull* hull) {
    auto& node = model.getBV(k);
    corners.clear();
    for (const auto* v : {model.vertices, model.prev_vertices})
      if (v)
        for (int i = node.first_primitive; i < node.first_primitive + node.num_primitives; ++i)
        {
          const fcl::Triangle& t = model.tri_indices[order[std::size_t(i)]];
          for (int c = 0; c < 3; ++c) corners.push_back(&v[t[c]]);
        }
    node.bv = fitTriangles<S>(
        int(corners.size() / 3),
        [&](int i, int c) -> const fcl::Vector3<S>& { return *corners[std::size_t(3 * i + c)]; }, fit, hull);
  };
  if (fit == FrameFit::kConvexHull)
    forEachNodeHull(model, [&](int k, const ConvexHull& hull) { fitNode(k, &hull); });
  else
    for (int k = 0; k < model.getNumBVs(); ++k) fitNode(k, nullptr);
}

}  // namespace fcl_rs

#endif
