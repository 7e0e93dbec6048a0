// CGAL's Epeck decides every predicate and distance exactly; degenerate triangles are reduced to the segment
// or point they are, since CGAL's Triangle_3 must have area.
#include "exact_oracle.h"

#include <algorithm>
#include <cmath>
#include <variant>

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

Exact toExact(const ExactTriangle& t)
{
  Exact e{{Point(t[0].x(), t[0].y(), t[0].z()), Point(t[1].x(), t[1].y(), t[1].z()), Point(t[2].x(), t[2].y(), t[2].z())},
          Point()};
  if (!CGAL::collinear(e.v[0], e.v[1], e.v[2]))
    e.shape = Triangle(e.v[0], e.v[1], e.v[2]);
  else
  {
    // Collinear: the segment between the lexicographically smallest and largest vertex (a point if equal).
    const Point lo = std::min({e.v[0], e.v[1], e.v[2]}), hi = std::max({e.v[0], e.v[1], e.v[2]});
    e.shape = lo == hi ? Primitive(lo) : Primitive(Segment(lo, hi));
  }
  return e;
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

}  // namespace

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
