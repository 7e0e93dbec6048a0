// Environment: a SelfCollision checker, named obstacles with bounding spheres, per-configuration queries and
// adaptive motion checks (Schwarzer, Saha and Latombe).
#include "fcl_rs/robot/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>
#endif

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include "../scalars.h"
#include "../validated_entries.h"
#include "body_hulls.h"
#include "box_tree.h"
#include "self_collision_internals.h"
#include "world_balls.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/fcl_float.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/robot/link_sweeps.h"
#include "fcl_rs/traversal/collision_traversal.h"
#include "fcl_rs/traversal/shape_switch.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {

namespace {

constexpr const char* kApi = "fcl_rs::Environment";

template <typename S>
using Tf = fcl::Transform3<S>;

template <typename S>
void validateConfiguration(const fcl::VectorX<S>& q, int dof, const char* what)
{
  if (q.size() != dof)
    throw std::invalid_argument(std::string(kApi) + ": " + what + " has " + std::to_string(q.size()) +
                                " values, the robot has " + std::to_string(dof) + " joint variables");
  if (!q.allFinite())
    throw std::invalid_argument(std::string(kApi) + ": " + what + " has a non-finite value");
}

/// A body's elements in its own frame and a ball about them (the link's, or an obstacle's AABB ball).
template <typename S>
struct Body
{
  std::vector<LinkElement<S>> elements;
  fcl::Vector3<S> center = fcl::Vector3<S>::Zero();
  S radius = 0;
};

using detail::sphereGap;
using detail::spheresApart;
using detail::WorldSphere;

/// A body's ball placed at its pose (detail::placeBall).
template <typename S>
WorldSphere<S> place(const Body<S>& body, const Tf<S>& pose)
{
  return detail::placeBall(pose, body.center, body.radius);
}

/// Whether any element of a touches any element of b (FCL's and fcl_rs's exact tests, first contact): link pairs
/// of motion checks (obstacles take Environment's own path, linkHitsObstacle).
template <typename S>
bool bodiesCollide(const Body<S>& a, const Tf<S>& ta, const Body<S>& b, const Tf<S>& tb)
{
  const fcl::CollisionRequest<S> request(/*num_max_contacts=*/1, /*enable_contact=*/false);
  for (const LinkElement<S>& ea : a.elements)
    for (const LinkElement<S>& eb : b.elements)
    {
      fcl::CollisionResult<S> result;
      if (fcl_rs::collide(ea.geometry, Tf<S>(ta * ea.origin), eb.geometry, Tf<S>(tb * eb.origin), request, result))
        return true;
    }
  return false;
}

/// The smallest element distance between a and b when below `bound` (else `bound`), with the nearest points
/// (a's first, root frame) when `points` is given. Colliding elements give 0. With rel_err > 0 the result may
/// exceed the distance by that factor (fcl_rs::distance's contract): divide by 1 + rel_err for a lower bound.
template <typename S>
S bodiesDistance(const Body<S>& a, const Tf<S>& ta, const Body<S>& b, const Tf<S>& tb, S bound,
                 fcl::Vector3<S>* points, S rel_err = 0)
{
  fcl::DistanceRequest<S> request;
  request.enable_nearest_points = points != nullptr;
  request.rel_err = rel_err;
  for (const LinkElement<S>& ea : a.elements)
    for (const LinkElement<S>& eb : b.elements)
    {
      // Started at the bound, the traversal prunes every node pair that cannot beat it.
      fcl::DistanceResult<S> result;
      result.min_distance = bound;
      const S d = std::max(S(0), fcl_rs::distance(ea.geometry, Tf<S>(ta * ea.origin), eb.geometry,
                                                  Tf<S>(tb * eb.origin), request, result));
      if (d >= bound) continue;
      bound = d;
      if (points)
      {
        // fcl_rs::distance, as FCL, names a mesh before a shape given first, and an octree first.
        const fcl::OBJECT_TYPE type_a = ea.geometry->getObjectType(), type_b = eb.geometry->getObjectType();
        const bool swapped = type_b == fcl::OT_OCTREE || (type_a == fcl::OT_GEOM && type_b == fcl::OT_BVH);
        points[0] = result.nearest_points[swapped ? 1 : 0];
        points[1] = result.nearest_points[swapped ? 0 : 1];
      }
      if (bound <= 0) return 0;
    }
  return bound;
}

/// A plane n . x = d or a halfspace n . x <= d (|n| = 1) in the root frame. Unbounded: no ball or box holds it,
/// and FCL measures no distance to it, so links are measured against it exactly here (Impl::heights).
template <typename S>
struct Flat
{
  fcl::Vector3<S> n;
  S d;
  bool plane;  ///< else a halfspace
};

/// The obstacle geometry placed at pose as a Flat, or none for a bounded geometry.
template <typename S>
std::optional<Flat<S>> flatAt(const fcl::CollisionGeometry<S>& geometry, const Tf<S>& pose)
{
  return detail::withShape(
      geometry,
      [&](const auto& shape) -> std::optional<Flat<S>> {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Plane<S>> || std::is_same_v<Shape, fcl::Halfspace<S>>)
        {
          const Shape placed = fcl::transform(shape, pose);
          return Flat<S>{placed.n, placed.d, std::is_same_v<Shape, fcl::Plane<S>>};
        }
        else
          return std::nullopt;
      },
      []() -> std::optional<Flat<S>> { return std::nullopt; });
}

/// The point of a link shape (a box, cylinder or sphere: the shapes SelfCollision makes) farthest along the unit
/// vector u, in the shape's frame.
template <typename S>
fcl::Vector3<S> linkShapeSupport(const fcl::CollisionGeometry<S>& geometry, const fcl::Vector3<S>& u)
{
  const auto not_a_link_shape = []() -> fcl::Vector3<S> {
    throw std::logic_error("fcl_rs::Environment: a link shape is not a box, cylinder or sphere");
  };
  return detail::withShape(
      geometry,
      [&](const auto& shape) -> fcl::Vector3<S> {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Box<S>>)
        {
          const auto half = [](S side, S along) { return along < 0 ? -side / 2 : side / 2; };
          return fcl::Vector3<S>(half(shape.side.x(), u.x()), half(shape.side.y(), u.y()), half(shape.side.z(), u.z()));
        }
        else if constexpr (std::is_same_v<Shape, fcl::Sphere<S>>)
          return shape.radius * u;
        else if constexpr (std::is_same_v<Shape, fcl::Cylinder<S>>)  // the leaf test's support function
          return triangle_shape::ShapeGeometry<Shape>(shape).support(u.template cast<double>()).template cast<S>();
        else
          return not_a_link_shape();
      },
      not_a_link_shape);
}

/// The lowest and highest signed heights n . x - d of a link's geometry over a Flat, with their points (root
/// frame).
template <typename S>
struct Heights
{
  S lo = std::numeric_limits<S>::infinity();
  S hi = -std::numeric_limits<S>::infinity();
  fcl::Vector3<S> lo_point = fcl::Vector3<S>::Zero(), hi_point = fcl::Vector3<S>::Zero();
};

/// An obstacle shape's hull in its own frame (SelfCollision::hullDistanceBound), for a box, sphere, capsule or
/// cylinder (a 16-gon prism about it, within 2 % of its radius); none for other shapes.
template <typename S>
std::optional<BodyHull<S>> shapeHull(const fcl::CollisionGeometry<S>& geometry)
{
  return detail::withShape(
      geometry,
      [&](const auto& shape) -> std::optional<BodyHull<S>> {
        using Shape = std::decay_t<decltype(shape)>;
        std::vector<fcl::Vector3d> points;
        BodyHull<S> hull;
        if constexpr (std::is_same_v<Shape, fcl::Box<S>>)
        {
          points = detail::boxCorners(0.5 * shape.side.template cast<double>());
        }
        else if constexpr (std::is_same_v<Shape, fcl::Sphere<S>>)
        {
          points.emplace_back(fcl::Vector3d::Zero());
          hull.radius = double(shape.radius);
        }
        else if constexpr (std::is_same_v<Shape, fcl::Capsule<S>>)
        {
          points.emplace_back(0, 0, 0.5 * double(shape.lz));
          points.emplace_back(0, 0, -0.5 * double(shape.lz));
          hull.radius = double(shape.radius);
        }
        else if constexpr (std::is_same_v<Shape, fcl::Cylinder<S>>)
        {
          // The polygon's sides touch the circle, so the prism holds the cylinder.
          const int sides = 16;
          const double corner = double(shape.radius) / std::cos(M_PI / sides) * (1 + 1e-12);
          for (int k = 0; k < sides; ++k)
            for (double z : {-0.5 * double(shape.lz), 0.5 * double(shape.lz)})
              points.emplace_back(corner * std::cos(2 * M_PI * k / sides), corner * std::sin(2 * M_PI * k / sides), z);
        }
        else
          return std::nullopt;
        hull.points = triangle_shape::HullPoints(std::move(points));
        hull.reach = detail::hullReach(hull);
        return hull;
      },
      []() -> std::optional<BodyHull<S>> { return std::nullopt; });
}

/// The hull of a box (an octree's occupied cells: a hull bound against it is a lower bound on the distance to the
/// cells, as against a mesh's vertices for the mesh).
template <typename S>
BodyHull<S> boxHull(const fcl::AABB<S>& box)
{
  const fcl::Vector3d center = box.center().template cast<double>();
  std::vector<fcl::Vector3d> points = detail::boxCorners(0.5 * (box.max_ - box.min_).template cast<double>());
  for (fcl::Vector3d& point : points) point += center;
  BodyHull<S> hull;
  hull.points = triangle_shape::HullPoints(std::move(points));
  hull.center = box.center();
  hull.reach = detail::hullReach(hull);
  return hull;
}

template <typename BV>
std::shared_ptr<fcl::CollisionGeometry<typename BV::S>> buildTree(const TriangleMesh<typename BV::S>& mesh)
{
  return buildModel<BV>(mesh);
}

template <typename S>
std::shared_ptr<fcl::CollisionGeometry<S>> buildTree(BVType bv, const TriangleMesh<S>& mesh)
{
  switch (bv)
  {
    case BVType::kRS: return buildTree<RS<S>>(mesh);
    case BVType::kOBBRSS: return buildTree<fcl::OBBRSS<S>>(mesh);
    case BVType::kOBB: return buildTree<fcl::OBB<S>>(mesh);
    case BVType::kRSS: return buildTree<fcl::RSS<S>>(mesh);
    case BVType::kKDOP18: break;
  }
  throw std::invalid_argument("fcl_rs::Environment: KDOP18 trees are refitted in place per check; use RS, OBBRSS, "
                              "OBB or RSS");
}

#if FCL_HAVE_OCTOMAP
/// Grows `box` by the octree's cells under `node` (whose cell is `cell`) that FCL's traversals, and fcl_rs's,
/// test: leaves reached through occupied nodes and occupied themselves (isNodeOccupied, the octree's threshold;
/// distance descends by this rule, collision without cost also skips uncertain nodes: fewer cells).
template <typename S>
void addOccupiedCells(const fcl::OcTree<S>& octree, const typename fcl::OcTree<S>::OcTreeNode* node,
                      const fcl::AABB<S>& cell, std::optional<fcl::AABB<S>>& box)
{
  if (!octree.isNodeOccupied(node)) return;
  if (!octree.nodeHasChildren(node))
  {
    box = box ? *box + cell : cell;
    return;
  }
  for (unsigned int i = 0; i < 8; ++i)
    if (octree.nodeChildExists(node, i))
    {
      fcl::AABB<S> child;
      fcl::computeChildBV(cell, i, child);  // as the traversals compute it, to the bit
      addOccupiedCells(octree, octree.getNodeChild(node, i), child, box);
    }
}

/// The box of the octree's occupied cells in its own frame (see addOccupiedCells); none for a map without any.
template <typename S>
std::optional<fcl::AABB<S>> occupiedCells(const fcl::OcTree<S>& octree)
{
  std::optional<fcl::AABB<S>> box;
  if (octree.getRoot()) addOccupiedCells(octree, octree.getRoot(), octree.getRootBV(), box);
  return box;
}
#endif

}  // namespace

/// Shapes whose RS volume bounds them (collidePlacedShape): all that addShape takes but planes and halfspaces,
/// which are unbounded (addShape refuses a TriangleP).
template <typename Shape>
constexpr bool placeable = !std::is_same_v<Shape, fcl::Plane<typename Shape::S>> &&
                           !std::is_same_v<Shape, fcl::Halfspace<typename Shape::S>> &&
                           !std::is_same_v<Shape, fcl::TriangleP<typename Shape::S>>;

/// The relative error motion checks allow their distances: a lower bound within this factor of the distance
/// certifies nearly as much and prunes far more of the trees.
constexpr double kMotionDistanceError = 0.25;

template <typename S>
struct Environment<S>::Impl
{
  struct Obstacle
  {
    std::string name;
    std::shared_ptr<fcl::CollisionGeometry<S>> geometry;
    Body<S> body;  ///< no element for an octree without occupied cells (nothing to touch or measure)
    Tf<S> pose;
    Tf<S> from_world;       ///< pose's inverse, set with it: every query's box gaps read it
    WorldSphere<S> sphere;  ///< at pose
    fcl::AABB<S> box;       ///< the geometry's box in its own frame (tighter than the ball for slabs such as tables;
                            ///< an octree's: its occupied cells')
    fcl::AABB<S> world_box;  ///< box at pose, in the root frame's axes (placeCulling)
    bool aligned = false;    ///< pose does not rotate, so world_box is box moved
    bool box_in_ball = false;  ///< the ball holds the box (a shape's), so the box gap is never below the balls'
    std::optional<Flat<S>> flat;  ///< a plane or halfspace, placed at pose (its sphere then holds everything)
    /// In an RS environment: the mesh's tree, or a shape's RS fitted once in its own frame (placed per query, so
    /// setPose keeps it), for the direct paths of linkHitsObstacle; unset otherwise.
    const fcl::BVHModel<RS<S>>* rs_mesh = nullptr;
    std::optional<RS<S>> shape_bv;
    /// A box's, sphere's, capsule's, cylinder's or mesh's hull, or the box of an octree's occupied cells (fit),
    /// which motion checks bound link distances with (SelfCollision::hullDistanceBound).
    std::optional<BodyHull<S>> hull;
    /// Per link that no joint moves (Impl::fixed_pose): whether it touches the obstacle, decided when the obstacle
    /// is added, moved or refreshed, since no configuration changes the answer.
    std::vector<std::uint8_t> fixed_link_hits;
  };

  /// A pair a motion check certifies: a self pair (pairs()[self_pair], other_link >= 0) or a link and an obstacle,
  /// with the moving joints that change their distance: the first `depth` joints up each link's chain
  /// (LinkSweeps: for a self pair those below the links' common ancestor).
  struct MotionPair
  {
    int link, other_link, obstacle, self_pair;
    int depth, other_depth;
  };

  /// One configuration along a motion: poses, link spheres, the sweep terms of the intervals it starts (a link's
  /// taken when a pair of the link first needs them), per pair a distance lower bound and the distance that was
  /// enough when it was last asked for (infinite once the bound is final), and whether some pair collides there.
  struct Sample
  {
    S t;
    std::vector<Tf<S>> poses;
    std::vector<WorldSphere<S>> spheres;
    std::vector<typename LinkSweeps<S>::Terms> terms;
    std::vector<std::uint8_t> has_terms;  ///< per link
    std::vector<S> bound;
    std::vector<S> asked;
    bool colliding = false;
  };

  /// An interval of a motion check: its end samples and its pairs, active[begin, end) of the check's Scratch.
  struct Interval
  {
    int a, b;
    std::size_t begin, end;
  };

  /// A pair whose motion an interval's end bounds do not cover (segment).
  struct Uncovered
  {
    S covered;  ///< the ends' bounds over the motion
    int pair;
    S motion;
  };

  /// What a motion check keeps between its steps, per thread and reused by the next check (whose vectors keep
  /// their capacity), so that checks in a planner's loop allocate nothing once warm.
  struct Scratch
  {
    std::vector<MotionPair> pairs;
    std::vector<Sample> samples;  ///< samples[0, used) are the check's
    std::size_t used = 0;
    std::vector<Interval> waiting;
    std::size_t head = 0;  ///< without earliest, waiting is a queue from here
    std::vector<int> active;  ///< the intervals' pair lists, back to back
    std::vector<int> remaining;
    std::vector<Uncovered> uncovered;
    std::vector<std::pair<S, S>> certified;
    fcl::VectorX<S> q;
    std::vector<int> near;  ///< motionPairs' obstacles of one link
  };

  Impl(const RobotModel& robot, BVType bv_type, const std::vector<DisabledCollision>& disabled)
    : bv(bv_type), self(robot, bv_type, disabled), sweeps(makeSweeps(robot, self)),
      self_motion_pairs(selfMotionPairs(self, sweeps))
  {
    if (bv == BVType::kKDOP18)
      throw std::invalid_argument("fcl_rs::Environment: KDOP18 trees are refitted in place per check, so they cannot "
                                  "be shared; use RS, OBBRSS, OBB or RSS");
    const int n = int(robot.links.size());
    links.resize(n);
    link_vertices.resize(n);
    for (int i = 0; i < n; ++i)
    {
      links[i].elements = self.linkElements(i);
      const LinkSphere<S> s = self.linkSphere(i);
      links[i].center = s.center;
      links[i].radius = s.radius;
      if (!links[i].elements.empty()) geometric_links.push_back(i);
      for (const fcl::Vector3d& v : robot.links[i].mesh.vertices) link_vertices[i].push_back(v.template cast<S>());
    }
    // Links no joint variable moves (a base on a table is tested once per obstacle, not at every query).
    const std::vector<Tf<S>> poses = self.kinematics().linkPoses(self.kinematics().lower());
    for (int link : geometric_links)
    {
      bool fixed = true;
      for (int j = robot.links[link].parent_joint; j >= 0; j = robot.links[robot.joints[j].parent_link].parent_joint)
        fixed = fixed && sweeps.jointVariable(j) < 0;
      if (fixed) fixed_pose.emplace_back(link, poses[link]);
    }
    fixed_link.assign(n, 0);
    for (const auto& [link, pose] : fixed_pose) fixed_link[link] = 1;
  }

  static LinkSweeps<S> makeSweeps(const RobotModel& robot, const SelfCollision<S>& self)
  {
    std::vector<fcl::Vector3<S>> centers;
    std::vector<S> radii;
    for (int i = 0; i < int(robot.links.size()); ++i)
    {
      const LinkSphere<S> ball = self.linkSphere(i);
      centers.push_back(ball.center);
      radii.push_back(ball.radius);
    }
    return LinkSweeps<S>(robot, self.kinematics(), centers, radii);
  }

  int find(const std::string& name) const
  {
    for (std::size_t i = 0; i < obstacles.size(); ++i)
      if (obstacles[i].name == name) return int(i);
    return -1;
  }

  int require(const std::string& name, const char* caller) const
  {
    const int i = find(name);
    if (i < 0)
      throw std::invalid_argument(std::string("fcl_rs::Environment::") + caller + ": no obstacle named '" + name + "'");
    return i;
  }

  /// Adds an obstacle; a mesh's hull comes with it (meshHull), a shape's is made here (shapeHull).
  void add(const std::string& name, std::shared_ptr<fcl::CollisionGeometry<S>> geometry, const Tf<S>& pose,
           std::optional<BodyHull<S>> hull = std::nullopt)
  {
    Obstacle o;
    o.name = name;
    o.geometry = std::move(geometry);
    o.hull = std::move(hull);
    if (!o.hull) o.hull = shapeHull(*o.geometry);
    o.pose = pose;
    o.from_world = pose.inverse(Eigen::Isometry);
    o.flat = flatAt(*o.geometry, pose);
    fit(o);
    if (bv == BVType::kRS)
    {
      o.rs_mesh = dynamic_cast<const fcl::BVHModel<RS<S>>*>(o.geometry.get());
      detail::withShape(
          *o.geometry,
          [&](const auto& shape) {
            if constexpr (placeable<std::decay_t<decltype(shape)>>)
            {
              RS<S> fitted;
              fcl::computeBV(shape, Tf<S>::Identity(), fitted);
              o.shape_bv = fitted;
            }
          },
          [] {});
    }
    touchFixedLinks(o);
    obstacles.push_back(std::move(o));
    indexObstacles();
  }

  /// Sets o.fixed_link_hits at o's pose (after fit, for an octree's current cells).
  void touchFixedLinks(Obstacle& o) const
  {
    o.fixed_link_hits.assign(links.size(), 0);
    if (o.body.elements.empty()) return;
    for (const auto& [link, pose] : fixed_pose) o.fixed_link_hits[link] = linkHitsObstacle(link, pose, o);
  }

  /// Whether the link at `pose` touches the obstacle (first contact): fcl_rs::collide's answer for each of the
  /// link's elements, without its per-call validation (the poses come from kinematics and validated obstacle poses,
  /// the request is fixed). RS link meshes meet RS mesh obstacles on the tree traversal directly and shapes through
  /// collidePlacedShape with the shape's volume fitted once (fcl_rs::collide would refit it per call); FCL's BV
  /// types take fcl::collide, as SelfCollision queries them.
  bool linkHitsObstacle(int link, const Tf<S>& pose, const Obstacle& o) const
  {
    if (o.flat)
    {
      const Heights<S> h = heights(link, pose, *o.flat);
      return h.lo <= 0 && (!o.flat->plane || h.hi >= 0);  // touching counts
    }
    const fcl::CollisionRequest<S> request(/*num_max_contacts=*/1, /*enable_contact=*/false);
    for (const LinkElement<S>& e : links[link].elements)
    {
      const Tf<S> tf = pose * e.origin;
      fcl::CollisionResult<S> result;
      if (bv != BVType::kRS)
      {
        if (fcl::collide(e.geometry, tf, o.geometry.get(), o.pose, request, result) > 0) return true;
        continue;
      }
      if (e.geometry->getObjectType() == fcl::OT_BVH && (o.rs_mesh || o.shape_bv))
      {
        const auto& mesh = static_cast<const fcl::BVHModel<RS<S>>&>(*e.geometry);
        if (o.rs_mesh ? meshHitsMesh(mesh, tf, *o.rs_mesh, o.pose, request, result)
                      : meshHitsShape(mesh, tf, o, request, result))
          return true;
        continue;
      }
      if (detail::collideValidated(e.geometry, tf, o.geometry.get(), o.pose, request, result) > 0) return true;
    }
    return false;
  }

  static bool meshHitsMesh(const fcl::BVHModel<RS<S>>& a, const Tf<S>& ta, const fcl::BVHModel<RS<S>>& b,
                           const Tf<S>& tb, const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
  {
    MeshCollisionTraversalNodeRS<S> node;
    initialize(node, a, ta, b, tb, request, result);
    collideTrees(node);
    return result.isCollision();
  }

  static bool meshHitsShape(const fcl::BVHModel<RS<S>>& mesh, const Tf<S>& tf, const Obstacle& o,
                            const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
  {
    fcl::detail::GJKSolver_libccd<S> solver;
    solver.collision_tolerance = request.gjk_tolerance;
    return detail::withShape(
        *o.geometry,
        [&](const auto& shape) -> bool {
          if constexpr (placeable<std::decay_t<decltype(shape)>>)
            return collidePlacedShape(mesh, tf, shape, *o.shape_bv, o.pose, solver, request, result);
          else
            throw std::logic_error("fcl_rs::Environment: an unbounded shape has no fitted volume");
        },
        []() -> bool { throw std::logic_error("fcl_rs::Environment: an obstacle with a fitted volume is no shape"); });
  }

  /// The obstacle's element and culling volumes, from what of its geometry can touch a link: all of it, or an
  /// octree's occupied cells (its own box is the whole root cube of the map).
  static void fit(Obstacle& o)
  {
    o.body = Body<S>();
    o.box = fcl::AABB<S>();
    if (o.flat)
    {
      // A ball holding everything; the gaps to a plane or halfspace are its own (obstacleGap), its box unused.
      o.body.elements.push_back({o.geometry.get(), Tf<S>::Identity()});
      o.sphere = WorldSphere<S>{fcl::Vector3<S>::Zero(), std::numeric_limits<S>::infinity()};
      return;
    }
#if FCL_HAVE_OCTOMAP
    if (o.geometry->getNodeType() == fcl::GEOM_OCTREE)
    {
      const std::optional<fcl::AABB<S>> cells = occupiedCells(static_cast<const fcl::OcTree<S>&>(*o.geometry));
      if (!cells)
      {
        o.sphere = WorldSphere<S>();
        o.hull.reset();
        return;
      }
      o.box = *cells;
      o.body.center = cells->center();
      o.body.radius = (cells->max_ - o.body.center).norm();
      o.hull = boxHull(*cells);
    }
    else
#endif
    {
      o.geometry->computeLocalAABB();
      o.box = o.geometry->aabb_local;
      o.body.center = o.geometry->aabb_center;
      o.body.radius = o.geometry->aabb_radius;
    }
    o.body.radius *= S(1 + 1e-6);
    o.box_in_ball = (o.box.max_ - o.body.center).norm() <= o.body.radius &&
                    (o.box.min_ - o.body.center).norm() <= o.body.radius;
    o.body.elements.push_back({o.geometry.get(), Tf<S>::Identity()});
    placeCulling(o);
  }

  /// The culling volumes of a fitted obstacle (not a plane or halfspace) at its pose: its ball, and the box around
  /// its own box's placed corners, grown by the rounding of placing them (16 ulps of each corner's terms).
  static void placeCulling(Obstacle& o)
  {
    o.sphere = place(o.body, o.pose);
    o.aligned = o.pose.linear() == fcl::Matrix3<S>::Identity();
    fcl::Vector3<S> lo = fcl::Vector3<S>::Constant(std::numeric_limits<S>::infinity()), hi = -lo;
    S terms = 0;
    for (int corner = 0; corner < 8; ++corner)
    {
      const fcl::Vector3<S> local(corner & 1 ? o.box.max_[0] : o.box.min_[0], corner & 2 ? o.box.max_[1] : o.box.min_[1],
                                  corner & 4 ? o.box.max_[2] : o.box.min_[2]);
      const fcl::Vector3<S> placed = o.pose * local;
      lo = lo.cwiseMin(placed);
      hi = hi.cwiseMax(placed);
      terms = std::max(terms, local.template lpNorm<1>());
    }
    const S pad = 16 * std::numeric_limits<S>::epsilon() * (terms + o.pose.translation().template lpNorm<1>());
    o.world_box = fcl::AABB<S>(lo - fcl::Vector3<S>::Constant(pad), hi + fcl::Vector3<S>::Constant(pad));
  }

  void checkNewName(const std::string& name) const
  {
    if (name.empty()) throw std::invalid_argument("fcl_rs::Environment: an obstacle name is empty");
    if (find(name) >= 0) throw std::invalid_argument("fcl_rs::Environment: an obstacle named '" + name + "' exists");
  }

  void placeLinks(const std::vector<Tf<S>>& poses, std::vector<WorldSphere<S>>& spheres) const
  {
    spheres.resize(links.size());
    for (int link : geometric_links) spheres[link] = place(links[link], poses[link]);
  }

  /// The obstacles whose world boxes and balls meet the box around every link ball, and the planes and halfspaces.
  void nearObstacles(const std::vector<WorldSphere<S>>& spheres, std::vector<int>& near) const
  {
    fcl::Vector3<S> lo = fcl::Vector3<S>::Constant(std::numeric_limits<S>::infinity()), hi = -lo;
    for (int link : geometric_links)
    {
      lo = lo.cwiseMin(spheres[link].centre - fcl::Vector3<S>::Constant(spheres[link].reach));
      hi = hi.cwiseMax(spheres[link].centre + fcl::Vector3<S>::Constant(spheres[link].reach));
    }
    obstaclesMeeting(fcl::AABB<S>(lo, hi), near);
    std::sort(near.begin(), near.end());  // pairs are reported link by link, obstacles in the order added
  }

  /// The planes and halfspaces, and the obstacles whose world boxes and balls meet `box` in the tree's order (found
  /// on obstacle_tree, so that hundreds of far obstacles cost little).
  void obstaclesMeeting(const fcl::AABB<S>& box, std::vector<int>& near) const
  {
    near = flat_obstacles;
    obstacle_tree.overlapping(box, [&](int i) {
      const WorldSphere<S>& s = obstacles[std::size_t(i)].sphere;
      if (squaredOutside(box, s.centre) <= s.reach * s.reach) near.push_back(i);
    });
  }

  /// Rebuilds the broad phase (obstacle_tree and the lists beside it) after an obstacle was added, moved,
  /// refreshed or removed.
  void indexObstacles()
  {
    obstacles_with_elements.clear();
    flat_obstacles.clear();
    std::vector<std::pair<fcl::AABB<S>, int>> boxes;
    for (std::size_t i = 0; i < obstacles.size(); ++i)
    {
      const Obstacle& o = obstacles[i];
      if (o.body.elements.empty()) continue;
      obstacles_with_elements.push_back(int(i));
      if (o.flat)
        flat_obstacles.push_back(int(i));
      else
        boxes.emplace_back(o.world_box, int(i));
    }
    obstacle_tree.build(std::move(boxes));
  }

  /// The gap between a link's ball and the obstacle's own box (the ball's centre moved into the obstacle's
  /// frame, or for a pose that does not rotate the box moved, world_box): tighter than the balls' for slabs such as
  /// tables and for an octree's occupied cells.
  static S boxGap(const WorldSphere<S>& ball, const Obstacle& o)
  {
    const S outside =
        o.aligned ? squaredOutside(o.world_box, ball.centre) : squaredOutside(o.box, o.from_world * ball.centre);
    return std::sqrt(outside) - ball.reach * S(1 + 1e-5);
  }

  /// A lower bound on the distance between a link's ball and an obstacle: the balls' gap or the gap to the
  /// obstacle's box, whichever is larger; for a plane or halfspace the ball centre's height over it.
  static S obstacleGap(const WorldSphere<S>& ball, const Obstacle& o)
  {
    if (o.flat)
    {
      const S height = o.flat->n.dot(ball.centre) - o.flat->d;
      return (o.flat->plane ? std::abs(height) : height) - ball.reach * S(1 + 1e-5);
    }
    return o.box_in_ball ? boxGap(ball, o) : std::max(sphereGap(ball, o.sphere), boxGap(ball, o));
  }

  /// Whether the link's ball may touch the obstacle: its world box (no rotation, no square root), the balls (a
  /// mesh's ball holds its vertices, not its box), then, for an obstacle whose pose rotates, its own box.
  static bool mayTouch(const WorldSphere<S>& ball, const Obstacle& o)
  {
    if (o.flat) return obstacleGap(ball, o) <= 0;
    const S reach = ball.reach * S(1 + 1e-5);  // boxGap's pad
    if (squaredOutside(o.world_box, ball.centre) > reach * reach || spheresApart(ball, o.sphere)) return false;
    return o.aligned || squaredOutside(o.box, o.from_world * ball.centre) <= reach * reach;
  }

  /// The squared distance from a point to a box (0 inside).
  static S squaredOutside(const fcl::AABB<S>& box, const fcl::Vector3<S>& point)
  {
    return (box.min_ - point).cwiseMax(point - box.max_).cwiseMax(S(0)).squaredNorm();
  }

  /// The link's extreme heights over a plane or halfspace, exact: a linear function's extremes over a mesh are at
  /// its vertices, over a box, cylinder or sphere at its support points along -n and n.
  Heights<S> heights(int link, const Tf<S>& pose, const Flat<S>& flat) const
  {
    Heights<S> h;
    const auto keep = [&](const fcl::Vector3<S>& x) {
      const S height = flat.n.dot(x) - flat.d;
      if (height < h.lo)
      {
        h.lo = height;
        h.lo_point = x;
      }
      if (height > h.hi)
      {
        h.hi = height;
        h.hi_point = x;
      }
    };
    for (const LinkElement<S>& e : links[link].elements)
    {
      const Tf<S> placed = pose * e.origin;
      if (e.geometry->getObjectType() == fcl::OT_BVH)
        for (const fcl::Vector3<S>& v : link_vertices[link]) keep(placed * v);
      else
      {
        const fcl::Vector3<S> u = placed.linear().transpose() * flat.n;
        keep(placed * linkShapeSupport(*e.geometry, fcl::Vector3<S>(-u)));
        keep(placed * linkShapeSupport(*e.geometry, u));
      }
    }
    return h;
  }

  /// bodiesDistance between the link at pose and the obstacle; exact for a plane or halfspace (rel_err unused).
  S linkDistance(int link, const Tf<S>& pose, const Obstacle& o, S bound, fcl::Vector3<S>* points, S rel_err = 0) const
  {
    if (!o.flat) return bodiesDistance(links[link], pose, o.body, o.pose, bound, points, rel_err);
    const Heights<S> h = heights(link, pose, *o.flat);
    // The side the link is on: above (lo > 0), or for a plane below (hi < 0); else they touch.
    const bool above = h.lo > 0, below = o.flat->plane && h.hi < 0;
    const S d = above ? h.lo : below ? -h.hi : S(0);
    if (d >= bound) return bound;
    if (points)
    {
      // The extreme point on the link's side and its foot on the flat (both the foot when they touch).
      points[0] = below ? h.hi_point : h.lo_point;
      points[1] = points[0] - (below ? h.hi : h.lo) * o.flat->n;
      if (d == 0) points[0] = points[1];
    }
    return d;
  }

  BodyPair selfPair(const LinkPair& p) const
  {
    return {self.linkNames()[p.first], self.linkNames()[p.second], true};
  }
  BodyPair obstaclePair(int link, int obstacle) const
  {
    return {self.linkNames()[link], obstacles[obstacle].name, false};
  }

  EnvironmentResult<S> query(const fcl::VectorX<S>& q, const EnvironmentRequest& request) const
  {
    validateConfiguration(q, self.kinematics().numVariables(), "configuration");
    if (request.minimum_distance && bv == BVType::kOBB)
      throw std::invalid_argument("fcl_rs::Environment::query: FCL has no distance query for OBB trees; use RS, "
                                  "OBBRSS or RSS for minimum distances");
    // Per thread, so that a query allocates nothing once its thread has run one (a planner makes millions).
    struct Scratch
    {
      std::vector<Tf<S>> poses;
      std::vector<WorldSphere<S>> spheres;
      std::vector<int> near;
    };
    static thread_local Scratch scratch;
    std::vector<Tf<S>>& poses = scratch.poses;
    self.kinematics().linkPoses(q, poses);
    EnvironmentResult<S> result;
    // The links' balls serve the self check's culling and the obstacles'.
    std::vector<WorldSphere<S>>& spheres = scratch.spheres;
    placeLinks(poses, spheres);
    SelfCheckRequest self_request;
    self_request.colliding_pairs = request.colliding_pairs;
    const SelfCheckResult<S> self_result =
        detail::SelfCollisionInternals<S>::queryPlaced(self, poses, spheres, self_request);
    result.colliding = self_result.colliding;
    for (const LinkPair& p : self_result.pairs) result.pairs.push_back(selfPair(p));
    const bool stop_at_first = !request.colliding_pairs;
    if (result.colliding && stop_at_first && !request.minimum_distance) return result;

    std::vector<int>& near = scratch.near;
    nearObstacles(spheres, near);
    if (!(result.colliding && stop_at_first))
      for (int link : geometric_links)
      {
        for (int o : near)
          if (fixed_link[link]
                  ? obstacles[o].fixed_link_hits[link]
                  : mayTouch(spheres[link], obstacles[o]) && linkHitsObstacle(link, poses[link], obstacles[o]))
          {
            result.colliding = true;
            if (stop_at_first) break;
            result.pairs.push_back(obstaclePair(link, o));
          }
        if (result.colliding && stop_at_first) break;
      }
    if (request.minimum_distance && !result.colliding) minimumDistance(poses, spheres, result);
    return result;
  }

  /// The smallest distance over the self pairs and link x obstacle pairs. The pairs go in order of a lower bound
  /// on their distance (the balls' gap, or for an obstacle the larger of that and the link ball's gap to the
  /// obstacle's own box): the nearest pairs set a small minimum early, each measurement starts at the best so far
  /// (bodiesDistance), and once a bound reaches it no later pair can lower it. The order depends on the
  /// configuration only, so the result does too.
  void minimumDistance(const std::vector<Tf<S>>& poses, const std::vector<WorldSphere<S>>& spheres,
                       EnvironmentResult<S>& result) const
  {
    struct Candidate
    {
      S bound;
      int first, second;  ///< a self pair's links, or a link and an obstacle's index
      bool self;
      bool operator<(const Candidate& other) const { return bound < other.bound; }
    };
    std::vector<Candidate> order;
    for (const LinkPair& p : self.pairs())
      order.push_back({sphereGap(spheres[p.first], spheres[p.second]), p.first, p.second, true});
    for (int link : geometric_links)
      for (int o = 0; o < int(obstacles.size()); ++o)
        if (!obstacles[o].body.elements.empty())
          order.push_back({obstacleGap(spheres[link], obstacles[o]), link, o, false});
    std::stable_sort(order.begin(), order.end());
    S best = std::numeric_limits<S>::infinity();
    fcl::Vector3<S> points[2];
    for (const Candidate& c : order)
    {
      if (c.bound >= best) break;
      const S d = c.self
                      ? bodiesDistance(links[c.first], poses[c.first], links[c.second], poses[c.second], best, points)
                      : linkDistance(c.first, poses[c.first], obstacles[c.second], best, points);
      if (d >= best) continue;
      best = d;
      result.nearest_pair = c.self ? selfPair({c.first, c.second}) : obstaclePair(c.first, c.second);
      result.nearest_points[0] = points[0];
      result.nearest_points[1] = points[1];
    }
    result.minimum_distance = best;
  }

  // ---- motion checks ----

  /// The pairs a motion from the placed sample `start` by `step` (per unit parameter) certifies, into x.pairs: the
  /// self pairs (made once, selfMotionPairs), then each link with the obstacles its ball may reach over the whole
  /// motion: those meeting the box around the ball at the start grown by the most it travels (LinkSweeps), cut to
  /// the box around the root that holds the ball in every configuration, and the planes and halfspaces; with every
  /// obstacle when the broad phase is a single leaf (a box would save nothing).
  void motionPairs(Sample& start, const fcl::VectorX<S>& step, S pad, Scratch& x) const
  {
    x.pairs = self_motion_pairs;
    const bool cull = obstacle_tree.branches();
    for (int link : geometric_links)
    {
      if (cull)
      {
        const WorldSphere<S>& ball = start.spheres[link];
        const S reach = ball.reach + S(sweep(start, step, link, sweeps.depth(link), S(1)) * (1 + 1e-6)) + pad;
        const fcl::Vector3<S> workspace = fcl::Vector3<S>::Constant(S(sweeps.workspace(link) * (1 + 1e-6)) + pad);
        obstaclesMeeting(fcl::AABB<S>((ball.centre - fcl::Vector3<S>::Constant(reach)).cwiseMax(-workspace),
                                      (ball.centre + fcl::Vector3<S>::Constant(reach)).cwiseMin(workspace)),
                         x.near);
      }
      for (int o : cull ? x.near : obstacles_with_elements)
        x.pairs.push_back({link, -1, o, -1, sweeps.depth(link), 0});
    }
  }

  static std::vector<MotionPair> selfMotionPairs(const SelfCollision<S>& self, const LinkSweeps<S>& sweeps)
  {
    std::vector<MotionPair> pairs;
    for (std::size_t i = 0; i < self.pairs().size(); ++i)
    {
      const LinkPair& p = self.pairs()[i];
      pairs.push_back({p.first, p.second, -1, int(i), sweeps.depthBelow(p.first, p.second),
                       sweeps.depthBelow(p.second, p.first)});
    }
    return pairs;
  }

  /// Places sample s at parameter t: its configuration's poses and link balls, no sweep terms yet. q: scratch.
  void placeSample(Sample& s, const fcl::VectorX<S>& from, const fcl::VectorX<S>& to, S t, fcl::VectorX<S>& q) const
  {
    s.t = t;
    q = from + t * (to - from);
    self.kinematics().linkPoses(q, s.poses);
    placeLinks(s.poses, s.spheres);
    s.terms.resize(sweeps.termsSize());
    s.has_terms.assign(links.size(), 0);
    s.colliding = false;
  }

  /// Sets the bound of each pair in [begin, end) of the placed sample s to its cheap gap (see gap), none asked for
  /// yet; no other pair's bound is read there.
  void boundSample(Sample& s, const std::vector<MotionPair>& pairs, const int* begin, const int* end) const
  {
    s.bound.resize(pairs.size());
    for (const int* i = begin; i != end; ++i) s.bound[*i] = gap(s, pairs[*i]);
    s.asked.assign(pairs.size(), 0);
  }

  /// A lower bound on the pair's distance: the balls' gap, or for an obstacle the gap between the link's ball and
  /// the obstacle's own box (the ball's centre moved into the obstacle's frame), whichever is larger.
  S gap(const Sample& s, const MotionPair& p) const
  {
    const WorldSphere<S>& ball = s.spheres[p.link];
    if (p.other_link >= 0) return std::max(S(0), sphereGap(ball, s.spheres[p.other_link]));
    return std::max(S(0), obstacleGap(ball, obstacles[p.obstacle]));
  }

  /// The most the link's ball moves relative to its ancestor `depth` joints up over the interval of length dt
  /// starting at s (LinkSweeps::sweep), with the link's terms taken at s once.
  double sweep(Sample& s, const fcl::VectorX<S>& step, int link, int depth, S dt) const
  {
    if (!s.has_terms[link])
    {
      sweeps.linkTerms(s.poses, step, link, s.terms);
      s.has_terms[link] = 1;
    }
    return sweeps.sweep(s.terms, link, depth, double(dt));
  }

  /// The most the pair's bodies move relative to each other over the interval of length dt starting at s, padded
  /// by `pad` for rounding.
  S moved(Sample& s, const fcl::VectorX<S>& step, const MotionPair& p, S dt, S pad) const
  {
    double m = sweep(s, step, p.link, p.depth, dt);
    if (p.other_link >= 0) m += sweep(s, step, p.other_link, p.other_depth, dt);
    return S(m * (1 + 1e-6)) + pad;
  }

  /// A lower bound on the distance between the link at s and the obstacle: the link's separation from the
  /// obstacle's box (its own frame's, which holds the geometry) along the normal of the face its ball's centre is
  /// farthest outside of.
  S faceSeparation(int link, const Sample& s, const Obstacle& o) const
  {
    const fcl::Vector3<S> c = o.from_world * s.spheres[link].centre;
    const fcl::Vector3<S> below = o.box.min_ - c, above = c - o.box.max_;
    int k;
    const S out = below.cwiseMax(above).maxCoeff(&k);
    const bool up = above[k] == out;
    // Along n = the face's outward normal, the box reaches n . pose.translation() + its face's offset.
    const fcl::Vector3<S> n = up ? fcl::Vector3<S>(o.pose.linear().col(k)) : fcl::Vector3<S>(-o.pose.linear().col(k));
    const S face = up ? o.box.max_[k] : -o.box.min_[k];
    // The box's side, rounded in S as the link's (SelfCollision::lowestAlong's margin).
    const S margin = S(1024) * std::numeric_limits<S>::epsilon() *
                     (o.pose.translation().template lpNorm<1>() + o.box.min_.norm() + o.box.max_.norm());
    return self.lowestAlong(link, s.poses[link], n) - (n.dot(o.pose.translation()) + face) - margin;
  }

  /// A lower bound on the pair's distance at s, as cheap as reaching `enough` allows: SelfCollision's search for
  /// self pairs; for obstacles the hulls' bound, then (obstacles without a hull) the distance with
  /// kMotionDistanceError started at enough. Without `measure`, bodies with hulls are not measured: the hulls'
  /// distance is a lower bound whatever their shapes, and nearly the distance for convex ones.
  S lowerBound(const Sample& s, const MotionPair& p, S enough, bool measure) const
  {
    if (p.other_link >= 0) return self.pairDistanceBound(s.poses, p.self_pair, enough, measure);
    const Obstacle& o = obstacles[p.obstacle];
    if (o.hull)
    {
      // Most pairs that need more than the balls' gap are certified by the link's separation from the obstacle's
      // box along one of its faces, one support point where GJK takes several.
      const S apart = faceSeparation(p.link, s, o);
      if (!(apart < enough)) return apart;
      const S d = std::max(apart, self.hullDistanceBound(p.link, s.poses[p.link], *o.hull, o.pose, enough));
      if (!(d < enough) || !measure) return d;
    }
    const S err = S(kMotionDistanceError);
    return linkDistance(p.link, s.poses[p.link], obstacles[p.obstacle], enough * S(1 + err), nullptr, err) /
           S(1 + err);
  }

  /// Raises the pair's bound at s towards `enough`. A bound within rounding of contact is decided by the collision
  /// test, as query decides it (s.colliding); when that finds the pair apart, the bound is measured (a link
  /// inside another's hull does not touch it).
  void refine(Sample& s, const MotionPair& p, int i, S enough, S contact, MotionResult<S>& result) const
  {
    if (!(enough > s.asked[i])) return;
    ++result.distance_queries;
    S d = lowerBound(s, p, enough, /*measure=*/false);
    if (d <= contact)
    {
      const bool self_pair = p.other_link >= 0;
      const Tf<S>& pose = s.poses[p.link];
      if (self_pair ? bodiesCollide(links[p.link], pose, links[p.other_link], s.poses[p.other_link])
                    : linkHitsObstacle(p.link, pose, obstacles[p.obstacle]))
      {
        s.bound[i] = 0;
        s.asked[i] = std::numeric_limits<S>::infinity();
        s.colliding = true;
        return;
      }
      ++result.distance_queries;
      d = lowerBound(s, p, enough, /*measure=*/true);
    }
    s.bound[i] = std::max(s.bound[i], d);
    // Below `enough` the answer is final: asking for more finds no more.
    s.asked[i] = d < enough ? std::numeric_limits<S>::infinity() : enough;
  }

  /// One segment, parameters in [0, 1] (see the class comment). free_until is where the intervals certified
  /// from 0 stop.
  MotionResult<S> segment(const fcl::VectorX<S>& from, const fcl::VectorX<S>& to, const MotionRequest<S>& request) const
  {
    static thread_local Scratch scratch;
    Scratch& x = scratch;
    const std::vector<MotionPair>& pairs = x.pairs;
    const fcl::VectorX<S> step = to - from;
    // Rounding of poses and distances in S, relative to the robot's reach.
    const S pad = S(32) * std::numeric_limits<S>::epsilon() * S(1 + sweeps.reach());
    // The start is placed first: its poses, balls and sweep terms also choose the pairs.
    if (x.samples.empty()) x.samples.emplace_back();
    placeSample(x.samples[0], from, to, S(0), x.q);
    motionPairs(x.samples[0], step, pad, x);
    const S shortest = std::max(S(1e-9), S(16) * std::numeric_limits<S>::epsilon());

    MotionResult<S> result;
    // With earliest, intervals are taken left first (a stack), so when a colliding configuration is reported
    // every interval before it has been certified. Without, coarse intervals first (a queue): a colliding segment
    // is found colliding at the first midpoint inside the collision, before the parts around it are certified.
    x.waiting.clear();
    x.head = 0;
    x.active.resize(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) x.active[i] = int(i);
    x.waiting.push_back({0, 1, 0, pairs.size()});
    const auto newSample = [&](S t, const int* begin, const int* end) {
      if (x.used == x.samples.size()) x.samples.emplace_back();
      placeSample(x.samples[x.used], from, to, t, x.q);
      boundSample(x.samples[x.used], pairs, begin, end);
      return int(x.used++);
    };
    boundSample(x.samples[0], pairs, x.active.data(), x.active.data() + pairs.size());
    x.used = 1;
    newSample(S(1), x.active.data(), x.active.data() + pairs.size());
    std::vector<std::pair<S, S>>& certified = x.certified;  // intervals found free
    certified.clear();
    const auto collision = [&](S t) {
      // free_until: where the certified intervals from 0 stop.
      std::sort(certified.begin(), certified.end());
      S free_until = 0;
      for (const auto& [lo, hi] : certified)
      {
        if (lo > free_until) break;
        free_until = std::max(free_until, hi);
      }
      result.colliding = true;
      result.parameter = t;
      result.free_until = std::min(free_until, t);
      result.configurations_checked = int(x.used);
      return result;
    };
    std::vector<int>& remaining = x.remaining;
    std::vector<Uncovered>& uncovered = x.uncovered;
    while (x.head < x.waiting.size())
    {
      Interval interval;
      if (request.earliest)
      {
        interval = x.waiting.back();
        x.waiting.pop_back();
      }
      else
        interval = x.waiting[x.head++];
      Sample& a = x.samples[std::size_t(interval.a)];
      Sample& b = x.samples[std::size_t(interval.b)];
      const S dt = b.t - a.t;
      remaining.clear();
      // Once a pair stays uncertified the interval is halved anyway: the other pairs' bounds are raised on the
      // halves, where less is enough (an interval too short to halve raises every bound).
      const bool thorough = dt < shortest;
      // The pairs whose motion the ends' bounds do not cover, those whose bounds cover least of it first: the
      // likeliest to stay uncertified (or to collide), so the others are not raised on an interval halved anyway.
      uncovered.clear();
      for (std::size_t k = interval.begin; k < interval.end; ++k)
      {
        const int i = x.active[k];
        const S m = moved(a, step, pairs[i], dt, pad);
        if (!(m < a.bound[i] + b.bound[i])) uncovered.push_back({(a.bound[i] + b.bound[i]) / m, i, m});
      }
      // A stable insertion sort: the lists are short, and std::stable_sort would allocate a buffer per interval.
      for (std::size_t k = 1; k < uncovered.size(); ++k)
      {
        const Uncovered u = uncovered[k];
        std::size_t j = k;
        for (; j > 0 && u.covered < uncovered[j - 1].covered; --j) uncovered[j] = uncovered[j - 1];
        uncovered[j] = u;
      }
      for (const auto& [covered, i, m] : uncovered)
      {
        if (!remaining.empty() && !thorough)
        {
          remaining.push_back(i);
          continue;
        }
        // Each end is asked only for what the other end's bound leaves of the motion (a pad more, so that a bound
        // that just reaches it covers): a bound search stops sooner the less it is asked for. The end with the
        // smaller bound goes first, asked for the least.
        Sample* ends[2] = {&a, &b};
        if (b.bound[i] < a.bound[i]) std::swap(ends[0], ends[1]);
        bool holds = false;
        for (int e = 0; e < 2 && !holds; ++e)
        {
          refine(*ends[e], pairs[i], i, m - ends[1 - e]->bound[i] + pad, pad, result);
          if (a.colliding) return collision(a.t);
          holds = m < a.bound[i] + b.bound[i];
        }
        if (!holds) remaining.push_back(i);
      }
      if (remaining.empty())
      {
        certified.emplace_back(a.t, b.t);
        if (b.colliding) return collision(b.t);
        continue;
      }
      if (b.colliding && (!request.earliest || dt <= request.tolerance)) return collision(b.t);
      // A pair that stays within rounding of contact without touching: bisection cannot certify it. An interval
      // this short joins configurations a few ulps apart, which the ends' bounds or collision tests found free.
      if (thorough)
      {
        certified.emplace_back(a.t, b.t);
        continue;
      }
      // The halves share the remaining pairs: appended once to active (which may move, so by offsets).
      const std::size_t begin = x.active.size();
      x.active.insert(x.active.end(), remaining.begin(), remaining.end());
      const std::size_t end = x.active.size();
      const S mid_t = S(0.5) * (a.t + b.t);
      const int mid = newSample(mid_t, x.active.data() + begin, x.active.data() + end);  // a and b are invalid now
      // What the ends' bounds leave at the midpoint: a bound less the most the pair moves on the way.
      Sample& start = x.samples[std::size_t(interval.a)];
      Sample& middle = x.samples[std::size_t(mid)];
      const Sample& finish = x.samples[std::size_t(interval.b)];
      const S half = middle.t - start.t;
      for (int i : remaining)
        middle.bound[i] = std::max({middle.bound[i], start.bound[i] - moved(start, step, pairs[i], half, pad),
                                    finish.bound[i] - moved(middle, step, pairs[i], half, pad)});
      if (request.earliest)  // the left half on top
      {
        x.waiting.push_back({mid, interval.b, begin, end});
        x.waiting.push_back({interval.a, mid, begin, end});
      }
      else
      {
        x.waiting.push_back({interval.a, mid, begin, end});
        x.waiting.push_back({mid, interval.b, begin, end});
      }
    }
    result.free_until = 1;
    result.configurations_checked = int(x.used);
    return result;
  }

  MotionResult<S> checkPath(const std::vector<fcl::VectorX<S>>& waypoints, const MotionRequest<S>& request) const
  {
    if (waypoints.empty()) throw std::invalid_argument("fcl_rs::Environment::checkPath: no waypoints");
    const int dof = self.kinematics().numVariables();
    for (std::size_t i = 0; i < waypoints.size(); ++i)
      validateConfiguration(waypoints[i], dof, ("waypoint " + std::to_string(i)).c_str());
    if (bv == BVType::kOBB)
      throw std::invalid_argument("fcl_rs::Environment: motion checks need distances, which FCL lacks for OBB "
                                  "trees; use RS, OBBRSS or RSS");
    if (!(request.tolerance > 0 && request.tolerance <= 1))
      throw std::invalid_argument("fcl_rs::Environment: motion tolerance " + std::to_string(double(request.tolerance)) +
                                  " is outside (0, 1]");
    MotionResult<S> total;
    const std::size_t segments = std::max<std::size_t>(1, waypoints.size() - 1);
    for (std::size_t i = 0; i < segments; ++i)
    {
      const fcl::VectorX<S>& to = waypoints[std::min(i + 1, waypoints.size() - 1)];
      MotionResult<S> one = segment(waypoints[i], to, request);
      total.configurations_checked += one.configurations_checked;
      total.distance_queries += one.distance_queries;
      total.free_until = S(i) + one.free_until;
      if (one.colliding)
      {
        total.colliding = true;
        total.parameter = S(i) + one.parameter;
        return total;
      }
    }
    return total;
  }

  BVType bv;
  SelfCollision<S> self;
  LinkSweeps<S> sweeps;
  std::vector<Body<S>> links;
  std::vector<std::vector<fcl::Vector3<S>>> link_vertices;  ///< each link's mesh vertices, link frame (heights)
  std::vector<int> geometric_links;
  std::vector<Obstacle> obstacles;
  // The broad phase (indexObstacles): a tree of the world boxes of the obstacles with a box, the planes and
  // halfspaces apart, and every obstacle with something to meet.
  detail::BoxTree<S> obstacle_tree;
  std::vector<int> flat_obstacles;
  std::vector<int> obstacles_with_elements;
  std::vector<MotionPair> self_motion_pairs;       ///< motionPairs' self pairs, which obstacles do not change
  std::vector<std::pair<int, Tf<S>>> fixed_pose;  ///< the geometric links no joint variable moves, at their pose
  std::vector<std::uint8_t> fixed_link;           ///< per link: one of fixed_pose
};

template <typename S>
Environment<S>::Environment(const RobotModel& robot, BVType bv, const std::vector<DisabledCollision>& disabled)
  : impl_(std::make_unique<Impl>(robot, bv, disabled))
{
}

template <typename S>
Environment<S>::~Environment() = default;
template <typename S>
Environment<S>::Environment(Environment&&) noexcept = default;
template <typename S>
Environment<S>& Environment<S>::operator=(Environment&&) noexcept = default;

template <typename S>
const SelfCollision<S>& Environment<S>::selfCollision() const
{
  return impl_->self;
}

template <typename S>
const Kinematics<S>& Environment<S>::kinematics() const
{
  return impl_->self.kinematics();
}

template <typename S>
BVType Environment<S>::bvType() const
{
  return impl_->bv;
}

template <typename S>
void Environment<S>::addShape(const std::string& name, std::shared_ptr<fcl::CollisionGeometry<S>> shape,
                              const fcl::Transform3<S>& pose)
{
  impl_->checkNewName(name);
  if (!shape) throw std::invalid_argument("fcl_rs::Environment::addShape: obstacle '" + name + "' has no geometry");
  // Every primitive shape but a TriangleP, for which FCL pairs with no link shape and no mesh of its own BV types.
  detail::withShape(
      *shape,
      [&](const auto& s) {
        if constexpr (std::is_same_v<std::decay_t<decltype(s)>, fcl::TriangleP<S>>)
          throw std::invalid_argument("fcl_rs::Environment::addShape: obstacle '" + name +
                                      "' is a TriangleP, which FCL cannot test against link shapes; use addMesh");
      },
      [&] {
        throw std::invalid_argument("fcl_rs::Environment::addShape: obstacle '" + name +
                                    "' is not a primitive shape (meshes go through addMesh, octomaps addOcTree)");
      });
  requireValidShape(shape.get(), "fcl_rs::Environment::addShape", ("obstacle '" + name + "'").c_str());
  requireRigidTransform(pose, kApi, ("the pose of obstacle '" + name + "'").c_str());
  impl_->add(name, std::move(shape), pose);
}

template <typename S>
void Environment<S>::addMesh(const std::string& name, const TriangleMesh<S>& mesh, const fcl::Transform3<S>& pose)
{
  impl_->checkNewName(name);
  requireRigidTransform(pose, kApi, ("the pose of obstacle '" + name + "'").c_str());
  impl_->add(name, buildTree<S>(impl_->bv, mesh), pose, meshHull(mesh));
}

#if FCL_HAVE_OCTOMAP
template <typename S>
void Environment<S>::addOcTree(const std::string& name, std::shared_ptr<fcl::OcTree<S>> octree,
                               const fcl::Transform3<S>& pose)
{
  impl_->checkNewName(name);
  if (!octree) throw std::invalid_argument("fcl_rs::Environment::addOcTree: obstacle '" + name + "' has no octree");
  requireRigidTransform(pose, kApi, ("the pose of obstacle '" + name + "'").c_str());
  impl_->add(name, std::move(octree), pose);
}

template <typename S>
void Environment<S>::refreshOcTree(const std::string& name)
{
  auto& o = impl_->obstacles[impl_->require(name, "refreshOcTree")];
  if (o.geometry->getNodeType() != fcl::GEOM_OCTREE)
    throw std::invalid_argument("fcl_rs::Environment::refreshOcTree: obstacle '" + name + "' is not an octree");
  Impl::fit(o);
  impl_->touchFixedLinks(o);
  impl_->indexObstacles();
}
#endif

template <typename S>
void Environment<S>::setPose(const std::string& name, const fcl::Transform3<S>& pose)
{
  const int i = impl_->require(name, "setPose");
  requireRigidTransform(pose, kApi, ("the pose of obstacle '" + name + "'").c_str());
  auto& o = impl_->obstacles[i];
  o.pose = pose;
  o.from_world = pose.inverse(Eigen::Isometry);
  o.flat = flatAt(*o.geometry, pose);
  if (!o.flat && !o.body.elements.empty()) Impl::placeCulling(o);
  impl_->touchFixedLinks(o);
  impl_->indexObstacles();
}

template <typename S>
void Environment<S>::remove(const std::string& name)
{
  impl_->obstacles.erase(impl_->obstacles.begin() + impl_->require(name, "remove"));
  impl_->indexObstacles();
}

template <typename S>
bool Environment<S>::contains(const std::string& name) const
{
  return impl_->find(name) >= 0;
}

template <typename S>
std::vector<std::string> Environment<S>::obstacleNames() const
{
  std::vector<std::string> names;
  for (const auto& o : impl_->obstacles) names.push_back(o.name);
  return names;
}

template <typename S>
const fcl::Transform3<S>& Environment<S>::pose(const std::string& name) const
{
  return impl_->obstacles[impl_->require(name, "pose")].pose;
}

template <typename S>
EnvironmentResult<S> Environment<S>::query(const fcl::VectorX<S>& q, const EnvironmentRequest& request) const
{
  return impl_->query(q, request);
}

template <typename S>
MotionResult<S> Environment<S>::checkMotion(const fcl::VectorX<S>& from, const fcl::VectorX<S>& to,
                                            const MotionRequest<S>& request) const
{
  const int dof = kinematics().numVariables();
  validateConfiguration(from, dof, "motion start");
  validateConfiguration(to, dof, "motion end");
  return impl_->checkPath({from, to}, request);
}

template <typename S>
MotionResult<S> Environment<S>::checkPath(const std::vector<fcl::VectorX<S>>& waypoints,
                                          const MotionRequest<S>& request) const
{
  return impl_->checkPath(waypoints, request);
}

#define FCL_RS_INSTANTIATE_ENVIRONMENT(S) template class Environment<S>;
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_ENVIRONMENT)
#undef FCL_RS_INSTANTIATE_ENVIRONMENT

}  // namespace fcl_rs
