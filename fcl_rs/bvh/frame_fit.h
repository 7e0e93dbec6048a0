// Frame fits for RS tree nodes (vertex PCA, area-weighted triangle PCA, convex-hull surface PCA) and refitting a
// tree with one. kConvexHull needs qhull: link fcl_rs::hull.
#ifndef FCL_RS_BVH_FRAME_FIT_H
#define FCL_RS_BVH_FRAME_FIT_H

#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bv/pca.h"
#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/convex_hull.h"

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
