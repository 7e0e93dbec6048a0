// A robot among named obstacles: one query per configuration (self and world together) and exact motion checks.
#ifndef FCL_RS_ROBOT_ENVIRONMENT_H
#define FCL_RS_ROBOT_ENVIRONMENT_H

#include <memory>
#include <string>
#include <vector>

#include <fcl/config.h>
#include <fcl/geometry/collision_geometry.h>

#include "fcl_rs/mesh/triangle_mesh.h"
#include "fcl_rs/robot/self_collision.h"

#if FCL_HAVE_OCTOMAP
namespace fcl {
template <typename S>
class OcTree;
}  // namespace fcl
#endif

namespace fcl_rs {

/// What Environment::query computes beyond "colliding or not" (which stops at the first contact).
struct EnvironmentRequest
{
  bool colliding_pairs = false;   ///< every colliding (link, link) and (link, obstacle) pair, by name
  bool minimum_distance = false;  ///< the smallest distance over the same pairs, its pair and nearest points
};

/// Two bodies by name: a link and another link (self) or an obstacle.
struct BodyPair
{
  std::string link;
  std::string other;
  bool other_is_link = false;

  bool operator==(const BodyPair& o) const
  {
    return link == o.link && other == o.other && other_is_link == o.other_is_link;
  }
};

template <typename S>
struct EnvironmentResult
{
  bool colliding = false;
  /// With colliding_pairs: the self pairs (SelfCollision::pairs() order), then link x obstacle pairs (links in
  /// model order, obstacles in insertion order).
  std::vector<BodyPair> pairs;
  /// With minimum_distance, for a collision-free configuration: the smallest distance (exact, as
  /// fcl_rs::distance with rel_err = abs_err = 0), the pair, and a nearest point on each (link first, root frame).
  /// 0 and no pair when colliding; infinity and no pair when there is nothing to measure.
  S minimum_distance = 0;
  BodyPair nearest_pair;
  fcl::Vector3<S> nearest_points[2] = {fcl::Vector3<S>::Zero(), fcl::Vector3<S>::Zero()};
};

/// Environment::checkMotion's options.
template <typename S>
struct MotionRequest
{
  /// true: find the first colliding configuration along the segment to within `tolerance` of the parameter;
  /// false: stop at any colliding configuration (the question a planner's motion validator asks).
  bool earliest = true;
  S tolerance = S(1e-3);  ///< in segment parameter (0..1 per segment)
};

template <typename S>
struct MotionResult
{
  bool colliding = false;
  /// When colliding: a parameter whose configuration collides (for a path: segment index + parameter in
  /// the segment), and every configuration at a parameter below free_until is collision-free (certified by
  /// distance bounds). With earliest, parameter - free_until <= tolerance. When free: the whole motion is.
  S parameter = 0;
  S free_until = 0;
  int configurations_checked = 0;  ///< configurations visited (kinematics runs)
  int distance_queries = 0;        ///< distance bounds asked for beyond the cheap gaps (hulls, measurements)
};

/// A robot (its SelfCollision checker, built here: link trees once) and named obstacles placed in the robot's
/// root frame: FCL shapes, triangle meshes built as trees of the checker's BV type (so that every BV type
/// answers the same questions with its own trees) and octomaps (fcl::OcTree, when FCL has octomap support),
/// which every link element meets with fcl_rs::collide's / fcl_rs::distance's answers (RS meshes on fcl_rs's
/// traversals directly, each obstacle shape's RS fitted once in its own frame; octrees on fcl_rs's octree
/// traversal; other BV types on FCL's; planes and halfspaces exactly here, see addShape). A link that no joint
/// moves (a robot's base) meets each obstacle once, when the obstacle is added, moved or refreshed, not at every
/// query.
///
/// query answers self-collision and collision with the obstacles at one configuration; checkMotion answers it
/// for every configuration of a straight joint-space segment, without sampling at a resolution: Schwarzer,
/// Saha and Latombe's adaptive dynamic collision checking (IEEE T-RO 2005). Each pair of bodies is certified
/// free on an interval when the distance lower bounds at its ends exceed the most any point of the two
/// bodies can move relative to each other along it (fcl_rs/robot/link_sweeps.h: per joint, |dq| times the
/// link ball's distance from the joint's axis at the interval's start plus its growth along the interval; 1 per
/// unit for prismatic joints); only the pairs and intervals that cannot be certified are bisected. Lower bounds
/// are the bounding spheres' (or an obstacle's box's) gap first, then GJK on the hulls of the link elements and
/// of the obstacle (SelfCollision::pairDistanceBound, hullDistanceBound), stopped once they reach what the
/// interval needs; bodies are measured only when their hulls are within rounding of contact and the collision
/// test finds them apart.
///
/// Queries and motion checks read the environment only (their state is per call): many threads may share one
/// (see fcl_rs/robot/batch_environment.h). Adding, moving, removing and refreshing obstacles (and changing an
/// octomap the environment holds) must not overlap queries.
/// BV types: RS, OBBRSS, OBB, RSS (KDOP18 is refused: its trees are refitted in place); distances and motion
/// checks need a distance query, which FCL lacks for OBB (std::invalid_argument).
template <typename S>
class Environment
{
public:
  using Scalar = S;

  /// Throws std::invalid_argument for KDOP18 and for a disabled pair naming no link (as SelfCollision).
  Environment(const RobotModel& robot, BVType bv, const std::vector<DisabledCollision>& disabled = {});
  ~Environment();
  Environment(Environment&&) noexcept;
  Environment& operator=(Environment&&) noexcept;

  const SelfCollision<S>& selfCollision() const;
  const Kinematics<S>& kinematics() const;
  BVType bvType() const;

  /// Adds an FCL shape (box, sphere, cylinder, capsule, cone, ellipsoid, convex, plane or halfspace) at `pose` in
  /// the root frame. A plane or halfspace (a table top, a floor) is measured exactly against each link: its
  /// extreme heights over the link mesh's vertices and the link shapes' support points decide collision
  /// (touching counts) and distance, with nearest points, for every BV type (FCL measures no distance to
  /// either). Throws std::invalid_argument when the name is empty or taken, the geometry is null, not one of
  /// these shapes (a TriangleP: FCL tests it against no link shape) or invalid (requireValidShape), or the pose is
  /// not a finite rigid transform.
  void addShape(const std::string& name, std::shared_ptr<fcl::CollisionGeometry<S>> shape,
                const fcl::Transform3<S>& pose);
  /// Adds a mesh (its own coordinates), built once as a tree of the environment's BV type, at `pose`. Throws
  /// std::invalid_argument as addShape, and for an invalid mesh (validateMesh).
  void addMesh(const std::string& name, const TriangleMesh<S>& mesh, const fcl::Transform3<S>& pose);
#if FCL_HAVE_OCTOMAP
  /// Adds an octomap at `pose`; its cells count as FCL's traversals count them (occupied leaves under occupied
  /// nodes: fcl::OcTree::isNodeOccupied, the octree's threshold). The environment shares the octree and reads
  /// its occupied cells here, once, for its culling volumes (the octree's own box is the map's whole root
  /// cube): after the map's cells or thresholds change, call refreshOcTree before the next query. A map without
  /// occupied cells collides with nothing and adds no distance. Throws std::invalid_argument as addShape.
  void addOcTree(const std::string& name, std::shared_ptr<fcl::OcTree<S>> octree, const fcl::Transform3<S>& pose);
  /// Reads a named octree's occupied cells again (see addOcTree). Throws std::invalid_argument for an unknown
  /// name or an obstacle that is not an octree.
  void refreshOcTree(const std::string& name);
#endif
  /// Moves a named obstacle; throws std::invalid_argument for an unknown name or a bad pose.
  void setPose(const std::string& name, const fcl::Transform3<S>& pose);
  /// Removes a named obstacle; throws std::invalid_argument for an unknown name.
  void remove(const std::string& name);
  bool contains(const std::string& name) const;
  /// Obstacle names in insertion order.
  std::vector<std::string> obstacleNames() const;
  const fcl::Transform3<S>& pose(const std::string& name) const;

  /// Self-collision and collision with every obstacle at q (kinematics once). Throws std::invalid_argument
  /// for a q of the wrong size or with a non-finite entry, and for minimum_distance with OBB.
  EnvironmentResult<S> query(const fcl::VectorX<S>& q, const EnvironmentRequest& request = {}) const;

  /// Every configuration of the straight segment from `from` to `to` (both included). Throws
  /// std::invalid_argument as query, for OBB, and for a tolerance outside (0, 1].
  MotionResult<S> checkMotion(const fcl::VectorX<S>& from, const fcl::VectorX<S>& to,
                              const MotionRequest<S>& request = {}) const;
  /// A path of straight segments through the rows of `waypoints` (at least one row); the parameter of a
  /// colliding result is segment index + parameter within that segment.
  MotionResult<S> checkPath(const std::vector<fcl::VectorX<S>>& waypoints, const MotionRequest<S>& request = {}) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

#define FCL_RS_DECLARE_ENVIRONMENT(S) extern template class Environment<S>;
FCL_RS_DECLARE_ENVIRONMENT(float)
FCL_RS_DECLARE_ENVIRONMENT(double)
#undef FCL_RS_DECLARE_ENVIRONMENT

}  // namespace fcl_rs

#endif
