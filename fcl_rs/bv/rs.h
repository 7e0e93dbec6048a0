// RS<S>: the oriented 18-DOP bounding volume R(S) (PCA frame, nine slabs, Tribox corners).
#ifndef FCL_RS_RS_H
#define FCL_RS_RS_H

#include <array>
#include <limits>

#include <fcl/common/types.h>

#include "fcl_rs/bv/directions.h"

namespace fcl_rs {

/// Oriented convex polyhedron R(S): the intersection of nine slabs whose directions are the
/// principal axes u0, u1, u2 of a frame and the six diagonals (u_i +- u_j)/sqrt(2).
///
/// A point x (in the model's coordinates) has frame coordinates y = axis^T (x - origin); it lies in
/// the volume when lo[k] <= d_k . y <= hi[k] for the nine unit directions d_k of kSlabDirections.
/// Intervals are along unit directions, so an interval gap is a true distance. The default
/// volume is empty (lo > hi); adding points grows the intervals in the volume's current frame.
template <typename S_>
class RS
{
public:
  using S = S_;
  /// A volume is stored in float whatever S is, except its origin: a BVNode<RS<double>> is 152 bytes instead of
  /// 264 (FCL's OBB<double> node: 136). Slab values are rounded outward (lo down, hi up: slabBelow, slabAbove)
  /// and measured from the origin, the points' mean, so they stay small far from the model origin; the frame is
  /// rounded to nearest before any slab is computed against it, so the stored volume contains every point as
  /// the fit computed it. What storage costs the pair tests (a float frame is orthonormal only to ~1e-7, and
  /// the 18 rounded slabs are no longer one support function) is detail::storageBound, part of every pair
  /// test's rounding bound: pruning only, about 1e-5 of the volumes' size.
  using Stored = float;
  using Slabs = Eigen::Matrix<Stored, kNumSlabs, 1>;
  using Axes = Eigen::Matrix<Stored, 3, 3>;

  /// Right-handed frame, orthonormal up to its storage; columns are u0, u1, u2 (u0 = largest principal
  /// variance). Read it in S through axes().
  Axes axis;
  /// Upper bound on how far the principal box reaches past the polytope along any unit direction.
  /// Overlap tests use it to skip exact supports wherever the box bound already decides; every
  /// member that grows the volume keeps it current (call updateBoxExcess() after writing lo/hi
  /// directly). Too small only costs pruning, never a missed contact: 0 makes the test boxed.
  /// (Stored next to axis, where it fills the float frame's padding.)
  Stored box_excess = 0;
  /// Frame origin in model coordinates (the mean of the fitted points).
  fcl::Vector3<S> origin;
  /// Slab intervals along the nine unit directions, in frame coordinates. Write them through slabBelow and
  /// slabAbove: a value rounded to nearest can cut a point off.
  Slabs lo = Slabs::Constant(std::numeric_limits<Stored>::max());  // empty: lo > hi
  Slabs hi = Slabs::Constant(-std::numeric_limits<Stored>::max());

  /// Empty volume in the identity frame at the model origin.
  RS();
  /// Empty volume in the given frame (rounded to the stored one).
  RS(const fcl::Matrix3<S>& axis, const fcl::Vector3<S>& origin);

  bool empty() const;

  /// A stored slab value <= v (for lo) and one >= v (for hi), each within two float ulps of v.
  static Stored slabBelow(S v);
  static Stored slabAbove(S v);
  /// slabBelow and slabAbove of each of n values at once (a fit rounds 18 per node: vectorised, not 18 calls).
  /// Inlined by force: gcc 12 calls them otherwise, about 90 more instructions per fitted node.
  template <int n>
  __attribute__((always_inline)) inline static Eigen::Array<Stored, n, 1> slabsBelow(const Eigen::Array<S, n, 1>& v);
  template <int n>
  __attribute__((always_inline)) inline static Eigen::Array<Stored, n, 1> slabsAbove(const Eigen::Array<S, n, 1>& v);

  /// The stored frame in S.
  fcl::Matrix3<S> axes() const { return axis.template cast<S>(); }

  /// Grows the intervals (in the current frame) to contain p. On an empty volume the origin moves to p.
  RS& operator+=(const fcl::Vector3<S>& p);
  /// Grows this volume (in its current frame) to contain every corner of other.
  RS& operator+=(const RS& other);
  /// A volume containing both operands, in the principal frame of their corners.
  RS operator+(const RS& other) const;

  /// Overlap with a volume in the same (model) coordinates; symmetric and conservative.
  bool overlap(const RS& other) const;
  /// Whether p (model coordinates) is inside, up to rounding.
  bool contain(const fcl::Vector3<S>& p) const;
  /// A lower bound on the distance to other (same coordinates); 0 when they may overlap.
  /// P and Q, if given, receive a point of each volume on the separating direction.
  S distance(const RS& other, fcl::Vector3<S>* P = nullptr, fcl::Vector3<S>* Q = nullptr) const;

  /// Centre of the principal box, in model coordinates.
  fcl::Vector3<S> center() const;
  /// Extents of the principal box along u0, u1, u2: the ball at center() of radius
  /// ||(width, height, depth)|| / 2 contains the volume.
  S width() const;
  S height() const;
  S depth() const;
  /// Traversal-order size: squared diagonal of the principal box.
  S size() const;
  /// Exact volume of the polytope.
  S volume() const;

  /// The 4 vertices of the polytope's corner in octant `octant` (bit i set = negative along u_i),
  /// in frame coordinates (Tribox construction). All 8 corners give the <= 32 polytope vertices.
  std::array<fcl::Vector3<S>, 4> cornerVertices(int octant) const;
  void cornerVertices(int octant, fcl::Vector3<S>* out4) const;
  /// All 32 corner points (with repeats where the polytope has fewer vertices), frame coordinates.
  std::array<fcl::Vector3<S>, 32> corners() const;
  /// max over the polytope of dir . y, for dir in frame coordinates (octant trick: 4 dot products).
  S support(const fcl::Vector3<S>& dir) const;
  /// Largest absolute slab value; the scale of the rounding error of anything derived from the volume.
  S magnitude() const;

  /// Frame coordinates of a model point: what defines the volume (exact but for the rounding in S).
  fcl::Vector3<S> toFrame(const fcl::Vector3<S>& p) const { return axes().transpose() * (p - origin); }
  /// A model point whose frame coordinates are y, up to the frame's departure from orthonormality (storageBound).
  fcl::Vector3<S> toModel(const fcl::Vector3<S>& y) const { return axes() * y + origin; }

  /// Grows the intervals to contain the frame point y, widened by abs_err (its known rounding error).
  /// Leaves box_excess stale: call updateBoxExcess() when done growing.
  void expandFrame(const fcl::Vector3<S>& y, S abs_err);
  /// Grows the intervals to contain the n model points point_at(i) and brings box_excess up to date.
  /// Equivalent to toFrame + expandFrame per point, but pads once, by the largest point's rounding.
  template <typename PointAt>
  void expandPoints(int n, PointAt point_at);
  /// Recomputes box_excess from the slabs: per corner, the distance from the box corner to the
  /// nearest of the corner's 4 vertices, maximised over the 8 corners.
  void updateBoxExcess();

private:
  /// The planes at octant `octant`'s corner, in the frame reflected so that the corner is (+,+,+): the box
  /// planes x = X, y = Y, z = Z and the unnormalised chamfers x + y = Cxy, x + z = Cxz, y + z = Cyz.
  struct CornerPlanes
  {
    S X, Y, Z, Cxy, Cxz, Cyz;
  };
  CornerPlanes cornerPlanes(int octant) const;
};

using RSf = RS<float>;
using RSd = RS<double>;

/// RS of n points given by point_at(i): principal frame of the points, then the nine intervals.
template <typename S, typename PointAt>
RS<S> fitPoints(int n, PointAt point_at);

template <typename S>
RS<S> fitPoints(const fcl::Vector3<S>* points, int n);

/// FCL's fit(ps, n, bv) for RS, found by argument-dependent lookup from FCL's refit code.
template <typename S>
void fit(const fcl::Vector3<S>* const points, int n, RS<S>& bv);

/// How two RS volumes are tested for overlap. Every variant first rejects pairs whose principal
/// boxes are apart along a face axis, and every variant is conservative (never reports touching
/// volumes as separate); they trade pruning for time.
enum class OverlapTest
{
  kTwoSided,  ///< exact polytopes on all 18 slab directions (both volumes'); symmetric, the tightest
  kOneSided,  ///< the paper's test: b2's polytope on b1's nine directions only
  kBoxed,     ///< each volume's nine slabs against the other's principal box; builds no corners
};

/// The test fcl_rs::collide, the traversal nodes and overlap() use unless told otherwise.
constexpr OverlapTest kDefaultOverlapTest = OverlapTest::kBoxed;

/// Overlap test in FCL's convention: b2 is mapped into b1's coordinates by x1 = R x2 + T.
/// Padded by the rounding error of the transform and of the corner arithmetic; world_offsets
/// (|t1|_1 + |t2|_1 of the query's poses, 0 when there are none) adds that of the world frame.
template <typename S>
bool overlap(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2,
             OverlapTest test = kDefaultOverlapTest, S world_offsets = 0);

/// Lower bound on the distance between b1 and b2 (b2 mapped by x1 = R x2 + T): the largest gap
/// over the 18 slab directions, minus rounding. P (in b1's coordinates) and Q (in b2's) receive
/// the two volumes' extreme points along that direction.
template <typename S>
S distance(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const RS<S>& b1, const RS<S>& b2,
           fcl::Vector3<S>* P = nullptr, fcl::Vector3<S>* Q = nullptr);

/// A copy of bv moved by the rigid transform tf (its frame and origin are transformed).
template <typename S>
RS<S> transform(const RS<S>& bv, const fcl::Transform3<S>& tf);

}  // namespace fcl_rs

#include "fcl_rs/bv/rs-inl.h"
#include "fcl_rs/bv/pair_kernel.h"
// FCL fits and splits a BVHModel<RS> with the specialisations in rs_fit.h; a translation unit that builds one
// without them silently compiles FCL's generic fit (the identity frame, point by point) and breaks the ODR.
#include "fcl_rs/bv/rs_fit.h"

#endif
