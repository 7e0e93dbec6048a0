// Robot self-collision: one collision model per link with a BV type chosen at run time, over a fixed pair list.
#ifndef FCL_RS_SELF_COLLISION_H
#define FCL_RS_SELF_COLLISION_H

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/mesh/triangle_mesh.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/robot/kinematics.h"
#include "fcl_rs/robot/robot_model.h"
#include "fcl_rs/robot/srdf.h"

namespace fcl_rs {

/// The bounding volume of the links' mesh trees.
enum class BVType { kRS, kOBBRSS, kOBB, kRSS, kKDOP18 };
inline constexpr std::array<BVType, 5> kRobotBVTypes = {BVType::kRS, BVType::kOBBRSS, BVType::kOBB, BVType::kRSS,
                                                        BVType::kKDOP18};

/// "RS", "OBBRSS", "OBB", "RSS", "KDOP18".
const char* bvTypeName(BVType bv);
/// The BV type of a name bvTypeName returns (any letter case); throws std::invalid_argument listing the names.
BVType parseBVType(const std::string& name);

/// Two link indices (RobotModel::links), first < second.
using LinkPair = std::pair<int, int>;

/// What SelfCollision::query computes beyond "colliding or not".
struct SelfCheckRequest
{
  bool colliding_pairs = false;   ///< every colliding pair (else the check stops at the first one)
  bool minimum_distance = false;  ///< the smallest distance between the geometries of any two checked links
};

/// One configuration's answer.
template <typename S>
struct SelfCheckResult
{
  bool colliding = false;
  std::vector<LinkPair> pairs;  ///< with SelfCheckRequest::colliding_pairs: what check() returns
  /// With SelfCheckRequest::minimum_distance: 0 when colliding, else the minimum over pairs() of
  /// fcl_rs::distance between the two links' elements (exact, rel_err = abs_err = 0).
  S minimum_distance = 0;
};

/// One collision element of a link: its mesh tree (in the checker's BV type) or one box, cylinder or sphere, placed
/// in the link frame. Read-only and owned by the checker.
template <typename S>
struct LinkElement
{
  const fcl::CollisionGeometry<S>* geometry;
  fcl::Transform3<S> origin;
};

/// A ball in a link's frame that holds all its collision geometry.
template <typename S>
struct LinkSphere
{
  fcl::Vector3<S> center = fcl::Vector3<S>::Zero();
  S radius = 0;
};

/// Points whose convex hull, grown by `radius`, holds a body, in the body's frame: what SelfCollision bounds the
/// distance between link elements with (GJK on their hulls), and other bodies against links (hullDistanceBound).
template <typename S>
struct BodyHull
{
  triangle_shape::HullPoints points;
  double radius = 0;
  double reach = 0;                                  ///< the largest |point| + radius: the rounding margin's scale
  fcl::Vector3<S> center = fcl::Vector3<S>::Zero();  ///< near the body's middle: where GJK starts
};

/// A triangle mesh's hull: its distinct vertices, walked along its edges (HullPoints), about the centre of their
/// box. `convex`, when given: whether every triangle's plane has all the vertices on one side (to 1e-2 of their
/// reach), so that the mesh's distance to a convex body is its hull's.
template <typename S>
BodyHull<S> meshHull(const TriangleMesh<S>& mesh, bool* convex = nullptr);

namespace detail {
/// What the robot layer's environment shares with the checker (src/robot/self_collision_internals.h).
template <typename S>
struct SelfCollisionInternals;
}  // namespace detail

/// Self-collision checker for one robot and one BV type.
///
/// Every link with collision geometry gets one BVHModel<BV> holding all its <mesh> elements, plus one FCL shape
/// per box, cylinder or sphere element. The pair list is fixed at construction: every two links with geometry,
/// except adjacent links (a link and its nearest ancestor with geometry, so links without geometry such as
/// panda_link8 do not hide an adjacency) and disabled pairs (SRDF). A check runs forward kinematics, skips
/// pairs whose bounding spheres are apart, then tests the link geometries: a pair collides when any of its
/// elements touch (FCL's triangle and GJK tests decide, so every BV type reports the same pairs). With RS, each
/// link's elements also share one RS volume, tested after the spheres and before any element query, and a
/// shape is tested against the mesh's root volume before its traversal is set up. A first-contact check
/// (inCollision, query without colliding_pairs) tests the pair that collided last first.
/// A minimum-distance query measures element pairs best first by a lower bound on their distance, tightened only
/// for the candidate that is nearest so far (link spheres; with RS the link volumes; per element pair the
/// elements' balls, then the distance of their convex hulls by GJK: a mesh's vertices, a box's corners), and
/// stops when the smallest bound reaches the best distance so far; each measurement starts at that best, so it
/// skips what cannot beat it. With RS a measurement takes the hulls' gap direction and measures only the
/// triangles near the gap along it when they are few (convex meshes), without a tree descent; its cost is in
/// docs/robots.md.
///
/// How each BV type is queried (the fastest path FCL offers for it):
/// * RS, OBBRSS, OBB, RSS: mesh-mesh in the links' own frames through collideWithStats (the relative
///   transform, no copy; fcl::collide would copy and rebuild RSS trees per query); mesh-shape through
///   fcl::collide, or for RS fcl_rs::collide's node with each shape's RS fitted once in its own frame and
///   placed per query; shape-shape through fcl_rs::collide.
/// * KDOP18: FCL's k-DOPs are axis-aligned, so they have no local-frame test. Once per check and only for the
///   links a pair needs, the link's vertices are moved to the world frame and its tree is refitted bottom-up
///   (same topology, exact leaves; cheaper than FCL's per-query copy and rebuild); the trees are then tested
///   with identity transforms.
///
/// check, checkPoses and inCollision are not thread-safe (the KDOP18 trees and the poses are updated per check).
/// query is: it only reads the checker, so many threads may share one (see fcl_rs/robot/batch_self_collision.h).
template <typename S>
class SelfCollision
{
public:
  using Scalar = S;

  /// Throws std::invalid_argument when a disabled pair names a link the robot does not have.
  SelfCollision(const RobotModel& robot, BVType bv, const std::vector<DisabledCollision>& disabled = {});
  ~SelfCollision();
  SelfCollision(SelfCollision&&) noexcept;
  SelfCollision& operator=(SelfCollision&&) noexcept;

  BVType bvType() const;
  const Kinematics<S>& kinematics() const;
  const std::vector<std::string>& linkNames() const;
  /// The link pairs every check tests, sorted.
  const std::vector<LinkPair>& pairs() const;

  /// The colliding pairs at configuration q (in the order of pairs()). When stats is given, the BV and
  /// triangle tests of the mesh-mesh queries are added to it.
  std::vector<LinkPair> check(const fcl::VectorX<S>& q, QueryStats* stats = nullptr);
  /// The same at given link poses, one per link (as Kinematics::linkPoses returns them). Throws
  /// std::invalid_argument naming poses[i] when a pose is not a rigid transform (fcl_rs/validate.h).
  std::vector<LinkPair> checkPoses(const std::vector<fcl::Transform3<S>>& poses, QueryStats* stats = nullptr);
  /// Whether any pair collides at q; stops at the first colliding pair (the query a planner makes).
  bool inCollision(const fcl::VectorX<S>& q);
  /// The same answers as check / inCollision (and the minimum distance on request) without changing the
  /// checker, so it may be called from many threads at once. Throws std::invalid_argument for KDOP18 (its
  /// trees are refitted in place per check) and, with minimum_distance, for OBB (FCL has no OBB distance).
  SelfCheckResult<S> query(const fcl::VectorX<S>& q, const SelfCheckRequest& request) const;
  /// query at given link poses (as Kinematics::linkPoses returns them), for callers that need the poses
  /// themselves (fcl_rs/robot/environment.h): kinematics run once per configuration. Thread-safe as query.
  SelfCheckResult<S> queryPoses(const std::vector<fcl::Transform3<S>>& poses, const SelfCheckRequest& request) const;

  /// A lower bound on the distance between the links of pairs()[pair] at the poses (as queryPoses takes them), as
  /// cheap as `enough` allows (for motion checks, fcl_rs/robot/environment.h): the minimum-distance search on that
  /// pair alone, started at `enough`, so each bound stops it once it reaches `enough`. Below `enough` the answer is
  /// the distance as minimum_distance measures it; without `measure`, GJK's bound on the distance of the elements'
  /// hulls, stopped within half of it (for convex elements, Panda-like meshes and the URDF shapes, at least half
  /// the distance less a rounding margin; for others less). 0 or less for touching links. Thread-safe as query; throws
  /// std::invalid_argument for KDOP18 and OBB (as query with minimum_distance) and for a pair or poses out of range.
  S pairDistanceBound(const std::vector<fcl::Transform3<S>>& poses, int pair, S enough, bool measure) const;

  /// A lower bound on the distance between the link at `pose` and a body whose hull is `body` at `body_pose`: the
  /// smallest of GJK's bounds between each element's hull and the body's (as pairDistanceBound bounds elements
  /// without measuring), each stopped once it reaches `enough` or is within half of the hulls' distance.
  S hullDistanceBound(int link, const fcl::Transform3<S>& pose, const BodyHull<S>& body,
                      const fcl::Transform3<S>& body_pose, S enough) const;

  /// A lower bound on n . x over the points x of the link's geometry at `pose` (n: a unit vector): the lowest of its
  /// elements' hull points along n, less the hulls' radii and a rounding margin (as hullDistanceBound's). With a
  /// box's face normal it bounds the link's distance to the box from below at the cost of a support point, not GJK.
  S lowestAlong(int link, const fcl::Transform3<S>& pose, const fcl::Vector3<S>& n) const;

  /// The link's collision elements, for queries against other geometry (empty for a link without geometry).
  /// Throws std::invalid_argument for KDOP18, whose trees live in the world frame.
  std::vector<LinkElement<S>> linkElements(int link) const;
  /// The link's bounding sphere (radius 0 for a link without geometry).
  LinkSphere<S> linkSphere(int link) const;

private:
  friend struct detail::SelfCollisionInternals<S>;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

#define FCL_RS_DECLARE_SELF_COLLISION(S)  \
  extern template class SelfCollision<S>; \
  extern template BodyHull<S> meshHull(const TriangleMesh<S>&, bool*);
FCL_RS_DECLARE_SELF_COLLISION(float)
FCL_RS_DECLARE_SELF_COLLISION(double)
#undef FCL_RS_DECLARE_SELF_COLLISION

}  // namespace fcl_rs

#endif
