// The exact solid of one bounding volume of any type, as a convex polytope (for export and pictures).
#ifndef FCL_RS_EXPORT_BV_POLYTOPE_H
#define FCL_RS_EXPORT_BV_POLYTOPE_H

#include <cstddef>
#include <vector>

#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// The closed half-space normal . x <= offset (model coordinates; normal need not be unit).
struct HalfSpace
{
  Eigen::Vector3d normal;
  double offset;
};

/// A convex polytope: vertices and planar faces, each face a vertex loop counter-clockwise seen from outside.
struct Polytope
{
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> faces;

  bool empty() const { return faces.empty(); }
  /// Enclosed volume (divergence theorem over the faces).
  double volume() const;
  /// The faces fanned into triangles, outward-facing.
  TriangleMesh<double> triangles() const;
};

/// A box (centre, axes as columns, orthonormal but for RS's stored frame, half extents >= 0) cut by half-spaces: the volume of
/// every BV type is one, so one clipper (intersectHalfSpaces) builds them all.
struct BoxCut
{
  Eigen::Vector3d center;
  Eigen::Matrix3d axes;
  Eigen::Vector3d half_extents;
  std::vector<HalfSpace> cuts;
};

/// The box of `shape` clipped by each of its cuts in turn (a plane through a vertex, within a relative
/// 1e-12 of the box size, keeps it rather than splitting it). Empty when the cuts leave nothing.
Polytope intersectHalfSpaces(const BoxCut& shape);

/// The directions the round volumes (RSS, kIOS) are cut by: kRoundDirections points of a Fibonacci spiral.
/// The intersection of a ball's tangent half-spaces at them contains the ball and reaches at most
/// kRoundOvershoot times its radius from its centre; for a swept rectangle (RSS) the tangent planes near
/// the rectangle's corners leave more, at most kSweptOvershoot times the radius from the rectangle
/// (both checked in tests/test_export.cpp).
inline constexpr int kRoundDirections = 240;
inline constexpr double kRoundOvershoot = 1.02;
inline constexpr double kSweptOvershoot = 1.15;
const std::vector<Eigen::Vector3d>& roundDirections();

/// The shape of each BV type as a box with cuts, in double precision from the volume's own numbers:
/// RS: its principal box cut by the six diagonal slab pairs (the 18-DOP with its 12 edges cut off, exact).
template <typename S>
BoxCut boxCut(const RS<S>& bv)
{
  // The volume is {x : lo <= d_k . A^T (x - origin) <= hi} for the stored frame A, orthonormal only up to its
  // storage: the slabs' normals are A d_k, and frame coordinates y are at x = origin + A^-T y.
  const Eigen::Matrix3d axis = bv.axis.template cast<double>();
  const Eigen::Vector3d origin = bv.origin.template cast<double>();
  BoxCut shape;
  shape.axes = axis.inverse().transpose();
  Eigen::Vector3d mid;
  for (int a = 0; a < 3; ++a)
  {
    mid[a] = (double(bv.lo[a]) + double(bv.hi[a])) / 2;
    shape.half_extents[a] = std::max(0.0, (double(bv.hi[a]) - double(bv.lo[a])) / 2);
  }
  shape.center = shape.axes * mid + origin;
  for (int k = 3; k < kNumSlabs; ++k)
  {
    const Eigen::Vector3d n = detail::slabOfColumns<double>(axis, k);  // slab k's normal, model coordinates
    shape.cuts.push_back({n, double(bv.hi[k]) + n.dot(origin)});
    shape.cuts.push_back({-n, -double(bv.lo[k]) - n.dot(origin)});
  }
  return shape;
}

/// OBB: the box itself.
template <typename S>
BoxCut boxCut(const fcl::OBB<S>& bv)
{
  return {bv.To.template cast<double>(), bv.axis.template cast<double>(), bv.extent.template cast<double>(), {}};
}

/// OBBRSS: its OBB (the tighter of its two volumes on most nodes; FCL tests the OBB for overlap).
template <typename S>
BoxCut boxCut(const fcl::OBBRSS<S>& bv)
{
  return boxCut(bv.obb);
}

/// AABB: the box itself.
template <typename S>
BoxCut boxCut(const fcl::AABB<S>& bv)
{
  return {bv.center().template cast<double>(), Eigen::Matrix3d::Identity(),
          ((bv.max_ - bv.min_) / 2).template cast<double>(), {}};
}

/// k-DOP: its axis-aligned slabs as the box, cut by the (N - 6) / 2 diagonal slab pairs in FCL's order
/// (x+y, x+z, y+z, x-y, x-z, y-z, x+y-z, x+z-y, y+z-x); FCL's diagonal distances are unnormalised.
template <typename S, std::size_t N>
BoxCut boxCut(const fcl::KDOP<S, N>& bv)
{
  static const double kDiagonals[9][3] = {{1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, -1, 0},  {1, 0, -1},
                                          {0, 1, -1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  BoxCut shape;
  shape.axes.setIdentity();
  for (int a = 0; a < 3; ++a)
  {
    shape.center[a] = (double(bv.dist(std::size_t(a))) + double(bv.dist(N / 2 + std::size_t(a)))) / 2;
    shape.half_extents[a] = std::max(0.0, (double(bv.dist(N / 2 + std::size_t(a))) - double(bv.dist(std::size_t(a)))) / 2);
  }
  for (std::size_t k = 0; k < (N - 6) / 2; ++k)
  {
    const Eigen::Vector3d n(kDiagonals[k][0], kDiagonals[k][1], kDiagonals[k][2]);
    shape.cuts.push_back({n, double(bv.dist(N / 2 + 3 + k))});
    shape.cuts.push_back({-n, -double(bv.dist(3 + k))});
  }
  return shape;
}

/// RSS (the rectangle swept by a ball): its bounding box cut by the volume's tangent planes at
/// roundDirections(), so the polytope circumscribes the swept rectangle (contains it, overshooting
/// by at most kSweptOvershoot - 1 of the radius, near the rectangle's corners).
template <typename S>
BoxCut boxCut(const fcl::RSS<S>& bv)
{
  const Eigen::Matrix3d axis = bv.axis.template cast<double>();
  const Eigen::Vector3d to = bv.To.template cast<double>();
  const double l0 = double(bv.l[0]), l1 = double(bv.l[1]), r = double(bv.r);
  BoxCut shape{axis * Eigen::Vector3d(l0 / 2, l1 / 2, 0) + to, axis, Eigen::Vector3d(l0 / 2 + r, l1 / 2 + r, r), {}};
  for (const Eigen::Vector3d& u : roundDirections())
  {
    const Eigen::Vector3d n = axis * u;  // support of the rectangle along n, plus the radius
    const double support = std::max(0.0, u[0] * l0) + std::max(0.0, u[1] * l1) + n.dot(to);
    shape.cuts.push_back({n, support + r});
  }
  return shape;
}

/// kIOS: its OBB cut by the tangent planes of each of its spheres at roundDirections() (FCL's overlap
/// test needs both the OBB and every sphere to overlap, so the volume is their intersection); circumscribed.
template <typename S>
BoxCut boxCut(const fcl::kIOS<S>& bv)
{
  BoxCut shape = boxCut(bv.obb);
  for (unsigned int i = 0; i < bv.num_spheres; ++i)
  {
    const Eigen::Vector3d o = bv.spheres[i].o.template cast<double>();
    for (const Eigen::Vector3d& n : roundDirections()) shape.cuts.push_back({n, n.dot(o) + double(bv.spheres[i].r)});
  }
  return shape;
}

/// The exact solid of bv (circumscribed for RSS and kIOS, see their boxCut), in double precision.
template <typename BV>
Polytope bvPolytope(const BV& bv)
{
  return intersectHalfSpaces(boxCut(bv));
}

}  // namespace fcl_rs

#endif
