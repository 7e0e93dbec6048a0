// Triangle-triangle leaf test of RS mesh-mesh queries: closed triangles, degenerate ones included (zero area,
// collinear vertices, a single point), decided conservatively within a documented rounding bound; contacts as
// FCL computes them wherever FCL's contact routine is defined, a documented convention elsewhere.
//
// Guarantee (docs/robustness.md). Let A's vertices p (model 1, its frame), B's vertices q (model 2, its frame),
// and the poses tf1 = (R1, t1), tf2 = (R2, t2) with rotations orthonormal to a few ulps. The test runs on
// q' = R q + T in A's frame ((R, T) = tf1^-1 tf2 as FCL's oriented traversal rounds it) and reports the pair
// iff its computed distance is at most
//     tolerance = 32 eps(S) (|t1|_inf + |t2|_inf + |T|_inf + 3 max_i |p_i|_inf + 3 max_j |q_j|_inf).
// That covers the rounding of the world vertices tf1 p and tf2 q, of (R, T) and of R q + T (each a few ulps of
// the same magnitudes), so two triangles whose world-frame vertices, as computed, touch or intersect exactly
// are always reported; and a reported pair is at most 2 tolerance apart (exactly, in the world frame). The
// answer does not depend on whether contacts are requested.
#ifndef FCL_RS_NARROWPHASE_TRIANGLE_INTERSECTION_H
#define FCL_RS_NARROWPHASE_TRIANGLE_INTERSECTION_H

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

#include "fcl_rs/bvh/node_links.h"

namespace fcl_rs {

/// The distance computation runs in a wider type than the coordinates, so its own rounding stays far below
/// the tolerance (float: double, double: long double).
template <typename S>
struct WiderScalar
{
  using type = long double;
};
template <>
struct WiderScalar<float>
{
  using type = double;
};

/// Where two triangles meet, in A's frame: closest points (equal where they cross) and their squared distance.
template <typename S>
struct TriangleProximity
{
  bool reported = false;
  fcl::Vector3<S> on_a = fcl::Vector3<S>::Zero();
  fcl::Vector3<S> on_b = fcl::Vector3<S>::Zero();
};

/// The leaf test's tolerance (see the header comment) for vertices at most `size` in max norm (A's in A's frame,
/// B's in B's frame), poses translated by t1 and t2, and T as the traversal computed it.
template <typename S>
S leafTolerance(S size, const fcl::Vector3<S>& t1, const fcl::Vector3<S>& t2, const fcl::Vector3<S>& T)
{
  const S scale = t1.cwiseAbs().maxCoeff() + t2.cwiseAbs().maxCoeff() + T.cwiseAbs().maxCoeff() + 6 * size;
  return 32 * std::numeric_limits<S>::epsilon() * scale;
}

/// The largest absolute coordinate of a triangle's vertices.
template <typename S>
S largestCoordinate(const fcl::Vector3<S> v[3])
{
  static_assert(sizeof(fcl::Vector3<S>) == 3 * sizeof(S), "three vertices are nine consecutive coordinates");
  return Eigen::Map<const Eigen::Array<S, 9, 1>>(v[0].data()).abs().maxCoeff();
}

/// The leaf test's tolerance for triangles p (A's frame) and q (B's frame).
template <typename S>
S triangleTolerance(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q[3], const fcl::Vector3<S>& t1,
                    const fcl::Vector3<S>& t2, const fcl::Vector3<S>& T)
{
  return leafTolerance<S>(std::max(largestCoordinate(p), largestCoordinate(q)), t1, t2, T);
}

namespace detail {

template <typename W>
using Vec3 = Eigen::Matrix<W, 3, 1>;

/// Running minimum of squared distances between a point of A and a point of B.
template <typename W>
struct ClosestSoFar
{
  W sq_distance = std::numeric_limits<W>::infinity();
  Vec3<W> on_a, on_b;
  void offer(const Vec3<W>& a, const Vec3<W>& b)
  {
    const W d = (a - b).squaredNorm();
    if (d < sq_distance)
    {
      sq_distance = d;
      on_a = a;
      on_b = b;
    }
  }
};

/// Point of segment [a, b] (possibly a point) closest to x: the clamped projection, stable for any length.
template <typename W>
Vec3<W> closestOnSegment(const Vec3<W>& a, const Vec3<W>& b, const Vec3<W>& x)
{
  const Vec3<W> d = b - a;
  const W dd = d.squaredNorm();
  if (!(dd > 0)) return a;
  const W t = std::clamp((x - a).dot(d) / dd, W(0), W(1));
  return a + t * d;
}

/// Closest points of segments [p0, p1] and [q0, q1]: the four endpoint-to-segment candidates, and the two lines'
/// closest points when both fall inside. Every candidate is a feasible pair. The lines' solution minimises
/// |(r + s d1) x d2| = |A + s B| over s: for lines that cross within the segments A is nearly -s B, so the computed
/// distance is off by a few roundings of the segments' coordinates at any angle between them, where the normal
/// equations (denominator |d1|^2 |d2|^2 - (d1.d2)^2) lose precision as the square of the angle shrinks.
template <typename W>
void segmentSegment(const Vec3<W>& p0, const Vec3<W>& p1, const Vec3<W>& q0, const Vec3<W>& q1, ClosestSoFar<W>& best)
{
  best.offer(p0, closestOnSegment(q0, q1, p0));
  best.offer(p1, closestOnSegment(q0, q1, p1));
  best.offer(closestOnSegment(p0, p1, q0), q0);
  best.offer(closestOnSegment(p0, p1, q1), q1);
  const Vec3<W> d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const Vec3<W> A = r.cross(d2), B = d1.cross(d2);
  const W bb = B.squaredNorm();
  if (!(bb > 0)) return;
  const W s = -A.dot(B) / bb;
  if (!(s > 0 && s < 1)) return;
  const Vec3<W> on_p = p0 + s * d1;
  const W t = (on_p - q0).dot(d2) / d2.squaredNorm();
  if (t > 0 && t < 1) best.offer(on_p, q0 + t * d2);
}

/// Whether x, a point of the plane of (v0, v1, v2) with normal n, lies in the closed triangle: the three edge
/// signs, and within margin of the triangle's box. The signs alone are ill-conditioned beyond a sliver's sharp tips
/// (every edge line passes within rounding of such a point), where they can call a point inside that lies as far
/// beyond the tip as rounding times the aspect ratio; there the point leaves the box by a third of that distance,
/// so the box settles it, and elsewhere a wrong sign means a point within rounding of the triangle.
template <typename W>
bool insideTriangle(const Vec3<W> v[3], const Vec3<W>& n, const Vec3<W>& x, W margin)
{
  const Vec3<W> lo = v[0].cwiseMin(v[1]).cwiseMin(v[2]), hi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
  if (((x - lo).array() < -margin).any() || ((x - hi).array() > margin).any()) return false;
  for (int i = 0; i < 3; ++i)
    if ((v[(i + 1) % 3] - v[i]).cross(x - v[i]).dot(n) < 0) return false;
  return true;
}

/// Squared distance between closed triangles a and b (each possibly degenerate), with early exit once it is
/// known to be at most stop. Two closed triangles meet iff an edge of one meets the other; apart, their distance
/// is realized edge-to-edge or vertex-to-interior. So: edges crossing the other's interior, the nine
/// edge-edge distances, the six vertex-to-interior distances; a zero-area triangle is just its edges.
template <typename W>
ClosestSoFar<W> triangleDistance(const Vec3<W> a[3], const Vec3<W> b[3], W stop)
{
  // insideTriangle's box must admit a vertex's projection that rounding moved off a triangle whose box is flat (a
  // triangle parallel to a coordinate plane): the projection's few roundings of the largest coordinate.
  W scale = 0;
  for (int i = 0; i < 3; ++i) scale = std::max({scale, a[i].cwiseAbs().maxCoeff(), b[i].cwiseAbs().maxCoeff()});
  const W margin = std::max(std::sqrt(stop), 16 * std::numeric_limits<W>::epsilon() * scale);
  ClosestSoFar<W> best;
  const Vec3<W> na = (a[1] - a[0]).cross(a[2] - a[0]), nb = (b[1] - b[0]).cross(b[2] - b[0]);
  const bool a_has_area = na.squaredNorm() > 0, b_has_area = nb.squaredNorm() > 0;
  // An edge of `from` through the interior of triangle `to` (normal n): the crossing point is on both.
  const auto crossing = [&](const Vec3<W> from[3], const Vec3<W> to[3], const Vec3<W>& n) {
    for (int i = 0; i < 3; ++i)
    {
      const Vec3<W>&s0 = from[i], &s1 = from[(i + 1) % 3];
      const W d0 = n.dot(s0 - to[0]), d1 = n.dot(s1 - to[0]);
      if ((d0 > 0 && d1 > 0) || (d0 < 0 && d1 < 0) || (d0 == 0 && d1 == 0)) continue;  // coplanar: edges decide
      const Vec3<W> x = s0 + (d0 / (d0 - d1)) * (s1 - s0);
      if (insideTriangle(to, n, x, margin))
      {
        best.offer(x, x);
        return true;
      }
    }
    return false;
  };
  if (b_has_area && crossing(a, b, nb)) return best;
  if (a_has_area && crossing(b, a, na)) return best;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      segmentSegment(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], best);
      if (best.sq_distance <= stop) return best;
    }
  // A vertex above the interior of the other triangle: its projection.
  const auto aboveInterior = [](const Vec3<W>& x, const Vec3<W> to[3], const Vec3<W>& n) -> Vec3<W> {
    return x - n * (n.dot(x - to[0]) / n.squaredNorm());
  };
  for (int i = 0; i < 3; ++i)
  {
    if (b_has_area)
    {
      const Vec3<W> y = aboveInterior(a[i], b, nb);
      if (insideTriangle(b, nb, y, margin)) best.offer(a[i], y);
    }
    if (a_has_area)
    {
      const Vec3<W> y = aboveInterior(b[i], a, na);
      if (insideTriangle(a, na, y, margin)) best.offer(y, b[i]);
    }
  }
  return best;
}

/// Whether some axis of FCL's separating-axis set (the two normals, the nine edge-edge crosses, the six in-plane
/// edge normals) separates the triangles by more than tolerance, counting the projections' rounding: a cheap
/// proof that the exact distance exceeds tolerance, which settles most leaf pairs without triangleDistance.
template <typename S>
bool separatedBeyond(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q[3], S tolerance)
{
  const S size = std::max(largestCoordinate(p), largestCoordinate(q));
  // |fl(a.x) - a.x| <= 3 u |a|_1 |x|_inf per projection; the gap of two, with room to spare.
  const S slack = tolerance + 4 * std::numeric_limits<S>::epsilon() * size;
  const auto separates = [&](const fcl::Vector3<S>& axis) {
    S p_min = axis.dot(p[0]), p_max = p_min, q_min = axis.dot(q[0]), q_max = q_min;
    for (int i = 1; i < 3; ++i)
    {
      const S pi = axis.dot(p[i]), qi = axis.dot(q[i]);
      p_min = std::min(p_min, pi);
      p_max = std::max(p_max, pi);
      q_min = std::min(q_min, qi);
      q_max = std::max(q_max, qi);
    }
    // The 1-norm bounds the 2-norm: a gap above slack |axis|_1 is a distance above tolerance.
    const S margin = slack * axis.template lpNorm<1>();
    return q_min - p_max > margin || p_min - q_max > margin;
  };
  const fcl::Vector3<S> e[3] = {p[1] - p[0], p[2] - p[1], p[0] - p[2]};
  const fcl::Vector3<S> f[3] = {q[1] - q[0], q[2] - q[1], q[0] - q[2]};
  const fcl::Vector3<S> n = e[0].cross(e[1]), m = f[0].cross(f[1]);
  if (separates(n) || separates(m)) return true;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (separates(e[i].cross(f[j]))) return true;
  for (int i = 0; i < 3; ++i)
    if (separates(e[i].cross(n)) || separates(f[i].cross(m))) return true;
  return false;
}

/// Triple products r . (v x w) of differences of the given coordinates, with the rounding bounded once per pair (a
/// static filter): with r's coordinates at most `reach` in magnitude, v's at most a and w's at most b, the computed
/// cross product is within 8u a b of the exact one per component (u = eps / 2: each difference, product and sum
/// rounds once) and the computed triple product within 48u reach a b (to first order). The bounds below double
/// that, which also covers the rounding of the bounds and of the comparisons the certificates make with them, and
/// add underflow's absolute error. NaN and overflow make every certificate fail (its comparisons are false).
template <typename S>
struct CertainAxis
{
  CertainAxis(const fcl::Vector3<S>& v, const fcl::Vector3<S>& w, S reach, S a, S b)
    : m(v.cross(w)), ab(a * b),
      error(48 * std::numeric_limits<S>::epsilon() * reach * ab + 8 * (reach + 1) * std::numeric_limits<S>::denorm_min())
  {
  }
  /// r . (v x w) as computed, within `error` of the exact value.
  S value(const fcl::Vector3<S>& r) const { return r.dot(m); }
  /// An upper bound on |v x w| (exact): |m|_1 plus its rounding.
  S length() const
  {
    return m.template lpNorm<1>() + 24 * std::numeric_limits<S>::epsilon() * ab + 6 * std::numeric_limits<S>::denorm_min();
  }
  fcl::Vector3<S> m;
  S ab;
  S error;  ///< bound on the error of value(r) for any difference r within the reach
};

/// The vertices v of one triangle against the plane through o (a vertex of the other) with normal n: the
/// computed (v_i - o) . n.
template <typename S>
struct PlaneSides
{
  PlaneSides(const CertainAxis<S>& n, const fcl::Vector3<S> v[3], const fcl::Vector3<S>& o)
    : value{n.value(v[0] - o), n.value(v[1] - o), n.value(v[2] - o)}, error(n.error)
  {
  }
  /// Whether the values all exceed margin on one side (margin covering their error: the plane separates the
  /// triangles by more than margin - error, times |n|).
  bool beyond(S margin) const
  {
    return (value[0] > margin && value[1] > margin && value[2] > margin) ||
           (value[0] < -margin && value[1] < -margin && value[2] < -margin);
  }
  /// Whether the plane certainly has one vertex on one side and two on the other.
  bool straddled() const
  {
    const bool above = value[0] > 0;
    return std::abs(value[0]) > error && std::abs(value[1]) > error && std::abs(value[2]) > error &&
           !(above == (value[1] > 0) && above == (value[2] > 0));
  }
  /// The vertex alone on its side of a straddled plane.
  int lone() const
  {
    const bool above = value[0] > 0;
    return above == (value[1] > 0) ? 2 : above == (value[2] > 0) ? 1 : 0;
  }
  S value[3];
  S error;
};

enum class Certificate
{
  kNone,      ///< neither proved
  kApart,     ///< the exact distance exceeds the tolerance plus eps times the largest coordinate
  kCrossing,  ///< the triangles intersect exactly
};

/// A cheap certified verdict on p and q: apart or crossing (see Certificate), else kNone, every sign and gap
/// counted with its rounding (CertainAxis). A gap of eps times the largest coordinate beyond the tolerance puts
/// the distance computed in the wider type above the tolerance too.
///
/// First each plane: q's vertices all farther than the tolerance on one side of p's plane, or p's of q's, prove
/// the pair apart. Otherwise, where both triangles certainly straddle the other's plane (vertex a of p alone on side
/// s_a of q's plane, x of q alone on side s_x of p's), each crosses the planes' common line L in a segment, p's from
/// its edge a-u to edge a-u', q's from x-v to x-v', and the triangles intersect iff the segments overlap (the test
/// of Guigue and Devillers, 2003). Where edge a-u meets L at C and x-v at A, the triple product
/// g = (x - a) . ((u - a) x (v - x)) = ((u - a) x (v - x)) . (A - C) (moving x along its edge to A and a along
/// its edge to C changes nothing), A - C lies along L's direction d = n_p x n_q, and
/// ((u - a) x (v - x)) . d = -((u - a) . n_q) ((v - x) . n_p) has the sign -s_a s_x: so A comes after C along d
/// iff s_a s_x g < 0. Likewise (u - a) x (u' - a) = n_p orders p's ends: with (a, b, c) a cyclic order of p's
/// vertices, p's segment runs from its b edge to its c edge against d where s_a > 0 (along it where s_a < 0), and
/// q's, with (x, y, z) cyclic, from its y edge to its z edge along d where s_x > 0. The segments overlap iff p's
/// start is not after q's end and q's start not after p's end: two triple products, both with a certain sign
/// proving the crossing. One certainly of the wrong sign means the segments are apart along L, and
/// (u - a) x (v - x) is the axis that separates the triangles: its gap (both triangles' vertices projected, each
/// value certified) beyond the tolerance proves them apart. Any other configuration (touching, coplanar,
/// degenerate, an uncertain sign) gets kNone.
template <typename S>
Certificate certifyPair(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q[3], S tolerance)
{
  // Magnitudes: every edge of p within 2 e_max per coordinate (e_2 = e_1 - e_0), of q within 2 f_max, every
  // difference of a vertex of q and one of p within reach, every coordinate within |p_0| + reach.
  const fcl::Vector3<S> e[2] = {p[1] - p[0], p[2] - p[0]}, f[2] = {q[1] - q[0], q[2] - q[0]}, d = q[0] - p[0];
  const S e_max = e[0].cwiseAbs().cwiseMax(e[1].cwiseAbs()).maxCoeff();
  const S f_max = f[0].cwiseAbs().cwiseMax(f[1].cwiseAbs()).maxCoeff();
  const S reach = d.cwiseAbs().maxCoeff() + 2 * (e_max + f_max);
  const S slack = tolerance + std::numeric_limits<S>::epsilon() * (p[0].cwiseAbs().maxCoeff() + reach);

  const CertainAxis<S> normal_p(e[0], e[1], reach, e_max, e_max);
  const PlaneSides<S> q_sides(normal_p, q, p[0]);
  if (!q_sides.straddled())
    return q_sides.beyond(slack * normal_p.length() + normal_p.error) ? Certificate::kApart : Certificate::kNone;
  const CertainAxis<S> normal_q(f[0], f[1], reach, f_max, f_max);
  const PlaneSides<S> p_sides(normal_q, p, q[0]);
  if (!p_sides.straddled())
    return p_sides.beyond(slack * normal_q.length() + normal_q.error) ? Certificate::kApart : Certificate::kNone;
  static constexpr int kNext[3] = {1, 2, 0}, kLast[3] = {2, 0, 1};
  const int a = p_sides.lone(), x = q_sides.lone();
  const int s_a = p_sides.value[a] > 0 ? 1 : -1, s_x = q_sides.value[x] > 0 ? 1 : -1;
  // p's start not after q's end: s_a s_x g < 0 on (u, v) = (p's start, q's end); q's start not after p's end:
  // s_a s_x g > 0 on (p's end, q's start).
  const int p_ends[2] = {s_a > 0 ? kLast[a] : kNext[a], s_a > 0 ? kNext[a] : kLast[a]};
  const int q_ends[2] = {s_x > 0 ? kLast[x] : kNext[x], s_x > 0 ? kNext[x] : kLast[x]};
  const fcl::Vector3<S> r = q[x] - p[a];
  for (int k = 0; k < 2; ++k)
  {
    const int u = p_ends[k], v = q_ends[k], wanted = k == 0 ? -s_a * s_x : s_a * s_x;
    const CertainAxis<S> axis(p[u] - p[a], q[v] - q[x], reach, 2 * e_max, 2 * f_max);
    const S g = wanted * axis.value(r);
    if (g > axis.error) continue;  // this end overlaps
    if (!(g < -axis.error)) return Certificate::kNone;
    // Apart along L: projections on the axis relative to a, on q's side (-wanted): a and u at 0 exactly, x and v
    // at -g, the other two vertices.
    const S p_other = -wanted * axis.value(p[3 - a - u] - p[a]), q_other = -wanted * axis.value(q[3 - x - v] - p[a]);
    const S gap = slack * axis.length() + 2 * axis.error;
    const bool apart = -g > gap && q_other > gap && -g - p_other > gap && q_other - p_other > gap;
    return apart ? Certificate::kApart : Certificate::kNone;
  }
  return Certificate::kCrossing;
}

}  // namespace detail

/// Whether triangles p and q_in_a (B's vertices mapped into A's frame) are at most tolerance apart, with on_a and
/// on_b points of A and B that far apart (equal where the triangles cross); the distance is computed in the wider
/// type, after a separating axis has not proved it larger than tolerance.
template <typename S>
TriangleProximity<S> triangleProximity(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q_in_a[3], S tolerance)
{
  TriangleProximity<S> out;
  if (detail::separatedBeyond(p, q_in_a, tolerance)) return out;
  using W = typename WiderScalar<S>::type;
  const detail::Vec3<W> a[3] = {p[0].template cast<W>(), p[1].template cast<W>(), p[2].template cast<W>()};
  const detail::Vec3<W> b[3] = {q_in_a[0].template cast<W>(), q_in_a[1].template cast<W>(),
                                q_in_a[2].template cast<W>()};
  const W stop = W(tolerance) * W(tolerance);
  const detail::ClosestSoFar<W> best = detail::triangleDistance(a, b, stop);
  if (!(best.sq_distance <= stop)) return out;
  out.reported = true;
  out.on_a = best.on_a.template cast<S>();
  out.on_b = best.on_b.template cast<S>();
  return out;
}

/// The leaf test's verdict on p and q_in_a: reported iff their distance computed by triangleProximity is at most
/// tolerance. Most pairs are settled without it by detail::certifyPair: a pair it proves exactly intersecting has
/// that distance zero up to the wider type's rounding, one it proves apart has it above tolerance.
template <typename S>
bool trianglesWithin(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q_in_a[3], S tolerance)
{
  switch (detail::certifyPair(p, q_in_a, tolerance))
  {
    case detail::Certificate::kApart: return false;
    case detail::Certificate::kCrossing: return true;
    default: return triangleProximity(p, q_in_a, tolerance).reported;
  }
}

/// The leaf predicate exactly as the RS traversal runs it on triangle p of A and q of B (model coordinates):
/// q_in_a = R q + T (written out, the expression FCL's triangle test evaluates) and tolerance = triangleTolerance,
/// then trianglesWithin. Brute-force checks call this too, so that they and the tree decide every pair alike.
template <typename S>
bool leafReports(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q[3], const fcl::Matrix3<S>& R,
                 const fcl::Vector3<S>& T, const fcl::Vector3<S>& t1, const fcl::Vector3<S>& t2,
                 fcl::Vector3<S> q_in_a[3], S& tolerance)
{
  for (int i = 0; i < 3; ++i) q_in_a[i] = R * q[i] + T;
  tolerance = triangleTolerance<S>(p, q, t1, t2, T);
  return trianglesWithin(p, q_in_a, tolerance);
}

/// A contact for a reported pair where FCL's contact routine is undefined (a zero-area triangle: FCL reads an
/// uninitialised plane) or gives no point (touching within the tolerance): one point, midway between the
/// closest points; depth 0; normal, pointing from A to B, along on_b - on_a where they differ, else A's normal,
/// else minus B's normal, else A's x axis (two collinear or point triangles crossing). In A's frame.
template <typename S>
void degenerateContact(const fcl::Vector3<S> p[3], const fcl::Vector3<S> q_in_a[3], const TriangleProximity<S>& near,
                       fcl::Vector3<S>& point, fcl::Vector3<S>& normal)
{
  point = (near.on_a + near.on_b) / 2;
  const fcl::Vector3<S> candidates[3] = {near.on_b - near.on_a, (p[1] - p[0]).cross(p[2] - p[0]),
                                         -(q_in_a[1] - q_in_a[0]).cross(q_in_a[2] - q_in_a[0])};
  for (const auto& c : candidates)
  {
    const S norm = c.norm();
    if (norm > 0 && std::isfinite(norm))
    {
      normal = c / norm;
      return;
    }
  }
  normal = fcl::Vector3<S>::UnitX();
}

/// Drop-in replacement for fcl::detail::meshCollisionOrientedNodeLeafTesting (same arguments, same statistics
/// and cost sources) deciding with leafReports. Contacts: FCL's own (Intersect::intersect_Triangle with
/// contact outputs, converted to the world frame exactly as FCL's leaf test does) when both triangles have a
/// plane FCL can build and FCL's routine gives points; otherwise one degenerateContact.
template <typename BV>
void meshTriangleLeafTesting(int b1, int b2, const fcl::BVHModel<BV>* model1, const fcl::BVHModel<BV>* model2,
                             fcl::Vector3<typename BV::S>* vertices1, fcl::Vector3<typename BV::S>* vertices2,
                             fcl::Triangle* tri_indices1, fcl::Triangle* tri_indices2,
                             const fcl::Matrix3<typename BV::S>& R, const fcl::Vector3<typename BV::S>& T,
                             const fcl::Transform3<typename BV::S>& tf1, const fcl::Transform3<typename BV::S>& tf2,
                             bool enable_statistics, typename BV::S cost_density, int& num_leaf_tests,
                             const fcl::CollisionRequest<typename BV::S>& request,
                             fcl::CollisionResult<typename BV::S>& result)
{
  using S = typename BV::S;
  if (enable_statistics) num_leaf_tests++;
  // isOccupied() and isFree() written out: fcl::CollisionGeometry<double>'s members are out of line in libfcl.so.
  const auto occupied_geometry = [](const fcl::BVHModel<BV>* m) { return m->cost_density >= m->threshold_occupied; };
  const auto free_geometry = [](const fcl::BVHModel<BV>* m) { return m->cost_density <= m->threshold_free; };
  const bool occupied = occupied_geometry(model1) && occupied_geometry(model2);
  if (!occupied && !((!free_geometry(model1) && !free_geometry(model2)) && request.enable_cost)) return;

  const int id1 = primitiveId(model1->getBV(b1)), id2 = primitiveId(model2->getBV(b2));
  const std::array<fcl::Vector3<S>, 3> p_vertices = triangleVertices(vertices1, tri_indices1[id1]);
  const std::array<fcl::Vector3<S>, 3> q_vertices = triangleVertices(vertices2, tri_indices2[id2]);
  const fcl::Vector3<S>* p = p_vertices.data();
  const fcl::Vector3<S>* q = q_vertices.data();
  fcl::Vector3<S> q_in_a[3];  // FCL's contacts below see the same numbers
  S tolerance;
  if (!leafReports<S>(p, q, R, T, tf1.translation(), tf2.translation(), q_in_a, tolerance)) return;

  if (occupied && request.enable_contact)
  {
    const auto hasPlane = [](const fcl::Vector3<S> v[3]) { return (v[1] - v[0]).cross(v[2] - v[0]).squaredNorm() > 0; };
    fcl::Vector3<S> points[2], normal;
    S depth = 0;
    unsigned int n_points = 0;
    // FCL builds both planes from these cross products and reads an uninitialised one where it is zero; a
    // triangle collinear in its own frame gets a plane from rounding noise alone in A's: both are degenerate.
    if (!(hasPlane(p) && hasPlane(q) && hasPlane(q_in_a) &&
          fcl::detail::Intersect<S>::intersect_Triangle(p[0], p[1], p[2], q_in_a[0], q_in_a[1], q_in_a[2], points,
                                                        &n_points, &depth, &normal) &&
          n_points > 0))
    {
      n_points = 1;
      depth = 0;
      degenerateContact(p, q_in_a, triangleProximity(p, q_in_a, tolerance), points[0], normal);
    }
    for (unsigned int i = 0; i < n_points && result.numContacts() < request.num_max_contacts; ++i)
      result.addContact(fcl::Contact<S>(model1, model2, id1, id2, tf1 * points[i], tf1.linear() * normal, depth));
  }
  else if (occupied && result.numContacts() < request.num_max_contacts)
  {
    result.addContact(fcl::Contact<S>(model1, model2, id1, id2));
  }

  if (request.enable_cost)
  {
    fcl::AABB<S> overlap_part;
    fcl::AABB<S>(tf1 * p[0], tf1 * p[1], tf1 * p[2]).overlap(fcl::AABB<S>(tf2 * q[0], tf2 * q[1], tf2 * q[2]), overlap_part);
    result.addCostSource(fcl::CostSource<S>(overlap_part, cost_density), request.num_max_cost_sources);
  }
}

}  // namespace fcl_rs

#endif
