// An octomap of a triangle mesh's surface: every cell the surface passes through marked occupied, as a depth
// sensor sweeping the whole surface would leave it. For tests, benchmarks and scenes against fcl::OcTree.
#ifndef FCL_RS_SURFACE_OCTREE_H
#define FCL_RS_SURFACE_OCTREE_H

#include <fcl/config.h>
#if FCL_HAVE_OCTOMAP

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <octomap/OcTree.h>

#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// Adds the surface of mesh (at pose, default the identity) to tree: points on each triangle at most half a cell
/// apart, each recorded as one occupied observation (octomap's updateNode), so that every cell the surface
/// crosses holds at least one point.
template <typename S>
void addSurface(octomap::OcTree& tree, const TriangleMesh<S>& mesh,
                const fcl::Transform3<S>& pose = fcl::Transform3<S>::Identity())
{
  const double step = tree.getResolution() / 2;
  for (const auto& t : mesh.triangles)
  {
    const Eigen::Vector3d a = (pose * mesh.vertices[t[0]]).template cast<double>();
    const Eigen::Vector3d b = (pose * mesh.vertices[t[1]]).template cast<double>();
    const Eigen::Vector3d c = (pose * mesh.vertices[t[2]]).template cast<double>();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, int(std::ceil(longest / step)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
      {
        const Eigen::Vector3d p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        tree.updateNode(octomap::point3d(float(p.x()), float(p.y()), float(p.z())), true);
      }
  }
}

/// An octomap of mesh's surface with cells of size `resolution`.
template <typename S>
std::shared_ptr<octomap::OcTree> surfaceOcTree(const TriangleMesh<S>& mesh, double resolution)
{
  if (!(resolution > 0)) throw std::invalid_argument("fcl_rs::surfaceOcTree: resolution must be positive");
  auto tree = std::make_shared<octomap::OcTree>(resolution);
  addSurface(*tree, mesh);
  return tree;
}

}  // namespace fcl_rs

#endif  // FCL_HAVE_OCTOMAP
#endif
