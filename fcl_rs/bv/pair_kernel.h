// The pair kernel of RS volumes: the one rounding bound of every pair test, the frames a traversal moves once per
// node and query (MovedFrame, BoxedFrame), the pair frame (PairFrame), the boxed and exact overlap tests, the
// triangle filters of leaf-node pairs and the slab distance bound. Internal: included by fcl_rs/bv/rs.h after the
// volume's own definitions (rs-inl.h), which read against the paper.
#ifndef FCL_RS_PAIR_KERNEL_H
#define FCL_RS_PAIR_KERNEL_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

#include "fcl_rs/bv/lanes.h"
#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

namespace detail {

/// The principal box of a volume: centre and half extents in its frame.
template <typename S>
struct Box
{
  Box() = default;
  /// Computed in S from any volume's stored slabs (boxedOverlap works in the storage precision).
  template <typename VolumeS>
  explicit Box(const RS<VolumeS>& b)
    : c((b.lo.template head<3>().template cast<S>() + b.hi.template head<3>().template cast<S>()) / 2),
      h((b.hi.template head<3>().template cast<S>() - b.lo.template head<3>().template cast<S>()) / 2)
  {
  }
  /// How far the box reaches from its frame's origin along an axis; every slab value of the volume is at most
  /// sqrt(2) times this (the polytope lies in the box), so it scales the rounding of anything computed from it.
  S reach() const { return (c.cwiseAbs() + h).maxCoeff(); }
  fcl::Vector3<S> c, h;
};

/// The one rounding bound of every pair test (overlap variants, distance bounds, mesh-shape bounds): an upper
/// bound on the error of a comparison made in b1's frame between quantities derived from two volumes.
/// `offsets` is the L1 size of the translations the relative frame is built from (|R o2|_1 + |T|_1 + |o1|_1),
/// `reaches` the sum of both boxes' reach(). With u = eps:
///  - M = A1^T (R A2): two nested 3-term dot products of entries <= 1, plus the stored frames' departure from
///    orthonormality at S's precision (the fits pad for the rounding of A^T x, not for A^-T = A; a frame stored
///    narrower than S departs further, storageBound below): <= 16u per entry, so a point
///    y2 of b2 (|y2|_1 <= 3 reach2) moves by <= 48u reach2, and a vector v by <= 16u |v|_1;
///  - b2's box centre in b1's frame, A1^T ((R o2 + T) + (R A2) c2 - o1): the translations carry <= 8u offsets
///    per coordinate, the centre (|c2|_1 <= 3 reach2) <= 40u reach2; d = centre2 - c1 is within
///    8u offsets + 42u reaches, and so is t = centre2 - M c2 within 8u offsets + 102u reaches;
///  - face axes of b1 (|d_i| against h1_i + sum_c |M_ic| h2_c, sum_c h2_c <= 3 reach2): <= 8u offsets + 102u
///    reaches. Face axes of b2 (e = -M^T d, against h2 + sum_r |M_ri| h1_r): they decide a pair only when no axis
///    of b1 does, so |d|_1 <= 3 reach1 + 3 sqrt(3) reach2 (+ tol), and e carries sqrt(3) times d's error plus
///    19u |d|_1: <= 14u offsets + 232u reaches with the radius;
///  - diagonals, compared sqrt(2) times (against sqrt(2) tol): a sum or difference of two of those coordinates,
///    radii that are L1 norms of sums of two rows or columns of M scaled by the half extents (<= 110u reaches),
///    slab middles (<= 12u reaches): <= 28u offsets + 466u reaches;
///  - supports, projections and corner coordinates (exact variants, distance bounds) are sums of <= 6 products
///    of values <= sqrt(2) times the reaches (|dir| <= 1): <= 12 sqrt(2) u (reach1 + reach2) on top of t or d.
///  (R A2, R o2 + T, b2's box, its moved centre, its diagonal slabs from the centre and |R o2|_1 + |T|_1 are
///  computed once per node and query, MovedFrame, by the same operations as per pair.)
/// First-order total <= 28u offsets + 466u reaches on the diagonals' sqrt(2) scale, <= 14u offsets + 232u
/// reaches elsewhere; the bound is at least 1.5 times that (sqrt(2) tol = 45u offsets + 724u reaches), and the
/// rest is of order u^2.
/// A query between posed objects adds the world frame's rounding to offsets: |t1|_1 + |t2|_1 of the poses.
/// Contacts are promised for the world-frame vertices as computed, fl(R1 p + t1) and fl(R2 q + t2), each
/// within u (|R p|_1 + |t|_1) of the exact pose per coordinate, which (R, T) in A's frame never sees: far
/// from the origin (|t| >> the meshes and T) that is the largest term, and without it grazing pairs that
/// touch in the world frame are culled. The leaf test's tolerance (narrowphase/triangle_intersection.h)
/// carries the same term.
/// Plus storageBound(reaches + separation): the same errors where they come from storing the volumes narrower
/// than S (a float frame's departure from orthonormality, slabs rounded outward one by one), 0 for RS<float>.
/// `separation` is |d|_1, the box centres' distance in b1's frame: M's storage error maps it into b2's frame (e =
/// -M^T d, centre1()). At S's precision the offsets cover it; at storage precision they would cost far-away
/// volumes all pruning, while the separation only costs volumes farther apart than their own size (overlapping
/// volumes have |d|_1 <= 3 reach1 + 3 sqrt(3) reach2; the distance bounds need it).
template <typename S>
S pairRoundingBound(S offsets, S reaches, S separation = 0)
{
  return 32 * eps<S>() * (offsets + 16 * reaches) + storageBound(reaches + separation);
}

/// pairRoundingBound of a test that computes in the storage precision C = RS<S>::Stored what PairFrame computes in
/// S (boxedOverlap): only delta, the vector from b1's frame origin to b2's moved box centre, is formed in S and
/// rounded to C. The derivation above holds at C's precision with delta's L1 size for the translations' offsets;
/// the error of delta itself is pairRoundingBound's in S. The bound's own rounding to C is far inside its margin.
template <typename S>
typename RS<S>::Stored storedPairRoundingBound(S offsets, S reaches, S separation, S delta_norm1)
{
  using C = typename RS<S>::Stored;
  S bound = pairRoundingBound<S>(offsets, reaches, separation);
  if constexpr (!std::is_same_v<C, S>) bound += 32 * S(eps<C>()) * (delta_norm1 + 16 * reaches);
  return C(bound);
}

/// A volume's six diagonal slabs in diagonalLanes' order: lo[0], hi[0] hold slabs 3-6, lo[1], hi[1] slabs 7 and 8.
template <typename S>
void diagonalSlabs(const RS<S>& b, Lanes lo[2], Lanes hi[2])
{
  using Map = Eigen::Map<const Lanes, Eigen::Unaligned>;
  lo[0] = Map(b.lo.data() + 3);
  hi[0] = Map(b.hi.data() + 3);
  lo[1] = Lanes(b.lo[7], b.lo[8], 0.0f, 0.0f);
  hi[1] = Lanes(b.hi[7], b.hi[8], 0.0f, 0.0f);
}

/// The part of the pair kernel that depends on b2 and the query only: b2's frame and box centre moved by (R, T)
/// into b1's model coordinates, and b2's principal box and diagonal slabs measured from the box centre. A
/// traversal computes it once per visited node of its second tree and reuses it for every node of the first
/// tree that node meets.
template <typename S>
struct MovedFrame
{
  /// Uninitialised, for arrays filled as a traversal reaches their nodes.
  MovedFrame() = default;
  /// world_offsets: |t1|_1 + |t2|_1 of the query's poses (pairRoundingBound), 0 without poses.
  MovedFrame(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b2, S world_offsets = 0)
    : box(b2), reach(box.reach())
  {
    move(R, T, b2, world_offsets);
  }
  /// Sets the parts that depend on the motion (axis, origin, centre, offsets) to those of b2 moved by (R, T), in a
  /// frame already made for b2 (box and reach kept).
  void move(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b2, S world_offsets = 0)
  {
    axis.noalias() = R.lazyProduct(b2.axes());
    const OriginParts parts = movedOrigin(R, T, b2.origin, world_offsets);
    origin = parts.origin;
    centre = parts.centre;
    offsets = parts.offsets;
  }
  /// The parts of this frame that depend on b2's origin (origin, centre, offsets), as the constructor computes
  /// them for b2 with its origin at b2_origin (axes and slabs unchanged): the octree's cells of a split share
  /// their shape and differ in these only.
  struct OriginParts
  {
    fcl::Vector3<S> origin, centre;
    S offsets;
  };
  OriginParts movedOrigin(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const fcl::Vector3<S>& b2_origin,
                          S world_offsets) const
  {
    const fcl::Vector3<S> o2 = R * b2_origin;
    OriginParts parts;
    parts.origin = o2 + T;
    parts.centre.noalias() = axis * box.c + parts.origin;
    parts.offsets = o2.template lpNorm<1>() + T.template lpNorm<1>() + world_offsets;
    return parts;
  }
  fcl::Matrix3<S> axis;    ///< R A2
  fcl::Vector3<S> origin;  ///< R o2 + T
  Box<S> box;              ///< b2's principal box, in b2's frame
  fcl::Vector3<S> centre;  ///< the box's centre moved: R (o2 + A2 c2) + T
  S offsets;               ///< |R o2|_1 + |T|_1 (+ world_offsets), the translations' part of pairRoundingBound's offsets
  S reach;                 ///< box.reach()
};

/// MovedFrame plus what boxedOverlap reads of b2, in float lanes: collision traversals build it once per visited
/// node and query; distance traversals, which never run the boxed test, keep the plain MovedFrame.
template <typename S>
struct BoxedFrame : MovedFrame<S>
{
  BoxedFrame() = default;
  BoxedFrame(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b2, S world_offsets = 0)
    : MovedFrame<S>(R, T, b2, world_offsets)
  {
    setAxisRows();
    const Box<S>& box = this->box;
    half_extents = Lanes(float(box.h[0]), float(box.h[1]), float(box.h[2]), 0.0f);
    Lanes lo[2], hi[2], centre_diagonal[2];
    diagonalSlabs(b2, lo, hi);
    diagonalLanes(Lanes(float(box.c[0]), float(box.c[1]), float(box.c[2]), 0.0f), centre_diagonal[0], centre_diagonal[1]);
    const float scale = float(M_SQRT1_2);
    for (int h = 0; h < 2; ++h)
    {
      diagonal_mid[h] = (lo[h] + hi[h]) * scale - centre_diagonal[h];
      diagonal_half[h] = (hi[h] - lo[h]) * scale;
    }
  }
  /// MovedFrame::move, in a frame made for b2 by any motion: the lanes of b2's box and slabs do not depend on it.
  void move(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b2, S world_offsets = 0)
  {
    MovedFrame<S>::move(R, T, b2, world_offsets);
    setAxisRows();
  }
  /// The rows of axis, box.h, and b2's six diagonal slabs from the box centre, times sqrt(2) (the middle and the
  /// half width of each interval, in diagonalLanes' order).
  Lanes axis_rows[3];
  Lanes half_extents;
  Lanes diagonal_mid[2], diagonal_half[2];

private:
  void setAxisRows()
  {
    const fcl::Matrix3<S>& axis = this->axis;
    for (int k = 0; k < 3; ++k) axis_rows[k] = Lanes(float(axis(k, 0)), float(axis(k, 1)), float(axis(k, 2)), 0.0f);
  }
};

/// The pair kernel: b2 expressed in b1's frame (y1 = M y2 + t), both principal boxes, b2's box centre in b1's
/// frame, and the rounding bound of tests made there.
template <typename S>
struct PairFrame
{
  fcl::Matrix3<S> M;
  Box<S> box1, box2;
  fcl::Vector3<S> centre2;  ///< b2's box centre in b1's frame
  S tol;

  PairFrame(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2)
    : PairFrame(MovedFrame<S>(R, T, b2), b1)
  {
  }

  /// moved2 = MovedFrame(R, T, b2).
  PairFrame(const MovedFrame<S>& moved2, const RS<S>& b1) : box1(b1), box2(moved2.box)
  {
    const fcl::Matrix3<S> A1 = b1.axes();
    M.noalias() = A1.transpose().lazyProduct(moved2.axis);
    centre2.noalias() = A1.transpose() * (moved2.centre - b1.origin);
    tol = pairRoundingBound<S>(moved2.offsets + b1.origin.template lpNorm<1>(), box1.reach() + moved2.reach,
                               storageEps<S>() > 0 ? (centre2 - box1.c).template lpNorm<1>() : S(0));
  }

  /// b2's frame origin in b1's frame: y1 = M y2 + t maps b2's frame into b1's.
  fcl::Vector3<S> t() const { return centre2 - M * box2.c; }
  /// b1's box centre in b2's frame.
  fcl::Vector3<S> centre1() const { return M.transpose() * (box1.c - centre2) + box2.c; }
};

/// The vertex of b farthest along dir (both in b's frame): the one support(dir) found.
template <typename S>
fcl::Vector3<S> extremeVertex(const RS<S>& b, const fcl::Vector3<S>& dir)
{
  return SupportCorner<S>(b, dir).vertex();
}

/// One volume's principal box projected on the other volume's nine slab directions: each direction
/// expressed in the projected volume's frame, and the box's interval mid +- radius along it.
template <typename S>
struct ProjectedBox
{
  /// rows: the other volume's principal axes in this volume's frame; centre: this box's centre in
  /// the other volume's frame.
  ProjectedBox(const fcl::Matrix3<S>& rows, const fcl::Vector3<S>& centre, const Box<S>& box)
  {
    for (int k = 0; k < kNumSlabs; ++k)
    {
      dir[k] = slabOfRows(rows, k);
      mid[k] = projectOnSlab(centre, k);
      radius[k] = dir[k].cwiseAbs().dot(box.h);
    }
  }
  fcl::Vector3<S> dir[kNumSlabs];
  S mid[kNumSlabs];
  S radius[kNumSlabs];
};

/// Gap between [lo, hi] and volume b (box c, projection p) along p's direction k; positive means
/// separated. An exact support is computed only on a side where the box sticks out past the
/// interval, since only there can the polytope be apart; elsewhere the box bound is as good.
template <typename S>
S slabGap(S lo, S hi, const RS<S>& b, const Box<S>& box, const ProjectedBox<S>& p, int k)
{
  const fcl::Vector3<S>& e = p.dir[k];
  const S low_box = p.mid[k] - p.radius[k], high_box = p.mid[k] + p.radius[k];
  const S shift = p.mid[k] - e.dot(box.c);  // projection of b's frame origin
  const S lowest = low_box > hi || high_box <= hi ? low_box : shift - b.support(-e);
  const S highest = high_box < lo || low_box >= lo ? high_box : shift + b.support(e);
  return std::max(lowest - hi, lo - highest);
}

}  // namespace detail

namespace detail {

/// b1's side of the boxed test against a volume whose moved frame has axis rows `axis_rows` (BoxedFrame's, R A2):
/// M's rows and columns, b1's frame and box, and b1's share of the rounding bound. PairFrame's arithmetic in float
/// lanes, reading b1 as stored (no conversions); lane i of a 3-vector is coordinate i, unused lanes are 0 or never
/// compared.
template <typename S>
struct BoxedAxes
{
  static_assert(std::is_same_v<typename RS<S>::Stored, float>, "volumes are stored in float");
  BoxedAxes(const Lanes axis_rows[3], const RS<S>& b1)
    : origin(b1.origin), origin_norm(b1.origin.template lpNorm<1>())
  {
    using Map = Eigen::Map<const Lanes, Eigen::Unaligned>;
    // Columns u0, u1, u2; the last column's load reads one float past the frame (the next member), into a lane
    // that only the unused fourth row of a_rows receives.
    const float* A1 = b1.axis.data();
    // Rows of M = A1^T (R A2) (lane c: b2's axis c), then its columns (lane i: b1's axis i).
    for (int i = 0; i < 3; ++i)
      m[i] = A1[3 * i] * axis_rows[0] + A1[3 * i + 1] * axis_rows[1] + A1[3 * i + 2] * axis_rows[2];
    transpose3(m[0], m[1], m[2], w);
    transpose3(Map(A1), Map(A1 + 3), Map(A1 + 6), a_rows);
    const Lanes lo1 = Map(b1.lo.data()), hi1 = Map(b1.hi.data());  // lane 3 holds the first diagonal: unused
    c1 = (lo1 + hi1) * 0.5f;
    h1 = (hi1 - lo1) * 0.5f;
    reach = S((c1.abs() + h1).template head<3>().maxCoeff());
  }
  Lanes m[3], w[3], a_rows[3];
  Lanes c1, h1;  ///< b1's box
  fcl::Vector3<S> origin;
  S origin_norm, reach;  ///< |o1|_1 and the box's reach(), pairRoundingBound's terms of b1
};

/// b1's side of the boxed test's diagonals (BoxedAxes'): b1's radius sum_i |M_ic +- M_id| h1_i along b2's
/// diagonals, |M_ic +- M_jc| (b2's box reaches their sum weighted by h2 along b1's diagonal (i, j)), and b1's
/// diagonal slabs' middles and half widths, all sqrt(2) times.
template <typename S>
struct BoxedDiagonals
{
  BoxedDiagonals(const BoxedAxes<S>& a, const RS<S>& b1)
  {
    const float scale = float(M_SQRT1_2);
    Lanes diag[2];
    radius1[0] = radius1[1] = Lanes::Zero();
    for (int c = 0; c < 3; ++c)
    {
      diagonalLanes(a.w[c], diag[0], diag[1]);
      for (int h = 0; h < 2; ++h) w_diagonal[c][h] = diag[h].abs();
      diagonalLanes(a.m[c], diag[0], diag[1]);
      for (int h = 0; h < 2; ++h) radius1[h] += diag[h].abs() * a.h1[c];
    }
    Lanes lo[2], hi[2];
    diagonalSlabs(b1, lo, hi);
    for (int h = 0; h < 2; ++h)
    {
      mid1[h] = (lo[h] + hi[h]) * scale;
      half1[h] = (hi[h] - lo[h]) * scale;
    }
  }
  Lanes radius1[2], w_diagonal[3][2], mid1[2], half1[2];
};

/// b1's side of the boxed test computed for one pair: the diagonals' part only when the pair reaches them.
template <typename S>
struct FreshBoxedNode
{
  FreshBoxedNode(const Lanes axis_rows[3], const RS<S>& b1) : a(axis_rows, b1), b1(b1) {}
  const BoxedAxes<S>& axes() const { return a; }
  BoxedDiagonals<S> diagonals() const { return BoxedDiagonals<S>(a, b1); }
  BoxedAxes<S> a;
  const RS<S>& b1;
};

/// b1's side of the boxed test kept for every volume moved by the same axes (an octree's cells share the octree's
/// frame): a traversal computes it once per node of the first tree and query; the diagonals' part when first asked.
template <typename S>
class BoxedNode
{
public:
  BoxedNode(const Lanes axis_rows[3], const RS<S>& b1) : a_(axis_rows, b1), b1_(&b1) {}
  const BoxedAxes<S>& axes() const { return a_; }
  const BoxedDiagonals<S>& diagonals() const
  {
    if (!diagonals_) diagonals_.emplace(a_, *b1_);
    return *diagonals_;
  }

private:
  BoxedAxes<S> a_;
  const RS<S>* b1_;
  mutable std::optional<BoxedDiagonals<S>> diagonals_;
};

/// The boxed test (OverlapTest::kBoxed): each volume's nine slabs against the other's principal box, measured
/// from the box centres (|middle of the box - middle of the slab| > radius + half width means apart). Each
/// volume's three face axes come first with one exit (most separated pairs end there, as in an OBB test); the
/// twelve diagonals, which every overlapping pair reaches, have no branch. They are compared sqrt(2) times (a
/// diagonal is (u_i +- u_j) / sqrt(2)).
/// b1's side comes from `node` (FreshBoxedNode or BoxedNode, made with moved2's axis rows); b2 is `moved2` with
/// its box centre moved to `centre2_model` and its offsets `offsets2` (moved2's own, or those of a volume of the
/// same shape and axes elsewhere: an octree's cells). Inlined by force, so that b1's side computed for the pair
/// stays in registers.
template <typename S, typename Node>
__attribute__((always_inline)) inline bool boxedOverlap(const Node& node, const BoxedFrame<S>& moved2,
                                                        const fcl::Vector3<S>& centre2_model, S offsets2)
{
  const BoxedAxes<S>& a = node.axes();
  const fcl::Vector3<S> delta = centre2_model - a.origin;  // in S: both may be far from the model origin
  const Lanes centre2 = float(delta[0]) * a.a_rows[0] + float(delta[1]) * a.a_rows[1] + float(delta[2]) * a.a_rows[2];
  const Lanes& h1 = a.h1;
  const Lanes& h2 = moved2.half_extents;
  const Lanes d = centre2 - a.c1;  // from b1's box centre to b2's, b1's frame
  const float tol = storedPairRoundingBound<S>(offsets2 + a.origin_norm, a.reach + moved2.reach,
                                               S(d.abs().template head<3>().sum()), delta.template lpNorm<1>());
  // b2's box reaches sum_c |M_ic| h2_c along b1's axis i; b1's box reaches sum_i |M_ic| h1_i along b2's axis c.
  const Lanes gap1 = d.abs() - (a.w[0].abs() * h2[0] + a.w[1].abs() * h2[1] + a.w[2].abs() * h2[2]) - h1;
  if (gap1.template head<3>().maxCoeff() > tol) return false;
  const Lanes e = -(d[0] * a.m[0] + d[1] * a.m[1] + d[2] * a.m[2]);  // from b2's box centre to b1's, b2's frame
  const Lanes gap2 = e.abs() - (a.m[0].abs() * h1[0] + a.m[1].abs() * h1[1] + a.m[2].abs() * h1[2]) - h2;
  if (gap2.template head<3>().maxCoeff() > tol) return false;
  // The diagonals, sqrt(2) times: a box's reach along b1's diagonal (i, j) is sum_c |M_ic +- M_jc| h2_c, along
  // b2's sum_i |M_ic +- M_id| h1_i. b2's slabs are measured from its box centre (MovedFrame), b1's from its frame
  // origin, as centre2. Unused lanes give 0 - 0 - 0, never above the tolerance.
  const auto& dg = node.diagonals();
  Lanes radius2[2] = {Lanes::Zero(), Lanes::Zero()};
  for (int c = 0; c < 3; ++c)
    for (int h = 0; h < 2; ++h) radius2[h] += dg.w_diagonal[c][h] * h2[c];
  Lanes centre_diagonal[2], e_diagonal[2];
  diagonalLanes(centre2, centre_diagonal[0], centre_diagonal[1]);
  diagonalLanes(e, e_diagonal[0], e_diagonal[1]);
  Lanes worst = Lanes::Constant(-std::numeric_limits<float>::max());
  for (int h = 0; h < 2; ++h)
  {
    const Lanes gap_of_b1 = (centre_diagonal[h] - dg.mid1[h]).abs() - dg.half1[h] - radius2[h];
    const Lanes gap_of_b2 = (e_diagonal[h] - moved2.diagonal_mid[h]).abs() - moved2.diagonal_half[h] - dg.radius1[h];
    worst = worst.max(gap_of_b1).max(gap_of_b2);
  }
  return !(worst.maxCoeff() > float(M_SQRT2) * tol);
}

/// The boxed test of b1 and b2 moved into b1's coordinates (moved2 = BoxedFrame(R, T, b2)).
template <typename S>
bool boxedOverlap(const BoxedFrame<S>& moved2, const RS<S>& b1)
{
  return boxedOverlap(FreshBoxedNode<S>(moved2.axis_rows, b1), moved2, moved2.centre, moved2.offsets);
}

/// Whether a triangle, its vertices y in b's frame coordinates, may meet b: its interval along each of b's nine
/// slab directions meets the slab widened by tol. The face axes come first with one exit; the diagonals are
/// compared sqrt(2) times, as in boxedOverlap.
/// Rounding (triangleOverlap's tol is pairRoundingBound of the offsets and reaches named there; u = eps): the test
/// can only go wrong for a triangle that meets b (or comes within the leaf test's tolerance of a triangle in it),
/// and then every vertex lies within the triangle's diameter of a point of b's box, so |y_v|_1 and the vertex's
/// L1 distance from b's frame origin are <= 3 reach_b + 6 reach_leaf <= 6 reaches. A coordinate of y_v is a
/// 3-term dot product of a stored (or moved) axis, entries within 16u of an orthonormal frame as in
/// pairRoundingBound, with the vertex minus the frame origin: <= 19u * 6 reaches from the product and the
/// subtraction, plus sqrt(3) times the moved origin's (or R q + T's) error, 4u per coordinate of the offsets:
/// <= 7u offsets + 114u reaches. The diagonals add two of them and round lo, hi * sqrt(2) (<= 2u reaches): <= 14u
/// offsets + 232u reaches on the sqrt(2) scale. Both fit in the first-order bound pairRoundingBound already
/// carries with its margin (14u offsets + 232u reaches on the face axes, twice that on the diagonals).
template <typename S>
bool triangleMeetsSlabs(const fcl::Vector3<S> y[3], const RS<S>& b, S tol)
{
  const auto gap = [](S v0, S v1, S v2, S lo, S hi) __attribute__((always_inline)) {
    return std::max(std::min(v0, std::min(v1, v2)) - hi, lo - std::max(v0, std::max(v1, v2)));
  };
  S worst = -std::numeric_limits<S>::max();
  for (int i = 0; i < 3; ++i) worst = std::max(worst, gap(y[0][i], y[1][i], y[2][i], b.lo[i], b.hi[i]));
  if (worst > tol) return false;
  const S scale = S(M_SQRT2);
  for (int k = 3; k < kNumSlabs; ++k)
  {
    const SlabDirection& d = kSlabDirections[std::size_t(k)];
    const S sign = S(d.sign);
    worst = std::max(worst, gap(y[0][d.i] + sign * y[0][d.j], y[1][d.i] + sign * y[1][d.j],
                                y[2][d.i] + sign * y[2][d.j], b.lo[k] * scale, b.hi[k] * scale));
  }
  return !(worst > scale * tol);
}

/// A leaf's triangle p (b1's model coordinates; leaf1 is its RS) against b2 moved into them (moved2 =
/// MovedFrame(R, T, b2)): b2's nine slabs only. The triangle lies in leaf1, so on those slabs this is tighter
/// than boxedOverlap(moved2, leaf1); it does not test leaf1's slabs against b2's box. Offsets as PairFrame's
/// (the vertices' own size enters only through their distance from b2, a reach).
template <typename S>
bool triangleOverlap(const fcl::Vector3<S> p[3], const RS<S>& leaf1, const MovedFrame<S>& moved2, const RS<S>& b2)
{
  const fcl::Vector3<S> y[3] = {moved2.axis.transpose() * (p[0] - moved2.origin),
                                moved2.axis.transpose() * (p[1] - moved2.origin),
                                moved2.axis.transpose() * (p[2] - moved2.origin)};
  const S offsets = moved2.offsets + leaf1.origin.template lpNorm<1>();
  return triangleMeetsSlabs(y, b2, pairRoundingBound<S>(offsets, Box<S>(leaf1).reach() + moved2.reach));
}

/// b1 against a leaf's triangle q of b2's model (leaf2 is its RS), mapped into b1's model coordinates by
/// x = R q + T as the leaf test maps it: b1's nine slabs only. world_offsets as MovedFrame's; the offsets count
/// the vertices' L1 size, which R q + T rounds.
template <typename S>
bool triangleOverlap(const RS<S>& b1, const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const fcl::Vector3<S> q[3],
                     const RS<S>& leaf2, S world_offsets)
{
  const fcl::Vector3<S> y[3] = {b1.toFrame(R * q[0] + T), b1.toFrame(R * q[1] + T), b1.toFrame(R * q[2] + T)};
  const S largest_q = std::max({q[0].template lpNorm<1>(), q[1].template lpNorm<1>(), q[2].template lpNorm<1>()});
  const S offsets = largest_q + T.template lpNorm<1>() + world_offsets + b1.origin.template lpNorm<1>();
  return triangleMeetsSlabs(y, b1, pairRoundingBound<S>(offsets, Box<S>(b1).reach() + Box<S>(leaf2).reach()));
}

/// The exact overlap tests (OverlapTest::kOneSided, kTwoSided), compiled once per variant.
template <OverlapTest test, typename S>
bool exactOverlap(const MovedFrame<S>& moved2, const RS<S>& b1, const RS<S>& b2)
{
  const PairFrame<S> f(moved2, b1);
  const fcl::Matrix3<S>& M = f.M;
  const fcl::Vector3<S>& m2 = f.centre2;
  const fcl::Vector3<S> m1 = f.centre1();
  constexpr bool exact_on_2 = test == OverlapTest::kTwoSided;

  // Pass 1, boxes only: slab k of b1 (k < 9) or of b2 (k >= 9) against the other's principal box
  // projected on it (mid +- radius). Apart means separated. Otherwise the other polytope's interval
  // ends lie within box_excess of the box's, so a side needs an exact support (pass 2) only where
  // the box overlaps the slab by less than that.
  // Queue entries are 2 * slab + side (0: the other volume's low end against hi, 1: its high end
  // against lo), appended without branches: which sides need work is unpredictable.
  std::uint8_t queued[4 * kNumSlabs + 1];
  int num_queued = 0;
  const S excess1 = b2.box_excess, excess2 = exact_on_2 ? b1.box_excess : S(0);
  auto boxApart = [&](int k, S mid, S radius) {
    const bool on_1 = k < kNumSlabs;
    const int j = on_1 ? k : k - kNumSlabs;
    const RS<S>& slabs = on_1 ? b1 : b2;
    const S lo = slabs.lo[j] - f.tol, hi = slabs.hi[j] + f.tol;
    const S low = mid - radius, high = mid + radius, excess = on_1 ? excess1 : excess2;
    queued[num_queued] = std::uint8_t(2 * k);
    num_queued += low + excess > hi;
    queued[num_queued] = std::uint8_t(2 * k + 1);
    num_queued += high - excess < lo;
    return low > hi || high < lo;
  };

  // The six face axes first: most separated pairs are rejected there, as in an OBB test.
  const fcl::Matrix3<S> A = M.cwiseAbs();
  const fcl::Vector3<S> r2 = A * f.box2.h, r1 = A.transpose() * f.box1.h;
  for (int i = 0; i < 3; ++i)
    if (boxApart(i, m2[i], r2[i]) || boxApart(kNumSlabs + i, m1[i], r1[i])) return false;
  for (int k = 3; k < kNumSlabs; ++k)
  {
    const SlabDirection& d = kSlabDirections[k];
    const S sign = S(d.sign), scale = S(M_SQRT1_2);
    const fcl::Vector3<S> e1 = (M.row(d.i) + sign * M.row(d.j)).transpose().cwiseAbs();
    if (boxApart(k, (m2[d.i] + sign * m2[d.j]) * scale, e1.dot(f.box2.h) * scale)) return false;
    const fcl::Vector3<S> e2 = (M.col(d.i) + sign * M.col(d.j)).cwiseAbs();
    if (boxApart(kNumSlabs + k, (m1[d.i] + sign * m1[d.j]) * scale, e2.dot(f.box1.h) * scale)) return false;
  }

  // Pass 2: exact supports of the other polytope on the queued sides (octant trick).
  // With sigma = -1 for a low end and +1 for a high end, the other volume is apart when
  // sigma * shift + support(sigma * e) < sigma * (hi or lo) - tol.
  for (int q = 0; q < num_queued; ++q)
  {
    const int k = queued[q] >> 1, high_end = queued[q] & 1;
    const bool on_1 = k < kNumSlabs;
    const int j = on_1 ? k : k - kNumSlabs;
    const RS<S>& slabs = on_1 ? b1 : b2;
    const RS<S>& other = on_1 ? b2 : b1;
    const S sigma = high_end ? S(1) : S(-1);
    const fcl::Vector3<S> e = sigma * (on_1 ? slabOfRows(M, j) : slabOfColumns(M, j));
    // Projection of the other volume's frame origin on sigma * e.
    const S shift = sigma * projectOnSlab(on_1 ? m2 : m1, j) - e.dot(on_1 ? f.box2.c : f.box1.c);
    const S bound = sigma * (high_end ? slabs.lo[j] : slabs.hi[j]);
    if (shift + other.support(e) < bound - f.tol) return false;
  }
  return true;
}

/// overlap() with b2's frame already moved: moved2 = MovedFrame(R, T, b2).
template <typename S>
bool overlap(const BoxedFrame<S>& moved2, const RS<S>& b1, const RS<S>& b2, OverlapTest test)
{
  if (b1.empty() || b2.empty()) return false;
  switch (test)
  {
    case OverlapTest::kOneSided: return exactOverlap<OverlapTest::kOneSided>(moved2, b1, b2);
    case OverlapTest::kBoxed: return boxedOverlap(moved2, b1);
    default: return exactOverlap<OverlapTest::kTwoSided>(moved2, b1, b2);
  }
}

}  // namespace detail

template <typename S>
bool overlap(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2, OverlapTest test,
             S world_offsets)
{
  if (b1.empty() || b2.empty()) return false;
  return detail::overlap(detail::BoxedFrame<S>(R, T, b2, world_offsets), b1, b2, test);
}

template <typename S>
S distance(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2,
           fcl::Vector3<S>* P, fcl::Vector3<S>* Q)
{
  if (b1.empty() || b2.empty()) return std::numeric_limits<S>::max();
  const detail::PairFrame<S> f(R, T, b1, b2);
  const detail::ProjectedBox<S> on1(f.M, f.centre2, f.box2);              // b2's box on b1's directions
  const detail::ProjectedBox<S> on2(f.M.transpose(), f.centre1(), f.box1);  // b1's box on b2's directions
  S best = -std::numeric_limits<S>::max();
  int best_k = 0;
  for (int k = 0; k < 2 * kNumSlabs; ++k)
  {
    const S gap = k < kNumSlabs ? detail::slabGap<S>(b1.lo[k], b1.hi[k], b2, f.box2, on1, k)
                                : detail::slabGap<S>(b2.lo[k - kNumSlabs], b2.hi[k - kNumSlabs], b1, f.box1, on2,
                                                  k - kNumSlabs);
    if (gap > best) { best = gap; best_k = k; }
  }
  if (P || Q)
  {
    // Extreme points of each volume along the best direction n (b1's frame), facing each other.
    fcl::Vector3<S> n = best_k < kNumSlabs ? detail::slabDirection<S>(best_k)
                                           : detail::slabOfColumns(f.M, best_k - kNumSlabs);
    if (n.dot(f.centre2 - f.box1.c) < 0) n = -n;
    if (P) *P = b1.toModel(detail::extremeVertex(b1, n));
    if (Q) *Q = b2.toModel(detail::extremeVertex(b2, fcl::Vector3<S>(-(f.M.transpose() * n))));
  }
  return std::max(S(0), best - f.tol);
}

/// The distance traversal's lower bound on the distance between RS volumes b1 and b2 (b2 mapped into b1's
/// coordinates by x1 = R x2 + T). The gap between two convex sets along any direction, over the direction's
/// length, is a lower bound on their distance, so the bound is the largest such gap over a few directions,
/// cheapest first, returning as soon as it reaches `enough` (the traversal prunes the pair then, whatever the
/// bound): first the principal boxes (which contain the polytopes) along their six face normals, a few dozen
/// flops; then the polytopes' exact supports along the line c through the two box centres. Supports are
/// positively homogeneous, so that gap is measured along c itself and divided by |c| once (no unit vector).
/// Gaps are reduced by their rounding error, so the result never exceeds the true distance: measured along c,
/// every error of a unit direction's gap is scaled by |c| and then divided by it again, and the quotient adds
/// a few ulps of the gap, which is at most |c| (well inside pairRoundingBound's margin).
/// Most bounds only order a pair that is split anyway (docs/kernel.md): a second exact direction (the line
/// through the extreme vertices found along c, tighter on about half the pairs) and fcl_rs::distance (all 18
/// slab directions of both volumes) both cost more CPU time than the BV and triangle tests they save.
/// moved2 = detail::MovedFrame(R, T, b2) (the overload below builds it; traversals move each node once).
template <typename S>
S distanceLowerBound(const detail::MovedFrame<S>& moved2, const RS<S>& b1, const RS<S>& b2,
                     S enough = std::numeric_limits<S>::max())
{
  if (b1.empty() || b2.empty()) return std::numeric_limits<S>::max();
  using V = fcl::Vector3<S>;
  const detail::PairFrame<S> f(moved2, b1);
  const fcl::Matrix3<S>& M = f.M;
  // Principal boxes: half extents, and the vector from b1's box centre to b2's in b1's frame (c) and b2's (c2).
  const V& h1 = f.box1.h;
  const V& h2 = f.box2.h;
  const V c = f.centre2 - f.box1.c;
  const V c2 = M.transpose() * c;
  const fcl::Matrix3<S> A = M.cwiseAbs();
  // Box gaps along b1's axes (b2's box reaches h2 . |row i of M| along axis i) and b2's axes.
  const V gaps1 = c.cwiseAbs() - h1 - A * h2;
  const V gaps2 = c2.cwiseAbs() - A.transpose() * h1 - h2;
  const S boxes = std::max(gaps1.maxCoeff(), gaps2.maxCoeff()) - f.tol;
  if (boxes >= enough) return boxes;
  const S squared_length = c.squaredNorm();
  if (!(squared_length > 0)) return std::max(boxes, S(0));
  // The polytopes, exactly, along c: b2's lowest point minus b1's highest, times |c|.
  const S along = c.dot(f.t()) - detail::SupportCorner<S>(b2, V(-c2)).max() - detail::SupportCorner<S>(b1, c).max();
  return std::max({boxes, along / std::sqrt(squared_length) - f.tol, S(0)});
}

/// distanceLowerBound for b2 mapped into b1's coordinates by x1 = R x2 + T.
template <typename S>
S distanceLowerBound(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2,
                     S enough = std::numeric_limits<S>::max())
{
  return distanceLowerBound(detail::MovedFrame<S>(R, T, b2), b1, b2, enough);
}

}  // namespace fcl_rs

#endif
