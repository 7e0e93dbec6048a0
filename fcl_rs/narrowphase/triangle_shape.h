// Triangle-primitive leaf tests of RS mesh-shape queries: one implementation serves distance and collision.
//
// Every test runs in the shape's own frame, in double (float inputs are widened), on the triangle moved there by
// X = tf_shape^-1 tf_mesh. Sphere, capsule, box, convex, plane and halfspace are closed form: the distance is the
// exact distance of the moved triangle to the shape, to rounding (point-triangle, segment-triangle,
// segment-segment, segment-box and triangle-triangle distances over the features that can hold the closest pair).
// Cylinder, cone and ellipsoid have no closed form: GJK on their exact support functions (not FCL's, which adds
// margins and tolerances), stopped when its certified lower bound is within kIterativeRelativeGap of the distance
// it has reached (docs/distance.md); the cylinder's collision verdict is closed form wherever that settles it.
//
// Collision verdict: the pair is reported iff the computed distance of the moved triangle to the shape is at most
// leafTolerance (triangle_intersection.h) of the triangle's and the shape's largest coordinates and the poses, the
// contract of the mesh-mesh leaf test: a triangle that touches the shape exactly (in the world frame, as computed)
// is always reported. The iterative shapes report a pair unless GJK certifies it farther apart than that.
#ifndef FCL_RS_NARROWPHASE_TRIANGLE_SHAPE_H
#define FCL_RS_NARROWPHASE_TRIANGLE_SHAPE_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/utility.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>

#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/detail/relative_poses.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"

namespace fcl_rs {
namespace triangle_shape {

using Vec = Eigen::Vector3d;

/// GJK (cylinder, cone, ellipsoid) stops once its lower bound on the distance is within this fraction of the
/// distance it has reached; the reported distance is the reached one (an upper bound), at most this much too large.
constexpr double kIterativeRelativeGap = 1e-12;
/// ... or after this many support points (none of the tests comes near it).
constexpr int kIterativeMaxSteps = 200;

/// A pair of closest points (a on the triangle, b on the shape) and their distance.
struct Closest
{
  double distance = std::numeric_limits<double>::infinity();
  Vec on_triangle = Vec::Zero();
  Vec on_shape = Vec::Zero();
  void keep(double d, const Vec& a, const Vec& b)
  {
    if (d < distance) *this = Closest{d, a, b};
  }
};

/// The closest point of segment [a, b] to x, as the weight t of b.
inline double segmentWeight(const Vec& a, const Vec& b, const Vec& x)
{
  const Vec ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return 0;
  return std::clamp(ab.dot(x - a) / len2, 0.0, 1.0);
}

/// The closest point of triangle t to x, with its barycentric weights w: Ericson's region walk, then the three
/// edges. The walk decides its region by signs of products that cancel for a nearly degenerate triangle (vc, vb,
/// va), so it can pick the face of a sliver whose closest point is on an edge; its point is still a point of the
/// triangle (weights clamped to [0, 1]), never nearer than the true one, and the edges' closest points (clamped
/// projections, accurate to rounding for any shape) correct it. A triangle without area has only its edges.
inline Vec closestOnTriangle(const Vec t[3], const Vec& x, double w[3])
{
  Vec point = t[0];
  w[0] = 1, w[1] = w[2] = 0;
  const auto set = [&](double w0, double w1, double w2) {
    w[0] = w0, w[1] = w1, w[2] = w2;
    point = w0 * t[0] + w1 * t[1] + w2 * t[2];
  };
  const auto walk = [&]() {
    const Vec ab = t[1] - t[0], ac = t[2] - t[0], ap = x - t[0];
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return set(1, 0, 0);
    const Vec bp = x - t[1];
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return set(0, 1, 0);
    const double vc = d1 * d4 - d3 * d2;
    // Each edge region's denominator is its edge's squared length (here d1 - d3 = |ab|^2): zero for an edge
    // whose ends coincide, which has no region of its own (0 / 0); the walk goes on.
    if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0)
    {
      const double v = d1 / (d1 - d3);
      return set(1 - v, v, 0);
    }
    const Vec cp = x - t[2];
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return set(0, 0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0)
    {
      const double v = d2 / (d2 - d6);
      return set(1 - v, 0, v);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0)
    {
      const double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      return set(0, 1 - v, v);
    }
    const double a = std::max(va, 0.0), b = std::max(vb, 0.0), c = std::max(vc, 0.0), area = a + b + c;
    if (area > 0 && std::isfinite(area)) set(a / area, b / area, c / area);
  };
  walk();
  double best = (point - x).squaredNorm();
  for (int i = 0; i < 3; ++i)
  {
    const int j = (i + 1) % 3;
    const double s = segmentWeight(t[i], t[j], x);
    const Vec y = (1 - s) * t[i] + s * t[j];
    const double d = (y - x).squaredNorm();
    if (d < best)
    {
      best = d, point = y;
      w[0] = w[1] = w[2] = 0;
      w[i] = 1 - s, w[j] = s;
    }
  }
  return point;
}

inline Vec closestOnTriangle(const Vec t[3], const Vec& x)
{
  double w[3];
  return closestOnTriangle(t, x, w);
}

/// Closest points of segments [p0, p1] and [q0, q1], degenerate segments included: the mesh-mesh leaf test's, whose
/// lines' solution stays accurate for near-parallel segments. The normal equations lost precision as the square of
/// the angle: a thin capsule's axis passing a triangle edge at a small angle came out farther than the tolerance.
inline void segmentSegment(const Vec& p0, const Vec& p1, const Vec& q0, const Vec& q1, Closest& best)
{
  detail::ClosestSoFar<double> closest;
  detail::segmentSegment<double>(p0, p1, q0, q1, closest);
  best.keep(std::sqrt(closest.sq_distance), closest.on_a, closest.on_b);
}

/// Closest points of segment [p0, p1] and the box [-h, h] (on_triangle on the segment). Along the segment the
/// squared distance to the box is convex and piecewise quadratic, one piece between consecutive crossings of the
/// box's face planes: the first piece whose slope turns non-negative holds the minimum, in closed form.
inline void segmentBox(const Vec& p0, const Vec& p1, const Vec& h, Closest& best)
{
  const Vec u = p1 - p0;
  double cuts[7];
  int count = 0;
  for (int k = 0; k < 3; ++k)
    for (const double face : {-h[k], h[k]})
    {
      const double s = (face - p0[k]) / u[k];  // no crossing (s not in (0, 1), or NaN) for u[k] == 0
      if (s > 0 && s < 1)
      {
        int at = count++;  // sorted as they come
        for (; at > 0 && cuts[at - 1] > s; --at) cuts[at] = cuts[at - 1];
        cuts[at] = s;
      }
    }
  cuts[count++] = 1;
  double from = 0, s = 1;
  for (int i = 0; i < count; ++i)
  {
    const double to = cuts[i];
    if (!(to > from)) continue;
    // Half the slope on (from, to) is a s + b: the axes on which the piece lies outside the box add to it.
    const double mid = 0.5 * (from + to);
    double a = 0, b = 0;
    for (int k = 0; k < 3; ++k)
    {
      const double x = p0[k] + mid * u[k];
      if (x > h[k])
        a += u[k] * u[k], b += u[k] * (p0[k] - h[k]);
      else if (x < -h[k])
        a += u[k] * u[k], b += u[k] * (p0[k] + h[k]);
    }
    if (a * to + b >= 0)
    {
      s = a > 0 ? std::clamp(-b / a, from, to) : from;
      break;
    }
    from = to;
  }
  const Vec x = p0 + s * u;
  const Vec y = x.cwiseMax(-h).cwiseMin(h);
  best.keep((x - y).norm(), x, y);
}

/// Closest points of triangle t and segment [s0, s1] (on_shape on the segment).
inline Closest segmentTriangle(const Vec t[3], const Vec& s0, const Vec& s1)
{
  Closest best;
  // The segment crossing the triangle's plane inside the triangle: distance 0.
  const Vec n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double h0 = n.dot(s0 - t[0]), h1 = n.dot(s1 - t[0]);
  if (n.squaredNorm() > 0 && ((h0 <= 0 && h1 >= 0) || (h0 >= 0 && h1 <= 0)) && h0 != h1)
  {
    const Vec x = s0 + (h0 / (h0 - h1)) * (s1 - s0);
    const Vec y = closestOnTriangle(t, x);
    best.keep((x - y).norm(), y, x);
  }
  for (const Vec* s : {&s0, &s1})
  {
    const Vec y = closestOnTriangle(t, *s);
    best.keep((y - *s).norm(), y, *s);
  }
  for (int i = 0; i < 3; ++i)
  {
    Closest edge;
    segmentSegment(t[i], t[(i + 1) % 3], s0, s1, edge);
    best.keep(edge.distance, edge.on_triangle, edge.on_shape);
  }
  return best;
}

/// Closest points of triangles t and u (on_shape on u): the mesh-mesh leaf test's distance, which takes zero-area
/// triangles too (FCL's triDistance returns NaN for a triangle whose vertices coincide).
inline Closest triangleTriangle(const Vec t[3], const Vec u[3])
{
  const detail::ClosestSoFar<double> c = detail::triangleDistance<double>(t, u, 0);
  return Closest{std::sqrt(c.sq_distance), c.on_a, c.on_b};
}

/// A point of the Minkowski difference A - B: a on A, b on B, w = a - b.
struct DifferencePoint
{
  Vec a, b, w;
};

/// Closest points of two convex sets A and B (on_triangle on A, on_shape on B), by GJK on their Minkowski
/// difference with the closest point of each simplex found by closestOnTriangle. supportOf(d) is the difference's
/// point lowest along d (A's lowest and B's highest, a DifferencePoint); the first point is supportOf(start).
/// Stops when the pair is certified farther apart than `apart`, when it is within `touch` (meeting), or when the
/// lower bound is within relative_gap of the distance reached. lower: the certified lower bound reached.
///
/// With `exactSupportOf` (not nullptr), supportOf may return a point of the difference that is not its lowest
/// (a walk along a surface's edges): such a point moves the simplex but bounds nothing. Where GJK would stop on
/// it, exactSupportOf(v), the true lowest point, decides: it gives the bound, and replaces the walked point when
/// lower, so GJK goes on from there.
template <typename SupportOf, typename ExactSupportOf = std::nullptr_t>
Closest gjk(const SupportOf& supportOf, const Vec& start, double touch, double apart, double& lower,
            const ExactSupportOf& exactSupportOf = nullptr, double relative_gap = kIterativeRelativeGap)
{
  constexpr bool kCertifies = !std::is_same_v<ExactSupportOf, std::nullptr_t>;
  using Point = DifferencePoint;
  std::array<Point, 4> simplex;
  int size = 1;
  simplex[0] = supportOf(start);
  Vec v = simplex[0].w;
  double weights[4] = {1, 0, 0, 0};
  lower = 0;
  Closest reached;
  const auto finish = [&]() {
    reached.on_triangle = Vec::Zero(), reached.on_shape = Vec::Zero();
    for (int i = 0; i < size; ++i)
    {
      reached.on_triangle += weights[i] * simplex[i].a;
      reached.on_shape += weights[i] * simplex[i].b;
    }
    reached.distance = (reached.on_triangle - reached.on_shape).norm();
    return reached;
  };
  for (int step = 0; step < kIterativeMaxSteps; ++step)
  {
    const double vv = v.squaredNorm();
    if (!(vv > touch * touch)) return lower = 0, finish();
    const double norm = std::sqrt(vv);
    Point p = supportOf(v);
    const auto stops = [&](double bound) { return bound > apart || norm - bound <= relative_gap * norm; };
    const auto inSimplex = [&](const Point& q) {
      for (int i = 0; i < size; ++i)
        if (simplex[i].w == q.w) return true;
      return false;
    };
    // Every point of the difference lies beyond the plane through its lowest point normal to v: where p is that
    // point (supportOf exact, or confirmed by exactSupportOf), `along` is a lower bound.
    const double along = v.dot(p.w) / norm;
    // A support point already in the simplex: no progress left above rounding.
    bool repeated = inSimplex(p);
    if constexpr (kCertifies)
    {
      if (stops(std::max(lower, along)) || repeated)
      {
        const Point lowest = exactSupportOf(v);
        const double exact = v.dot(lowest.w) / norm;
        if (exact < along) p = lowest, repeated = inSimplex(p);
        lower = std::max(lower, exact);
      }
    }
    else
      lower = std::max(lower, along);
    if (stops(lower) || repeated) return finish();
    simplex[size++] = p;
    weights[size - 1] = 0;
    // The closest point of the simplex to the origin; vertices without weight leave it.
    Vec closest;
    if (size == 2)
    {
      const double s = segmentWeight(simplex[0].w, simplex[1].w, Vec::Zero());
      weights[0] = 1 - s, weights[1] = s;
      closest = weights[0] * simplex[0].w + weights[1] * simplex[1].w;
    }
    else if (size == 3)
    {
      const Vec w3[3] = {simplex[0].w, simplex[1].w, simplex[2].w};
      closest = closestOnTriangle(w3, Vec::Zero(), weights);
    }
    else
    {
      // A tetrahedron: the origin inside (on the inner side of all four faces) meets; else its nearest face.
      const Vec w[4] = {simplex[0].w, simplex[1].w, simplex[2].w, simplex[3].w};
      bool inside = (w[1] - w[0]).cross(w[2] - w[0]).dot(w[3] - w[0]) != 0;
      for (int f = 0; f < 4 && inside; ++f)
      {
        const Vec& a = w[(f + 1) % 4];
        const Vec n = (w[(f + 2) % 4] - a).cross(w[(f + 3) % 4] - a);
        const double opposite = n.dot(w[f] - a);
        inside = opposite != 0 && n.dot(-a) * opposite >= 0;
      }
      // Rounding can make a nearly flat tetrahedron seem to hold the origin; the certified bound overrules it.
      if (inside && lower <= touch)
      {
        lower = 0;
        finish();
        reached.distance = 0;
        return reached;
      }
      double best = std::numeric_limits<double>::infinity();
      double face_weights[3];
      int face = 0;
      for (int f = 0; f < 4; ++f)
      {
        const Vec tri[3] = {w[(f + 1) % 4], w[(f + 2) % 4], w[(f + 3) % 4]};
        const Vec x = closestOnTriangle(tri, Vec::Zero(), face_weights);
        if (x.squaredNorm() < best) best = x.squaredNorm(), face = f, closest = x;
      }
      const Vec tri[3] = {w[(face + 1) % 4], w[(face + 2) % 4], w[(face + 3) % 4]};
      closestOnTriangle(tri, Vec::Zero(), face_weights);
      const std::array<Point, 4> old = simplex;
      for (int k = 0; k < 3; ++k) simplex[k] = old[(face + 1 + k) % 4], weights[k] = face_weights[k];
      weights[3] = 0;
      size = 3;
    }
    // No progress: the reached point is as close as rounding allows.
    if (!(closest.squaredNorm() < vv)) return finish();
    int kept = 0;
    for (int i = 0; i < size; ++i)
      if (weights[i] > 0) simplex[kept] = simplex[i], weights[kept++] = weights[i];
    size = std::max(kept, 1);
    v = closest;
  }
  return finish();
}

/// Points whose convex hull GJK bounds (hullsLowerBound), with the edges of a triangulated surface over them when
/// there are many: then a support point is found by walking from the previous one along edges to a neighbour
/// lower along the direction, as long as one is (on a convex surface the walk ends at the lowest point), and only
/// the point GJK would stop on is checked against every point (gjk's exactSupportOf), which makes the bound
/// certified whatever the surface. That check skips the clusters of nearby points whose balls lie above it.
class HullPoints
{
public:
  HullPoints() = default;
  /// Every support a scan of the points.
  explicit HullPoints(std::vector<Vec> points) : points_(std::move(points)) {}
  /// triangles: indices into points. Fewer points than kMinWalked are scanned whatever the surface.
  HullPoints(std::vector<Vec> points, const std::vector<std::array<std::size_t, 3>>& triangles)
    : points_(std::move(points))
  {
    if (points_.size() < kMinWalked || points_.size() > std::numeric_limits<std::uint32_t>::max()) return;
    // Clusters: the points split at the median of their box's longest side until few are left, stored cluster
    // by cluster (`order` lists the old indices in the new order).
    std::vector<std::size_t> order(points_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    split(order, 0, order.size());
    std::vector<std::size_t> renamed(points_.size());
    std::vector<Vec> ordered(points_.size());
    for (std::size_t i = 0; i < order.size(); ++i) renamed[order[i]] = i, ordered[i] = points_[order[i]];
    points_ = std::move(ordered);
    std::vector<std::vector<std::uint32_t>> around(points_.size());
    for (const auto& t : triangles)
      for (int k = 0; k < 3; ++k)
      {
        const std::size_t from = renamed[t[k]], to = renamed[t[(k + 1) % 3]];
        if (from != to) around[from].push_back(std::uint32_t(to)), around[to].push_back(std::uint32_t(from));
      }
    first_.push_back(0);
    for (auto& next : around)
    {
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      neighbours_.insert(neighbours_.end(), next.begin(), next.end());
      first_.push_back(std::uint32_t(neighbours_.size()));
    }
    // The walks start at the point lowest along the axis direction nearest the first one.
    for (int k = 0; k < 6; ++k) starts_[std::size_t(k)] = lowest(k < 3 ? Vec(Vec::Unit(k)) : Vec(-Vec::Unit(k - 3)));
  }

  const std::vector<Vec>& points() const { return points_; }
  bool walks() const { return !first_.empty(); }

  /// The index of the first point lowest along d.
  std::size_t lowest(const Vec& d) const
  {
    std::size_t best = 0;
    double lowest_value = points_[0].dot(d);
    for (std::size_t i = 1; i < points_.size(); ++i)
    {
      const double value = points_[i].dot(d);
      if (value < lowest_value) lowest_value = value, best = i;
    }
    return best;
  }
  /// The index of a point lowest along d, `candidate` unless a point is lower: the clusters whose balls lie above
  /// the candidate along d are skipped (without walks(), lowest(d)).
  std::size_t lowestBelow(const Vec& d, std::size_t candidate) const
  {
    if (!walks()) return lowest(d);
    double value = points_[candidate].dot(d);
    const double length = d.norm();
    for (const Cluster& c : clusters_)
    {
      // The cluster's points are at least this low, by its ball and by its box (tighter along a face of the box,
      // where the ball dips below the points); the margin covers the rounding of both sides.
      const double floor = c.centre.dot(d) - std::min(c.radius * length, c.half.dot(d.cwiseAbs()));
      if (floor - kClusterMargin * (c.reach * length) > value) continue;
      for (std::size_t i = c.begin; i < c.end; ++i)
      {
        const double point = points_[i].dot(d);
        if (point < value) value = point, candidate = i;
      }
    }
    return candidate;
  }
  /// A point no neighbour of which is lower along d, reached from `from` (kNoPoint: from the start point for d);
  /// without walks(), lowest(d).
  std::size_t walk(const Vec& d, std::size_t from) const
  {
    if (!walks()) return lowest(d);
    std::size_t at = from;
    if (at == kNoPoint)
    {
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(d[k]) > std::abs(d[axis])) axis = k;
      at = starts_[std::size_t(d[axis] > 0 ? axis : axis + 3)];
    }
    double value = points_[at].dot(d);
    for (;;)
    {
      std::size_t next = at;
      for (std::uint32_t k = first_[at]; k < first_[at + 1]; ++k)
      {
        const double neighbour = points_[neighbours_[k]].dot(d);
        if (neighbour < value) value = neighbour, next = neighbours_[k];
      }
      if (next == at) return at;
      at = next;
    }
  }

  static constexpr std::size_t kNoPoint = std::numeric_limits<std::size_t>::max();
  /// Below this many points a scan costs about what a walk does.
  static constexpr std::size_t kMinWalked = 32;

private:
  /// Points [begin, end) within `radius` of `centre` and within the box of half sides `half` about it; reach:
  /// |centre| + radius.
  struct Cluster
  {
    std::size_t begin, end;
    Vec centre, half;
    double radius, reach;
  };
  static constexpr std::size_t kClusterSize = 16;
  /// Far above the relative rounding of a dot product of three terms.
  static constexpr double kClusterMargin = 1e-12;

  /// Orders order[begin, end) into clusters of at most kClusterSize points and records them.
  void split(std::vector<std::size_t>& order, std::size_t begin, std::size_t end)
  {
    Vec lo = points_[order[begin]], hi = lo;
    for (std::size_t i = begin; i < end; ++i) lo = lo.cwiseMin(points_[order[i]]), hi = hi.cwiseMax(points_[order[i]]);
    if (end - begin <= kClusterSize)
    {
      const Vec centre = (lo + hi) / 2;
      double radius = 0;
      for (std::size_t i = begin; i < end; ++i) radius = std::max(radius, (points_[order[i]] - centre).norm());
      radius *= 1 + kClusterMargin;
      const Vec half = (hi - lo) / 2 * (1 + kClusterMargin);
      clusters_.push_back(Cluster{begin, end, centre, half, radius, centre.norm() + radius});
      return;
    }
    int axis;
    (hi - lo).maxCoeff(&axis);
    const std::size_t middle = begin + (end - begin) / 2;
    std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle),
                     order.begin() + std::ptrdiff_t(end),
                     [&](std::size_t x, std::size_t y) { return points_[x][axis] < points_[y][axis]; });
    split(order, begin, middle);
    split(order, middle, end);
  }

  std::vector<Vec> points_;
  std::vector<std::uint32_t> first_, neighbours_;  ///< point i's neighbours: neighbours_[first_[i], first_[i + 1])
  std::array<std::size_t, 6> starts_{};          ///< lowest along +x, +y, +z, -x, -y, -z
  std::vector<Cluster> clusters_;                ///< cover the points in order, when walks()
};

/// A lower bound on the distance between the convex hulls of points a (posed by pa) and points b (posed by pb),
/// each at least one point: gjk's certified bound, from `start` (roughly from b towards a), stopped once it
/// exceeds `enough` (a caller that only asks whether the hulls are that far apart needs no more) or once it is
/// within relative_gap of the distance reached. With the default gap exact but for rounding, a few ulps of the
/// points' and poses' scale. direction: from the closest point reached on a's hull to
/// b's (zero when the hulls meet), the hulls' gap direction once GJK has converged.
inline double hullsLowerBound(const HullPoints& a, const Eigen::Isometry3d& pa, const HullPoints& b,
                              const Eigen::Isometry3d& pb, const Vec& start, double enough, Vec* direction = nullptr,
                              double relative_gap = kIterativeRelativeGap)
{
  const Eigen::Matrix3d ra = pa.linear().transpose(), rb = pb.linear().transpose();
  const auto differencePoint = [&](std::size_t i, std::size_t j) {
    const Vec pa_point = pa * a.points()[i];
    const Vec pb_point = pb * b.points()[j];
    return DifferencePoint{pa_point, pb_point, pa_point - pb_point};
  };
  // The difference's point lowest along d: a's lowest point and b's highest.
  const auto lowestPoint = [&](const Vec& d) { return differencePoint(a.lowest(ra * d), b.lowest(rb * Vec(-d))); };
  double lower = 0;
  Closest reached;
  if (!a.walks() && !b.walks())
    reached = gjk(lowestPoint, start, 0, enough, lower, nullptr, relative_gap);
  else
  {
    // Each walk goes on from where the previous support point of its hull was.
    std::size_t at_a = HullPoints::kNoPoint, at_b = HullPoints::kNoPoint;
    const auto walkedPoint = [&](const Vec& d) {
      at_a = a.walk(ra * d, at_a);
      at_b = b.walk(rb * Vec(-d), at_b);
      return differencePoint(at_a, at_b);
    };
    const auto scannedPoint = [&](const Vec& d) {
      at_a = a.lowestBelow(ra * d, at_a);
      at_b = b.lowestBelow(rb * Vec(-d), at_b);
      return differencePoint(at_a, at_b);
    };
    reached = gjk(walkedPoint, start, 0, enough, lower, scannedPoint, relative_gap);
  }
  if (direction) *direction = reached.on_shape - reached.on_triangle;
  return lower;
}

/// gjk for a triangle (A) and a convex shape (B) given by its support function (the point of the shape farthest
/// along a direction): the collision verdict stops at `apart`.
template <typename Support>
Closest gjk(const Vec t[3], const Support& support, double touch, double apart, double& lower)
{
  const auto supportOf = [&](const Vec& d) {
    int best = 0;
    for (int i = 1; i < 3; ++i)
      if (t[i].dot(d) < t[best].dot(d)) best = i;
    const Vec b = support(d);
    return DifferencePoint{t[best], b, t[best] - b};
  };
  return gjk(supportOf, Vec(-t[0]), touch, apart, lower);
}

/// Whether triangle t lies outside the box [-h, h] by more than tol along one of the box's axes.
inline bool outsideBox(const Vec t[3], const Vec& h, double tol)
{
  for (int k = 0; k < 3; ++k)
  {
    const double lo = std::min({t[0][k], t[1][k], t[2][k]}), hi = std::max({t[0][k], t[1][k], t[2][k]});
    if (lo > h[k] + tol || hi < -h[k] - tol) return true;
  }
  return false;
}

/// Whether axis (any length) separates triangle t from a shape symmetric about the origin that reaches `reach`
/// along it, by more than tol |axis|_1 (>= tol |axis|): the triangle's projections against [-reach, reach].
inline bool separatedAlong(const Vec t[3], const Vec& axis, double reach, double tol)
{
  const double p0 = axis.dot(t[0]), p1 = axis.dot(t[1]), p2 = axis.dot(t[2]);
  const double r = reach + tol * axis.lpNorm<1>();
  return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

/// A primitive in its own frame: `meets` decides the collision verdict within a tolerance, `closest` the
/// distance of a triangle that does not meet it. reach: the shape's largest coordinate (the tolerance's scale).
/// kRejectsCheaply: meets opens with the triangle's extent along the shape's axes and normal, a rejection that
/// costs less than a node test of the triangle's leaf, so the traversal skips that test.
template <typename Shape>
class ShapeGeometry;

template <typename S>
class ShapeGeometry<fcl::Sphere<S>>
{
public:
  static constexpr bool kRejectsCheaply = false;
  explicit ShapeGeometry(const fcl::Sphere<S>& s) : r_(s.radius) {}
  double reach() const { return r_; }
  Closest closest(const Vec t[3]) const
  {
    const Vec x = closestOnTriangle(t, Vec::Zero());
    const double n = x.norm();
    return Closest{n - r_, x, n > 0 ? Vec(x * (r_ / n)) : Vec(0, 0, r_)};
  }
  bool meets(const Vec t[3], double tol) const { return closestOnTriangle(t, Vec::Zero()).norm() <= r_ + tol; }

private:
  double r_;
};

template <typename S>
class ShapeGeometry<fcl::Capsule<S>>
{
public:
  static constexpr bool kRejectsCheaply = true;
  explicit ShapeGeometry(const fcl::Capsule<S>& c) : r_(c.radius), h_(double(c.lz) / 2) {}
  double reach() const { return r_ + h_; }
  Closest closest(const Vec t[3]) const
  {
    Closest c = segmentTriangle(t, Vec(0, 0, -h_), Vec(0, 0, h_));
    const Vec away = c.on_triangle - c.on_shape;
    c.on_shape += c.distance > 0 ? Vec(away * (r_ / c.distance)) : Vec::Zero();
    c.distance -= r_;
    return c;
  }
  bool meets(const Vec t[3], double tol) const
  {
    if (outsideBox(t, Vec(r_, r_, h_ + r_), tol)) return false;
    const Vec n = (t[1] - t[0]).cross(t[2] - t[0]);
    if (separatedAlong(t, n, std::abs(n.z()) * h_ + r_ * n.norm(), tol)) return false;
    return segmentTriangle(t, Vec(0, 0, -h_), Vec(0, 0, h_)).distance <= r_ + tol;
  }

private:
  double r_, h_;
};

template <typename S>
class ShapeGeometry<fcl::Box<S>>
{
public:
  static constexpr bool kRejectsCheaply = true;
  explicit ShapeGeometry(const fcl::Box<S>& b) : h_(b.side.template cast<double>() / 2) {}
  double reach() const { return h_.maxCoeff(); }

  /// The separating axis test: the box's three axes, the triangle's normal and the nine cross products of box
  /// axes and triangle edges. A pair is separated along an axis L only by more than tol |L|_1 (>= tol |L|).
  bool meets(const Vec t[3], double tol) const
  {
    if (outsideBox(t, h_, tol)) return false;
    const auto separates = [&](const Vec& axis) { return separatedAlong(t, axis, h_.dot(axis.cwiseAbs()), tol); };
    if (separates((t[1] - t[0]).cross(t[2] - t[0]))) return false;
    for (int i = 0; i < 3; ++i)
    {
      const Vec f = t[(i + 1) % 3] - t[i];
      if (separates(Vec(0, -f.z(), f.y())) || separates(Vec(f.z(), 0, -f.x())) || separates(Vec(-f.y(), f.x(), 0)))
        return false;
    }
    return true;
  }

  /// For two disjoint convex polytopes some closest pair is a vertex of one and a point of the other, or a
  /// point on an edge of each: a point of a triangle edge, or a box corner and a point inside the triangle.
  /// - Along an edge the squared distance is convex with slope 2 u.e at an end (u along the edge, e the end's
  ///   offset from its nearest box point): the edge is measured (segmentBox) only when the distance falls from
  ///   both ends into the edge, else its nearest point is an end, measured as a vertex.
  /// - At a corner with a point inside the triangle the triangle's plane separates, so the corner is the box's
  ///   nearest to that plane on the box's side; where several are (a box face or edge parallel to the plane), one
  ///   whose closest point is inside the triangle gives the distance, or a triangle edge passes over that face or
  ///   edge at the same distance. A box that crosses the plane (beyond the rounding) has no such pair.
  Closest closest(const Vec t[3]) const
  {
    Closest best;
    Vec offset[3];
    for (int i = 0; i < 3; ++i)
    {
      const Vec q = t[i].cwiseMax(-h_).cwiseMin(h_);
      offset[i] = t[i] - q;
      best.keep(offset[i].norm(), t[i], q);
    }
    for (int i = 0; i < 3; ++i)
    {
      const int j = (i + 1) % 3;
      const Vec u = t[j] - t[i];
      if (u.dot(offset[i]) < 0 && u.dot(offset[j]) > 0) segmentBox(t[i], t[j], h_, best);
    }
    const Vec n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double centre = n.dot(t[0]), half_width = h_.dot(n.cwiseAbs());
    // The rounding of both is far below 1e-9 of n's and the coordinates' scale.
    if (std::abs(centre) + 1e-9 * n.lpNorm<1>() * (t[0].lpNorm<1>() + h_.sum()) < half_width) return best;
    // The plane lies along towards * n from the box's centre (the origin): the corner nearest it is the box's
    // support point along that direction.
    const double towards = centre > 0 ? 1 : -1;
    Vec corner;
    for (int k = 0; k < 3; ++k) corner[k] = towards * n[k] >= 0 ? h_[k] : -h_[k];
    const Vec p = closestOnTriangle(t, corner);
    best.keep((p - corner).norm(), p, corner);
    return best;
  }

private:
  Vec h_;
};

/// A convex polytope by the fans of its faces, each fan triangle with its outward normal.
template <typename S>
class ShapeGeometry<fcl::Convex<S>>
{
public:
  static constexpr bool kRejectsCheaply = false;
  explicit ShapeGeometry(const fcl::Convex<S>& c)
  {
    const auto& vertices = c.getVertices();
    const auto& faces = c.getFaces();
    const Vec inner = c.getInteriorPoint().template cast<double>();
    for (const auto& v : vertices) reach_ = std::max(reach_, v.template cast<double>().cwiseAbs().maxCoeff());
    std::size_t at = 0;
    for (int f = 0; f < c.getFaceCount(); ++f)
    {
      const int count = faces[at];
      const Vec x0 = vertices[std::size_t(faces[at + 1])].template cast<double>();
      for (int i = 1; i + 1 < count; ++i)
      {
        Fan tri{{x0, vertices[std::size_t(faces[at + 1 + i])].template cast<double>(),
                 vertices[std::size_t(faces[at + 2 + i])].template cast<double>()},
                Vec::Zero()};
        tri.normal = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]);
        if (tri.normal.dot(inner - x0) > 0) tri.normal = -tri.normal;
        fans_.push_back(tri);
      }
      at += std::size_t(count) + 1;
    }
  }
  double reach() const { return reach_; }

  /// A triangle vertex inside every face plane (the triangle inside the polytope), or the triangle within tol
  /// of a face triangle (the mesh-mesh leaf test's contract).
  bool meets(const Vec t[3], double tol) const
  {
    const auto inside = [&](const Vec& x) {
      for (const Fan& f : fans_)
        if (f.normal.dot(x - f.v[0]) > tol * f.normal.template lpNorm<1>()) return false;
      return true;
    };
    if (inside(t[0])) return true;
    for (const Fan& f : fans_)
      if (trianglesWithin<double>(t, f.v, tol)) return true;
    return false;
  }

  /// Disjoint from the triangle, the polytope's closest point is on its boundary: the nearest face triangle.
  Closest closest(const Vec t[3]) const
  {
    Closest best;
    for (const Fan& f : fans_)
    {
      const Closest c = triangleTriangle(t, f.v);
      best.keep(c.distance, c.on_triangle, c.on_shape);
    }
    return best;
  }

private:
  struct Fan
  {
    Vec v[3];
    Vec normal;  ///< outward, not normalised
  };
  std::vector<Fan> fans_;
  double reach_ = 0;
};

/// Plane n . x = d and halfspace n . x <= d (|n| = 1): the triangle's signed vertex heights decide.
template <typename S>
class ShapeGeometry<fcl::Plane<S>>
{
public:
  static constexpr bool kRejectsCheaply = false;
  explicit ShapeGeometry(const fcl::Plane<S>& p) : n_(p.n.template cast<double>()), d_(p.d) {}
  double reach() const { return std::abs(d_); }
  bool meets(const Vec t[3], double tol) const
  {
    const double h0 = n_.dot(t[0]) - d_, h1 = n_.dot(t[1]) - d_, h2 = n_.dot(t[2]) - d_;
    return std::min({h0, h1, h2}) <= tol && std::max({h0, h1, h2}) >= -tol;
  }
  Closest closest(const Vec t[3]) const
  {
    Closest best;
    for (int i = 0; i < 3; ++i)
    {
      const double h = n_.dot(t[i]) - d_;
      best.keep(std::abs(h), t[i], t[i] - h * n_);
    }
    return best;
  }

private:
  Vec n_;
  double d_;
};

template <typename S>
class ShapeGeometry<fcl::Halfspace<S>>
{
public:
  static constexpr bool kRejectsCheaply = false;
  explicit ShapeGeometry(const fcl::Halfspace<S>& p) : n_(p.n.template cast<double>()), d_(p.d) {}
  double reach() const { return std::abs(d_); }
  bool meets(const Vec t[3], double tol) const
  {
    return std::min({n_.dot(t[0]), n_.dot(t[1]), n_.dot(t[2])}) - d_ <= tol;
  }
  Closest closest(const Vec t[3]) const
  {
    Closest best;
    for (int i = 0; i < 3; ++i)
    {
      const double h = n_.dot(t[i]) - d_;
      best.keep(h, t[i], t[i] - h * n_);
    }
    return best;
  }

private:
  Vec n_;
  double d_;
};

/// Cylinder, cone and ellipsoid: GJK on their exact support functions. The collision verdict first asks
/// Derived::decides, a closed-form verdict where a cheap one settles the triangle (none: GJK decides).
template <typename Derived>
class IterativeGeometry
{
public:
  bool meets(const Vec t[3], double tol) const
  {
    if (const std::optional<bool> verdict = static_cast<const Derived*>(this)->decides(t, tol)) return *verdict;
    double lower;
    gjk(t, support(), tol, tol, lower);
    return lower <= tol;
  }
  /// One GJK run for both: meets as meets(t, tol) decides it (to rounding: decides' verdicts keep a margin from
  /// the tolerance, so GJK's agrees), else the closest points.
  Closest closest(const Vec t[3], double tol, bool& meets) const
  {
    double lower;
    const Closest c = gjk(t, support(), tol, std::numeric_limits<double>::infinity(), lower);
    meets = lower <= tol;
    return c;
  }
  Closest closest(const Vec t[3]) const
  {
    bool meets;
    return closest(t, 0, meets);
  }
  /// No closed-form verdict (a shape that has one hides this and kRejectsCheaply).
  std::optional<bool> decides(const Vec*, double) const { return std::nullopt; }
  static constexpr bool kRejectsCheaply = false;

private:
  auto support() const
  {
    return [this](const Vec& d) { return static_cast<const Derived*>(this)->support(d); };
  }
};

template <typename S>
class ShapeGeometry<fcl::Cylinder<S>> : public IterativeGeometry<ShapeGeometry<fcl::Cylinder<S>>>
{
public:
  static constexpr bool kRejectsCheaply = true;
  explicit ShapeGeometry(const fcl::Cylinder<S>& c) : r_(c.radius), h_(double(c.lz) / 2) {}
  double reach() const { return std::max(r_, h_); }
  Vec support(const Vec& d) const
  {
    const double radial = std::hypot(d.x(), d.y());
    const double s = radial > 0 ? r_ / radial : 0;
    return Vec(s * d.x(), s * d.y(), d.z() >= 0 ? h_ : -h_);
  }
  /// Apart where the cylinder's axes or the triangle's normal separate them, or the triangle is apart from the
  /// capsule around the cylinder (same axis segment and radius), each by more than twice the tolerance, so that
  /// GJK, were it asked, would not report it either. Meets where a point of the triangle lies inside the
  /// cylinder: a vertex, or the triangle's point nearest the axis segment. Only triangles near the rims or at the
  /// tolerance go on to GJK.
  std::optional<bool> decides(const Vec t[3], double tol) const
  {
    if (outsideBox(t, Vec(r_, r_, h_), 2 * tol)) return false;
    const Vec n = (t[1] - t[0]).cross(t[2] - t[0]);
    if (separatedAlong(t, n, std::abs(n.z()) * h_ + r_ * std::hypot(n.x(), n.y()), 2 * tol)) return false;
    const auto inside = [&](const Vec& x) { return std::abs(x.z()) <= h_ && x.x() * x.x() + x.y() * x.y() <= r_ * r_; };
    if (inside(t[0]) || inside(t[1]) || inside(t[2])) return true;
    const Closest axis = segmentTriangle(t, Vec(0, 0, -h_), Vec(0, 0, h_));
    if (axis.distance > r_ + 2 * tol) return false;
    if (inside(axis.on_triangle)) return true;
    return std::nullopt;
  }

private:
  double r_, h_;
};

/// FCL's cone: apex at z = lz / 2, base of the radius at z = -lz / 2.
template <typename S>
class ShapeGeometry<fcl::Cone<S>> : public IterativeGeometry<ShapeGeometry<fcl::Cone<S>>>
{
public:
  explicit ShapeGeometry(const fcl::Cone<S>& c) : r_(c.radius), h_(double(c.lz) / 2) {}
  double reach() const { return std::max(r_, h_); }
  Vec support(const Vec& d) const
  {
    const double radial = std::hypot(d.x(), d.y());
    const double s = radial > 0 ? r_ / radial : 0;
    const Vec rim(s * d.x(), s * d.y(), -h_);
    return rim.dot(d) > h_ * d.z() ? rim : Vec(0, 0, h_);
  }

private:
  double r_, h_;
};

template <typename S>
class ShapeGeometry<fcl::Ellipsoid<S>> : public IterativeGeometry<ShapeGeometry<fcl::Ellipsoid<S>>>
{
public:
  explicit ShapeGeometry(const fcl::Ellipsoid<S>& e) : radii_(e.radii.template cast<double>()) {}
  double reach() const { return radii_.maxCoeff(); }
  Vec support(const Vec& d) const
  {
    const Vec scaled = radii_.cwiseProduct(d);
    const double n = scaled.norm();
    return n > 0 ? Vec(radii_.cwiseProduct(scaled) / n) : Vec::Zero();
  }

private:
  Vec radii_;
};

}  // namespace triangle_shape

/// The leaf test of one mesh-shape query: the shape's geometry in its frame and the mesh-to-shape map, set up once.
/// Triangles come in the mesh's frame; nearest points go out in the world frame.
template <typename Shape>
class TriangleShapeLeaf
{
public:
  using S = typename Shape::S;
  /// meets opens with a rejection cheaper than a node test (triangle_shape::ShapeGeometry).
  static constexpr bool kRejectsCheaply = triangle_shape::ShapeGeometry<Shape>::kRejectsCheaply;

  TriangleShapeLeaf(const Shape& shape, const fcl::Transform3<S>& tf_mesh, const fcl::Transform3<S>& tf_shape)
    : geometry_(shape),
      shape_to_world_(tf_shape.template cast<double>()),
      mesh_to_shape_(shape_to_world_.inverse(Eigen::Isometry) * tf_mesh.template cast<double>()),
      t1_(tf_mesh.translation()),
      t2_(tf_shape.translation()),
      T_(mesh_to_shape_.translation().template cast<S>())
  {
  }

  /// The collision verdict for triangle p (mesh frame): the leaf tolerance's contract (header comment).
  bool meets(const fcl::Vector3<S> p[3]) const
  {
    triangle_shape::Vec t[3];
    return geometry_.meets(moved(p, t), tolerance(p));
  }

  /// The triangle's distance to the shape and world nearest points (on_mesh, on_shape); -1 (FCL's convention for
  /// mesh-shape leaves) and both points at the triangle's closest point when it meets the shape (meets()).
  S distance(const fcl::Vector3<S> p[3], fcl::Vector3<S>& on_mesh, fcl::Vector3<S>& on_shape) const
  {
    triangle_shape::Vec t[3];
    moved(p, t);
    bool meets;
    const triangle_shape::Closest c = closestUnlessMeeting(t, tolerance(p), meets);
    if (meets)
    {
      on_mesh = on_shape = (shape_to_world_ * c.on_triangle).template cast<S>();
      return S(-1);
    }
    on_mesh = (shape_to_world_ * c.on_triangle).template cast<S>();
    on_shape = (shape_to_world_ * c.on_shape).template cast<S>();
    return S(c.distance);
  }

  const triangle_shape::ShapeGeometry<Shape>& geometry() const { return geometry_; }
  /// Triangle p (mesh frame) in the shape's frame.
  const triangle_shape::Vec* moved(const fcl::Vector3<S> p[3], triangle_shape::Vec t[3]) const
  {
    for (int i = 0; i < 3; ++i) t[i] = mesh_to_shape_ * p[i].template cast<double>();
    return t;
  }
  /// What a bounding-volume test must add to its rounding offsets (pairRoundingBound's) so that it never prunes a
  /// triangle this leaf reports: the tolerance's terms, 1-norms for max norms, for a mesh within mesh_reach of its
  /// frame's origin.
  S boundOffsets(S mesh_reach) const
  {
    return t1_.template lpNorm<1>() + t2_.template lpNorm<1>() + T_.template lpNorm<1>() +
           6 * (mesh_reach + S(geometry_.reach()));
  }
  S tolerance(const fcl::Vector3<S> p[3]) const { return tolerance(largestCoordinate(p)); }
  /// The tolerance of a triangle whose largest coordinate is `size`; it grows with size.
  S tolerance(S size) const { return leafTolerance<S>(std::max(size, S(geometry_.reach())), t1_, t2_, T_); }
  /// The map of the mesh's frame to the shape's, in which the leaf measures.
  const Eigen::Isometry3d& meshToShape() const { return mesh_to_shape_; }

private:
  /// The iterative shapes decide the verdict and the distance in one run.
  triangle_shape::Closest closestUnlessMeeting(const triangle_shape::Vec t[3], double tol, bool& meets) const
  {
    if constexpr (std::is_base_of_v<triangle_shape::IterativeGeometry<triangle_shape::ShapeGeometry<Shape>>,
                                    triangle_shape::ShapeGeometry<Shape>>)
      return geometry_.closest(t, tol, meets);
    else
    {
      meets = geometry_.meets(t, tol);
      return meets ? triangle_shape::Closest{0, t[0], t[0]} : geometry_.closest(t);
    }
  }

  triangle_shape::ShapeGeometry<Shape> geometry_;
  Eigen::Isometry3d shape_to_world_;
  Eigen::Isometry3d mesh_to_shape_;
  fcl::Vector3<S> t1_, t2_, T_;
};

/// The contact of triangle p (the mesh's frame, the mesh at tf_mesh) and shape (at tf_shape), a pair leaf.meets,
/// as FCL's solver gives it with the shape first (normal from the shape towards the triangle): position, normal
/// and depth from FCL's solver where it finds the pair too (far from the origin with both poses moved by
/// -tf_shape's translation, fcl_rs/detail/relative_poses.h, and the position moved back); where it does not (a pair
/// within the tolerance that FCL's GJK calls apart), the contact sits midway between the closest points with depth 0.
template <typename Shape, typename Solver>
void shapeTriangleContact(const TriangleShapeLeaf<Shape>& leaf, const std::array<fcl::Vector3<typename Shape::S>, 3>& p,
                          const Shape& shape, const fcl::Transform3<typename Shape::S>& tf_shape,
                          const fcl::Transform3<typename Shape::S>& tf_mesh, const Solver* nsolver,
                          fcl::Vector3<typename Shape::S>& position, fcl::Vector3<typename Shape::S>& normal,
                          typename Shape::S& depth)
{
  using S = typename Shape::S;
  // Far from the origin (beyond 2^20) both poses move by -tf_shape's translation, else libccd asserts (fuzz_api:
  // 1.5e124); near it FCL's own call is kept, its contacts to the bit as FCL's traversals give them (its MPR depths
  // move with the frame by a few percent).
  const fcl::Vector3<S> shift =
      tf_shape.translation().cwiseAbs().maxCoeff() > S(0x1p20) ? fcl::Vector3<S>(tf_shape.translation())
                                                               : fcl::Vector3<S>::Zero();
  if (nsolver->shapeTriangleIntersect(shape, detail::shifted(tf_shape, shift), p[0], p[1], p[2],
                                      detail::shifted(tf_mesh, shift), &position, &depth, &normal))
  {
    position += shift;
    return;
  }
  triangle_shape::Vec t[3];
  const triangle_shape::Closest c = leaf.geometry().closest(leaf.moved(p.data(), t));
  const Eigen::Isometry3d to_world = tf_shape.template cast<double>();
  triangle_shape::Vec towards = c.on_shape - c.on_triangle;  // from the triangle towards the shape
  if (!(towards.squaredNorm() > 0))
  {
    towards = (t[1] - t[0]).cross(t[2] - t[0]);
    if (towards.dot(-c.on_triangle) < 0) towards = -towards;
    if (!(towards.squaredNorm() > 0)) towards = -c.on_triangle;
    if (!(towards.squaredNorm() > 0)) towards = triangle_shape::Vec::UnitX();
  }
  position = (to_world * ((c.on_triangle + c.on_shape) / 2)).template cast<S>();
  normal = -(to_world.linear() * towards.normalized()).template cast<S>();
  depth = 0;
}

/// FCL's meshShapeCollisionOrientedNodeLeafTesting for triangle primitive_id of model1 (mesh at tf1) against
/// model2 (at tf2), with the verdict of leaf.meets and the contact of shapeTriangleContact.
template <typename BV, typename Shape, typename Solver>
void meshShapeLeafTesting(const TriangleShapeLeaf<Shape>& leaf, int primitive_id, const fcl::BVHModel<BV>* model1,
                          const Shape& model2, const fcl::Vector3<typename Shape::S>* vertices,
                          const fcl::Triangle* tri_indices, const fcl::Transform3<typename Shape::S>& tf1,
                          const fcl::Transform3<typename Shape::S>& tf2, const Solver* nsolver,
                          typename Shape::S cost_density, const fcl::CollisionRequest<typename Shape::S>& request,
                          fcl::CollisionResult<typename Shape::S>& result)
{
  using S = typename Shape::S;
  const bool occupied = model1->isOccupied() && model2.isOccupied();
  if (!occupied && !((!model1->isFree() || model2.isFree()) && request.enable_cost)) return;
  const auto p = triangleVertices(vertices, tri_indices[primitive_id]);
  if (!leaf.meets(p.data())) return;
  if (occupied && request.num_max_contacts > result.numContacts())
  {
    if (!request.enable_contact)
      result.addContact(fcl::Contact<S>(model1, &model2, primitive_id, fcl::Contact<S>::NONE));
    else
    {
      S depth;
      fcl::Vector3<S> normal, position;
      shapeTriangleContact(leaf, p, model2, tf2, tf1, nsolver, position, normal, depth);
      normal = -normal;  // FCL's mesh-shape contacts point from the mesh towards the shape
      result.addContact(fcl::Contact<S>(model1, &model2, primitive_id, fcl::Contact<S>::NONE, position, normal, depth));
    }
  }
  if (request.enable_cost)
  {
    fcl::AABB<S> overlap_part, shape_aabb;
    fcl::computeBV(model2, tf2, shape_aabb);
    fcl::AABB<S>(tf1 * p[0], tf1 * p[1], tf1 * p[2]).overlap(shape_aabb, overlap_part);
    result.addCostSource(fcl::CostSource<S>(overlap_part, cost_density), request.num_max_cost_sources);
  }
}

}  // namespace fcl_rs

#endif
