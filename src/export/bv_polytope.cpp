#include "fcl_rs/export/bv_polytope.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace fcl_rs {

namespace {

/// The box as a polytope: corner bit a set = +half extent along axis a; faces outward.
Polytope boxPolytope(const BoxCut& shape)
{
  Polytope box;
  for (int i = 0; i < 8; ++i)
  {
    Eigen::Vector3d p = shape.center;
    for (int a = 0; a < 3; ++a) p += ((i >> a) & 1 ? 1.0 : -1.0) * shape.half_extents[a] * shape.axes.col(a);
    box.vertices.push_back(p);
  }
  box.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  // The loops above are outward for a right-handed frame; a left-handed one mirrors them.
  if (shape.axes.determinant() < 0)
    for (auto& f : box.faces) std::reverse(f.begin(), f.end());
  return box;
}

/// poly cut by plane: faces clipped in turn (Sutherland-Hodgman), the cut closed by one new face. Vertices
/// within tol of the plane stay where they are; an edge crossing the plane gets one vertex, shared by both
/// of its faces.
Polytope clip(const Polytope& poly, const HalfSpace& plane, double tol)
{
  const double norm = plane.normal.norm();
  if (!(norm > 0)) return poly;
  std::vector<double> dist(poly.vertices.size());
  bool any_out = false, any_in = false;
  for (std::size_t v = 0; v < dist.size(); ++v)
  {
    dist[v] = (plane.normal.dot(poly.vertices[v]) - plane.offset) / norm;
    any_out |= dist[v] > tol;
    any_in |= dist[v] < -tol;
  }
  if (!any_out) return poly;
  if (!any_in) return {};

  Polytope out;
  std::vector<int> kept(poly.vertices.size(), -1);
  std::map<std::pair<int, int>, int> crossing;
  std::vector<int> on_plane;
  const auto keep = [&](int v) {
    if (kept[std::size_t(v)] < 0)
    {
      kept[std::size_t(v)] = int(out.vertices.size());
      out.vertices.push_back(poly.vertices[std::size_t(v)]);
      if (dist[std::size_t(v)] >= -tol) on_plane.push_back(kept[std::size_t(v)]);
    }
    return kept[std::size_t(v)];
  };
  const auto cross = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = crossing.find(key);
    if (it != crossing.end()) return it->second;
    const double da = dist[std::size_t(key.first)], db = dist[std::size_t(key.second)];
    const Eigen::Vector3d& pa = poly.vertices[std::size_t(key.first)];
    const Eigen::Vector3d& pb = poly.vertices[std::size_t(key.second)];
    const int id = int(out.vertices.size());
    out.vertices.push_back(pa + (da / (da - db)) * (pb - pa));
    on_plane.push_back(id);
    crossing.emplace(key, id);
    return id;
  };
  for (const auto& face : poly.faces)
  {
    std::vector<int> loop;
    for (std::size_t i = 0; i < face.size(); ++i)
    {
      const int a = face[i], b = face[(i + 1) % face.size()];
      const double da = dist[std::size_t(a)], db = dist[std::size_t(b)];
      if (da <= tol) loop.push_back(keep(a));
      // A strict crossing only: an endpoint on the plane is the crossing already.
      if ((da < -tol && db > tol) || (da > tol && db < -tol)) loop.push_back(cross(a, b));
    }
    if (loop.size() >= 3) out.faces.push_back(std::move(loop));
  }

  // The cap: the on-plane vertices in counter-clockwise order about the outward normal.
  const Eigen::Vector3d n = plane.normal / norm;
  if (on_plane.size() >= 3)
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : on_plane) centroid += out.vertices[std::size_t(v)];
    centroid /= double(on_plane.size());
    const Eigen::Vector3d e0 = n.unitOrthogonal(), e1 = n.cross(e0);
    std::vector<std::pair<double, int>> by_angle;
    for (int v : on_plane)
    {
      const Eigen::Vector3d d = out.vertices[std::size_t(v)] - centroid;
      by_angle.emplace_back(std::atan2(d.dot(e1), d.dot(e0)), v);
    }
    std::sort(by_angle.begin(), by_angle.end());
    std::vector<int> cap;
    for (const auto& av : by_angle) cap.push_back(av.second);
    out.faces.push_back(std::move(cap));
  }
  return out;
}

}  // namespace

Polytope intersectHalfSpaces(const BoxCut& shape)
{
  Polytope poly = boxPolytope(shape);
  const double tol = 1e-12 * std::max(shape.half_extents.maxCoeff(), shape.center.lpNorm<Eigen::Infinity>());
  for (const HalfSpace& h : shape.cuts)
  {
    poly = clip(poly, h, tol);
    if (poly.empty()) break;
  }
  return poly;
}

double Polytope::volume() const
{
  if (faces.empty()) return 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& v : vertices) c += v;
  c /= double(vertices.size());
  double six_volume = 0;
  for (const auto& f : faces)
    for (std::size_t i = 1; i + 1 < f.size(); ++i)
    {
      const Eigen::Vector3d a = vertices[std::size_t(f[0])] - c, b = vertices[std::size_t(f[i])] - c,
                            d = vertices[std::size_t(f[i + 1])] - c;
      six_volume += a.dot(b.cross(d));
    }
  return six_volume / 6;
}

TriangleMesh<double> Polytope::triangles() const
{
  TriangleMesh<double> mesh;
  mesh.vertices = vertices;
  for (const auto& f : faces)
    for (std::size_t i = 1; i + 1 < f.size(); ++i)
      mesh.triangles.emplace_back(std::size_t(f[0]), std::size_t(f[i]), std::size_t(f[i + 1]));
  return mesh;
}

const std::vector<Eigen::Vector3d>& roundDirections()
{
  static const std::vector<Eigen::Vector3d> directions = [] {
    std::vector<Eigen::Vector3d> d;
    const double golden_angle = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < kRoundDirections; ++i)
    {
      const double z = 1 - (2 * i + 1) / double(kRoundDirections), r = std::sqrt(1 - z * z);
      d.emplace_back(r * std::cos(golden_angle * i), r * std::sin(golden_angle * i), z);
    }
    return d;
  }();
  return directions;
}

}  // namespace fcl_rs
