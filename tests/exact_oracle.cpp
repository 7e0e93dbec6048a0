// CGAL's Epeck decides every predicate and distance exactly; degenerate triangles are reduced to the segment
// or point they are, since CGAL's Triangle_3 must have area.
#include "exact_oracle.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include <CGAL/Tetrahedron_3.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

namespace fcl_rs {
namespace test {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;
using Segment = K::Segment_3;
using Triangle = K::Triangle_3;
using Primitive = std::variant<Point, Segment, Triangle>;

struct Exact
{
  std::array<Point, 3> v;
  Primitive shape;
};

Exact fromPoints(const Point& x, const Point& y, const Point& z)
{
  Exact e{{x, y, z}, Point()};
  if (!CGAL::collinear(x, y, z))
    e.shape = Triangle(x, y, z);
  else
  {
    // Collinear: the segment between the lexicographically smallest and largest vertex (a point if equal).
    const Point lo = std::min({x, y, z}), hi = std::max({x, y, z});
    e.shape = lo == hi ? Primitive(lo) : Primitive(Segment(lo, hi));
  }
  return e;
}

Exact toExact(const ExactTriangle& t)
{
  return fromPoints(Point(t[0].x(), t[0].y(), t[0].z()), Point(t[1].x(), t[1].y(), t[1].z()),
                    Point(t[2].x(), t[2].y(), t[2].z()));
}

bool meet(const Point& a, const Point& b) { return a == b; }
template <typename X, typename Y>
bool meet(const X& a, const Y& b)
{
  return CGAL::do_intersect(a, b);
}

/// Squared distance of a point to a primitive.
K::FT pointDistance(const Point& x, const Primitive& p)
{
  return std::visit([&](const auto& s) { return CGAL::squared_distance(x, s); }, p);
}

/// Squared distance between two possibly degenerate segments.
K::FT edgeDistance(const Point& a0, const Point& a1, const Point& b0, const Point& b1)
{
  if (a0 == a1) return b0 == b1 ? CGAL::squared_distance(a0, b0) : CGAL::squared_distance(a0, Segment(b0, b1));
  if (b0 == b1) return CGAL::squared_distance(b0, Segment(a0, a1));
  return CGAL::squared_distance(Segment(a0, a1), Segment(b0, b1));
}

/// Squared distance between two closed primitives (apart or not: 0 when they meet).
K::FT primitiveDistance(const Exact& a, const Exact& b)
{
  if (std::visit([](const auto& x, const auto& y) { return meet(x, y); }, a.shape, b.shape)) return 0;
  K::FT best = pointDistance(a.v[0], b.shape);
  for (int i = 0; i < 3; ++i)
  {
    best = std::min(best, pointDistance(a.v[i], b.shape));
    best = std::min(best, pointDistance(b.v[i], a.shape));
    for (int j = 0; j < 3; ++j)
      best = std::min(best, edgeDistance(a.v[i], a.v[(i + 1) % 3], b.v[j], b.v[(j + 1) % 3]));
  }
  return best;
}

/// R y + t, exactly.
Point place(const ExactPose& pose, const Eigen::Vector3d& y)
{
  K::FT c[3];
  for (int r = 0; r < 3; ++r)
    c[r] = K::FT(pose.R(r, 0)) * y.x() + K::FT(pose.R(r, 1)) * y.y() + K::FT(pose.R(r, 2)) * y.z() + pose.t[r];
  return Point(c[0], c[1], c[2]);
}

/// A point's distance to a radius-inflated primitive from the exact squared distance sq.
ExactShapeAnswer inflated(const K::FT& sq, double radius)
{
  if (sq <= K::FT(radius) * K::FT(radius)) return {true, 0};
  return {false, std::sqrt(CGAL::to_double(sq)) - radius};
}

/// Height of x above the plane n . y = d of the shape's frame, times |n| (y = R^-1 (x - t), exactly).
K::FT scaledHeight(const Point& x, const ExactPose& pose, const Eigen::Vector3d& n, double d)
{
  K::FT R[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R[r][c] = pose.R(r, c);
  const K::FT det = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) - R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
                    R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
  // adj(R)[i][j] = cofactor(j, i).
  const auto cofactor = [&](int r, int c) {
    const int r0 = (r + 1) % 3, r1 = (r + 2) % 3, c0 = (c + 1) % 3, c1 = (c + 2) % 3;
    return R[r0][c0] * R[r1][c1] - R[r0][c1] * R[r1][c0];
  };
  const K::FT v[3] = {x.x() - pose.t.x(), x.y() - pose.t.y(), x.z() - pose.t.z()};
  K::FT h = 0;
  for (int i = 0; i < 3; ++i)
  {
    K::FT yi = 0;
    for (int j = 0; j < 3; ++j) yi += cofactor(j, i) * v[j];
    h += K::FT(n[i]) * (yi / det);
  }
  return h - d;
}

double planeDistance(const K::FT& h, const Eigen::Vector3d& n)
{
  return CGAL::to_double(CGAL::abs(h)) / n.norm();
}

}  // namespace

ExactShapeAnswer exactSphere(const ExactTriangle& a, const ExactPose& pose, double radius)
{
  return inflated(pointDistance(place(pose, Eigen::Vector3d::Zero()), toExact(a).shape), radius);
}

ExactShapeAnswer exactCapsule(const ExactTriangle& a, const ExactPose& pose, double radius, double half_length)
{
  const Point p0 = place(pose, Eigen::Vector3d(0, 0, -half_length)), p1 = place(pose, Eigen::Vector3d(0, 0, half_length));
  const Exact segment = fromPoints(p0, p1, p1);
  return inflated(primitiveDistance(toExact(a), segment), radius);
}

ExactShapeAnswer exactPolytope(const ExactTriangle& a, const ExactPose& pose, const std::vector<Eigen::Vector3d>& vertices,
                               const std::vector<std::array<int, 3>>& boundary)
{
  std::vector<Point> world;
  K::FT mx = 0, my = 0, mz = 0;
  for (const auto& v : vertices)
  {
    world.push_back(place(pose, v));
    mx += world.back().x(), my += world.back().y(), mz += world.back().z();
  }
  const K::FT count(static_cast<double>(world.size()));
  const Point mean(mx / count, my / count, mz / count);
  const Exact tri = toExact(a);
  K::FT best = -1;
  for (const auto& f : boundary)
  {
    const Point &x = world[std::size_t(f[0])], &y = world[std::size_t(f[1])], &z = world[std::size_t(f[2])];
    if (!CGAL::coplanar(mean, x, y, z))
    {
      const K::Tetrahedron_3 piece(mean, x, y, z);
      if (std::visit([&](const auto& s) { return CGAL::do_intersect(s, piece); }, tri.shape)) return {true, 0};
    }
    const K::FT sq = primitiveDistance(tri, fromPoints(x, y, z));
    if (best < 0 || sq < best) best = sq;
  }
  if (best <= 0) return {true, 0};
  return {false, std::sqrt(CGAL::to_double(best))};
}

ExactShapeAnswer exactPlane(const ExactTriangle& a, const ExactPose& pose, const Eigen::Vector3d& n, double d)
{
  const Exact tri = toExact(a);
  K::FT lo = scaledHeight(tri.v[0], pose, n, d), hi = lo;
  for (int i = 1; i < 3; ++i)
  {
    const K::FT h = scaledHeight(tri.v[i], pose, n, d);
    lo = std::min(lo, h), hi = std::max(hi, h);
  }
  if (lo <= 0 && hi >= 0) return {true, 0};
  return {false, planeDistance(lo > 0 ? lo : hi, n)};
}

ExactShapeAnswer exactHalfspace(const ExactTriangle& a, const ExactPose& pose, const Eigen::Vector3d& n, double d)
{
  const Exact tri = toExact(a);
  K::FT lo = scaledHeight(tri.v[0], pose, n, d);
  for (int i = 1; i < 3; ++i) lo = std::min(lo, scaledHeight(tri.v[i], pose, n, d));
  if (lo <= 0) return {true, 0};
  return {false, planeDistance(lo, n)};
}

bool exactlyIntersect(const ExactTriangle& a, const ExactTriangle& b)
{
  const Exact ea = toExact(a), eb = toExact(b);
  return std::visit([](const auto& x, const auto& y) { return meet(x, y); }, ea.shape, eb.shape);
}

double exactDistance(const ExactTriangle& a, const ExactTriangle& b)
{
  if (exactlyIntersect(a, b)) return 0;
  // Apart: the distance is realized edge to edge or vertex to the other's closed primitive.
  const Exact ea = toExact(a), eb = toExact(b);
  K::FT best = pointDistance(ea.v[0], eb.shape);
  for (int i = 0; i < 3; ++i)
  {
    best = std::min(best, pointDistance(ea.v[i], eb.shape));
    best = std::min(best, pointDistance(eb.v[i], ea.shape));
    for (int j = 0; j < 3; ++j)
      best = std::min(best, edgeDistance(ea.v[i], ea.v[(i + 1) % 3], eb.v[j], eb.v[(j + 1) % 3]));
  }
  return std::sqrt(CGAL::to_double(best));
}

}  // namespace test
}  // namespace fcl_rs
