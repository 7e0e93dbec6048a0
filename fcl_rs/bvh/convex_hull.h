// Convex hulls (qhull) of point sets and of every node of a built tree. Library fcl_rs::hull.
#ifndef FCL_RS_BVH_CONVEX_HULL_H
#define FCL_RS_BVH_CONVEX_HULL_H

#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/bvh/primitive_order.h"

namespace fcl_rs {

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
    if (isLeaf(node))
    {
      const fcl::Triangle& t = model.tri_indices[primitiveId(node)];
      for (const auto* v : {model.vertices, model.prev_vertices})
        if (v)
          for (int c = 0; c < 3; ++c) points.push_back(v[t[c]].template cast<double>());
    }
    else
    {
      const int l = leftChild(node), r = rightChild(node);
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

}  // namespace fcl_rs

#endif
