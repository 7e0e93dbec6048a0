// SelfCollision: per-link collision models of a run-time BV type, bounding-sphere filter, pair tests.
#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/robot/self_collision.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <type_traits>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include "../scalars.h"
#include "../validated_entries.h"
#include "body_hulls.h"
#include "self_collision_internals.h"
#include "world_balls.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/fcl_float.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/collision_traversal.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {

const char* bvTypeName(BVType bv)
{
  switch (bv)
  {
    case BVType::kRS: return "RS";
    case BVType::kOBBRSS: return "OBBRSS";
    case BVType::kOBB: return "OBB";
    case BVType::kRSS: return "RSS";
    case BVType::kKDOP18: return "KDOP18";
  }
  return "?";
}

BVType parseBVType(const std::string& name)
{
  std::string upper = name;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  std::string names;
  for (BVType bv : kRobotBVTypes)
  {
    if (upper == bvTypeName(bv)) return bv;
    names += std::string(names.empty() ? "" : ", ") + bvTypeName(bv);
  }
  throw std::invalid_argument("fcl_rs: unknown BV type '" + name + "' (expected one of " + names + ")");
}

namespace {

template <typename S>
using Tf = fcl::Transform3<S>;

/// GJK on hulls whose bound is not measured further (motion checks' bounds) stops once its certified bound is within
/// this fraction of the distance reached. A motion check asks for what covers a pair's motion: GJK goes on while the
/// bound stays below that, and a bound that stops below it cannot cover the interval, which is halved anyway, so
/// refining it further buys little.
constexpr double kUnmeasuredHullGap = 0.5;

/// x rounded down to S, so that a lower bound computed in double stays one.
template <typename S>
S roundedDown(double x)
{
  const S rounded = S(x);
  return double(rounded) > x ? std::nextafter(rounded, -std::numeric_limits<S>::infinity()) : rounded;
}

/// |ta.t|_1 + |tb.t|_1: what an RS test between volumes posed by ta and tb adds for the world frame's rounding
/// (as the tree traversals do).
template <typename S>
S worldOffsets(const Tf<S>& ta, const Tf<S>& tb)
{
  return ta.translation().template lpNorm<1>() + tb.translation().template lpNorm<1>();
}

/// A box, cylinder or sphere element of a link.
template <typename S>
struct LinkShape
{
  std::shared_ptr<fcl::CollisionGeometry<S>> geometry;
  Tf<S> origin;  ///< in the link frame
  RS<S> bv;      ///< its RS in its own frame, fitted once (RS checks place it per query instead of refitting)
};

/// f(shape) for a link's shape, cast to its type: a box, cylinder or sphere (makeShape).
template <typename S, typename F>
bool withLinkShape(const fcl::CollisionGeometry<S>& geometry, F&& f)
{
  const auto not_a_link_shape = []() -> bool {
    throw std::logic_error("fcl_rs::SelfCollision: a link shape is not a box, cylinder or sphere");
  };
  return detail::withShape(
      geometry,
      [&](const auto& shape) -> bool {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Box<S>> || std::is_same_v<Shape, fcl::Cylinder<S>> ||
                      std::is_same_v<Shape, fcl::Sphere<S>>)
          return f(shape);
        else
          return not_a_link_shape();
      },
      not_a_link_shape);
}

/// The mesh trees of all links for one BV type, and the mesh-mesh and mesh-shape tests on them.
template <typename S>
class MeshTrees
{
public:
  virtual ~MeshTrees() = default;
  /// Called once per check before any test, with the poses every test of the check uses.
  virtual void setPoses(const Tf<S>* /*poses*/) const {}
  virtual bool meshMesh(int a, const Tf<S>& ta, int b, const Tf<S>& tb, const fcl::CollisionRequest<S>& request,
                        QueryStats* stats) const = 0;
  virtual bool meshShape(int a, const Tf<S>& ta, const LinkShape<S>& shape, const Tf<S>& ts,
                         const fcl::CollisionRequest<S>& request) const = 0;
  /// The link's tree in its own frame, queried read-only; nullptr when the trees are updated per check.
  virtual const fcl::CollisionGeometry<S>* localModel(int link) const = 0;
};

/// RS, OBBRSS, OBB, RSS: trees stay in their link frames; queries use the relative transform.
template <typename BV>
class LocalTrees : public MeshTrees<typename BV::S>
{
  using S = typename BV::S;

public:
  explicit LocalTrees(const std::vector<TriangleMesh<S>>& meshes)
  {
    for (const auto& m : meshes) models_.push_back(m.triangles.empty() ? nullptr : buildModel<BV>(m));
  }
  bool meshMesh(int a, const Tf<S>& ta, int b, const Tf<S>& tb, const fcl::CollisionRequest<S>& request,
                QueryStats* stats) const override
  {
    fcl::CollisionResult<S> result;
    const QueryStats s = collideWithStats(*models_[a], ta, *models_[b], tb, request, result);
    if (stats)
    {
      stats->num_bv_tests += s.num_bv_tests;
      stats->num_leaf_tests += s.num_leaf_tests;
      stats->num_node_pairs += s.num_node_pairs;
    }
    return result.isCollision();
  }
  /// FCL's types through fcl::collide; RS through its traversal node directly, the shape's RS placed rather
  /// than refitted (what fcl_rs::collide does otherwise, after finding the types).
  bool meshShape(int a, const Tf<S>& ta, const LinkShape<S>& shape, const Tf<S>& ts,
                 const fcl::CollisionRequest<S>& request) const override
  {
    if constexpr (std::is_same<BV, RS<S>>::value)
    {
      return withLinkShape(*shape.geometry,
                           [&](const auto& geometry) { return meshShapeRS(a, ta, geometry, shape, ts, request); });
    }
    else
    {
      fcl::CollisionResult<S> result;
      return fcl::collide(models_[a].get(), ta, shape.geometry.get(), ts, request, result) > 0;
    }
  }
  const fcl::CollisionGeometry<S>* localModel(int link) const override { return models_[link].get(); }

private:
  template <typename Shape>
  bool meshShapeRS(int a, const Tf<S>& ta, const Shape& geometry, const LinkShape<S>& shape, const Tf<S>& ts,
                   const fcl::CollisionRequest<S>& request) const
  {
    fcl::detail::GJKSolver_libccd<S> solver;
    solver.collision_tolerance = request.gjk_tolerance;
    fcl::CollisionResult<S> result;
    return collidePlacedShape(*models_[a], ta, geometry, shape.bv, ts, solver, request, result);
  }

  std::vector<std::shared_ptr<fcl::BVHModel<BV>>> models_;
};

/// KDOP18: world-frame trees, refitted on demand once per check (see the class comment in self_collision.h).
template <typename S>
class WorldKDOPTrees : public MeshTrees<S>
{
  using BV = fcl::KDOP<S, 18>;
  using Solver = fcl::detail::GJKSolver_libccd<S>;

public:
  explicit WorldKDOPTrees(const std::vector<TriangleMesh<S>>& meshes)
  {
    for (const auto& m : meshes)
    {
      models_.push_back(m.triangles.empty() ? nullptr : buildModel<BV>(m));
      local_.push_back(m.vertices);
    }
    current_.assign(meshes.size(), false);
  }
  void setPoses(const Tf<S>* poses) const override
  {
    poses_ = poses;
    std::fill(current_.begin(), current_.end(), false);
  }
  bool meshMesh(int a, const Tf<S>&, int b, const Tf<S>&, const fcl::CollisionRequest<S>& request,
                QueryStats* stats) const override
  {
    fcl::detail::MeshCollisionTraversalNode<BV> node;
    fcl::CollisionResult<S> result;
    Tf<S> identity1 = Tf<S>::Identity(), identity2 = Tf<S>::Identity();
    fcl::detail::initialize(node, world(a), identity1, world(b), identity2, request, result);
    node.enable_statistics = stats != nullptr;
    fcl::detail::collide(&node);
    if (stats)
    {
      stats->num_bv_tests += node.num_bv_tests;
      stats->num_leaf_tests += node.num_leaf_tests;
      stats->num_node_pairs += node.num_bv_tests;
    }
    return result.isCollision();
  }
  bool meshShape(int a, const Tf<S>&, const LinkShape<S>& link_shape, const Tf<S>& ts,
                 const fcl::CollisionRequest<S>& request) const override
  {
    return withLinkShape(*link_shape.geometry,
                         [&](const auto& shape) { return meshShapeOf(a, shape, ts, request); });
  }

  const fcl::CollisionGeometry<S>* localModel(int) const override { return nullptr; }

private:
  // The refit cache behind the const interface: SelfCollision::query refuses KDOP18, so only the
  // single-threaded check path updates it.
  fcl::BVHModel<BV>& world(int link) const
  {
    fcl::BVHModel<BV>& m = *models_[link];
    if (current_[link]) return m;
    const Tf<S>& pose = poses_[link];
    m.beginReplaceModel();
    for (const auto& v : local_[link]) m.replaceVertex(pose * v);
    m.endReplaceModel(/*refit=*/true, /*bottomup=*/true);
    current_[link] = true;
    return m;
  }
  template <typename Shape>
  bool meshShapeOf(int a, const Shape& shape, const Tf<S>& ts, const fcl::CollisionRequest<S>& request) const
  {
    fcl::detail::MeshShapeCollisionTraversalNode<BV, Shape, Solver> node;
    fcl::CollisionResult<S> result;
    Tf<S> identity = Tf<S>::Identity();
    fcl::detail::initialize(node, world(a), identity, shape, ts, &solver_, request, result);
    fcl::detail::collide(&node);
    return result.isCollision();
  }

  std::vector<std::shared_ptr<fcl::BVHModel<BV>>> models_;
  std::vector<std::vector<fcl::Vector3<S>>> local_;
  mutable std::vector<bool> current_;
  mutable const Tf<S>* poses_ = nullptr;
  Solver solver_;
};

template <typename S>
std::unique_ptr<MeshTrees<S>> makeTrees(BVType bv, const std::vector<TriangleMesh<S>>& meshes)
{
  switch (bv)
  {
    case BVType::kRS: return std::make_unique<LocalTrees<RS<S>>>(meshes);
    case BVType::kOBBRSS: return std::make_unique<LocalTrees<fcl::OBBRSS<S>>>(meshes);
    case BVType::kOBB: return std::make_unique<LocalTrees<fcl::OBB<S>>>(meshes);
    case BVType::kRSS: return std::make_unique<LocalTrees<fcl::RSS<S>>>(meshes);
    case BVType::kKDOP18: return std::make_unique<WorldKDOPTrees<S>>(meshes);
  }
  throw std::invalid_argument("fcl_rs::SelfCollision: unknown BV type");
}

template <typename S, typename Shape>
LinkShape<S> makeShape(const Shape& shape, const Primitive& p)
{
  LinkShape<S> made{std::make_shared<Shape>(shape), p.origin.template cast<S>(), RS<S>()};
  made.geometry->computeLocalAABB();
  fcl::computeBV(shape, Tf<S>::Identity(), made.bv);
  return made;
}

template <typename S>
LinkShape<S> makeShape(const Primitive& p)
{
  switch (p.type)
  {
    case Primitive::Type::kBox: return makeShape<S>(fcl::Box<S>(p.size.cast<S>()), p);
    case Primitive::Type::kCylinder: return makeShape<S>(fcl::Cylinder<S>(S(p.size[0]), S(p.size[1])), p);
    case Primitive::Type::kSphere: return makeShape<S>(fcl::Sphere<S>(S(p.size[0])), p);
  }
  throw std::logic_error("fcl_rs::SelfCollision: unknown primitive type");
}

/// Radius of a ball about the primitive's origin that holds it.
double primitiveRadius(const Primitive& p)
{
  switch (p.type)
  {
    case Primitive::Type::kBox: return 0.5 * p.size.norm();
    case Primitive::Type::kCylinder: return std::hypot(p.size[0], 0.5 * p.size[1]);
    case Primitive::Type::kSphere: return p.size[0];
  }
  return 0;
}

/// Points of the primitive's frame whose convex hull, grown by `radius`, holds the primitive: a box's corners, a
/// cylinder's box's corners (a superset, so distances to it are lower bounds), a sphere's centre grown by its
/// radius.
std::vector<fcl::Vector3d> primitiveHullPoints(const Primitive& p, double& radius)
{
  radius = 0;
  fcl::Vector3d half = fcl::Vector3d::Zero();
  switch (p.type)
  {
    case Primitive::Type::kBox: half = 0.5 * p.size; break;
    case Primitive::Type::kCylinder: half = fcl::Vector3d(p.size[0], p.size[0], 0.5 * p.size[1]); break;
    case Primitive::Type::kSphere: radius = p.size[0]; return {fcl::Vector3d::Zero()};
  }
  return detail::boxCorners(half);
}

/// Whether the plane of every triangle of mesh with area has all `points` on one side, to 1e-2 of their reach.
bool convexPosition(const TriangleMesh<double>& mesh, const std::vector<fcl::Vector3d>& points)
{
  double reach = 0;
  for (const fcl::Vector3d& p : points) reach = std::max(reach, p.norm());
  const double tolerance = 1e-2 * reach;
  for (const auto& t : mesh.triangles)
  {
    const fcl::Vector3d& v0 = mesh.vertices[t[0]];
    const fcl::Vector3d normal = (mesh.vertices[t[1]] - v0).cross(mesh.vertices[t[2]] - v0);
    if (!(normal.norm() > 0)) continue;
    const fcl::Vector3d unit = normal.normalized();
    double below = 0, above = 0;
    for (const fcl::Vector3d& p : points)
    {
      const double h = unit.dot(p - v0);
      below = std::min(below, h);
      above = std::max(above, h);
      if (below < -tolerance && above > tolerance) return false;
    }
  }
  return true;
}

}  // namespace

template <typename S>
BodyHull<S> meshHull(const TriangleMesh<S>& mesh, bool* convex)
{
  // Distinct vertices only (a mesh file may repeat each vertex per triangle): GJK's scans meet each once, and
  // its walks follow the triangles' edges between them.
  TriangleMesh<double> exact;
  for (const auto& v : mesh.vertices) exact.vertices.push_back(v.template cast<double>());
  exact.triangles = mesh.triangles;
  std::vector<fcl::Vector3d> points = exact.vertices;
  const auto before = [](const fcl::Vector3d& x, const fcl::Vector3d& y) {
    return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
  };
  std::sort(points.begin(), points.end(), before);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  std::vector<std::array<std::size_t, 3>> triangles;
  for (const fcl::Triangle& t : mesh.triangles)
  {
    std::array<std::size_t, 3> ids;
    for (int k = 0; k < 3; ++k)
      ids[std::size_t(k)] =
          std::size_t(std::lower_bound(points.begin(), points.end(), exact.vertices[t[k]], before) - points.begin());
    triangles.push_back(ids);
  }
  if (convex) *convex = convexPosition(exact, points);
  fcl::Vector3d lo = fcl::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const fcl::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  BodyHull<S> hull;
  hull.points = triangle_shape::HullPoints(std::move(points), triangles);
  hull.center = (0.5 * (lo + hi)).cast<S>();
  hull.reach = detail::hullReach(hull);
  return hull;
}

template <typename S>
struct SelfCollision<S>::Impl
{
  using Shape = LinkShape<S>;
  /// One collision element of a link as the minimum-distance search bounds it: a ball about it in the link frame
  /// and its hull.
  struct Element
  {
    const fcl::CollisionGeometry<S>* geometry = nullptr;  ///< the mesh tree (in the checker's BV type) or a shape
    Tf<S> origin = Tf<S>::Identity();                     ///< in the link frame
    fcl::Vector3<S> center = fcl::Vector3<S>::Zero();
    S radius = 0;
    /// In the link frame: the mesh's vertices (with its edges), or primitiveHullPoints; about `center`.
    BodyHull<S> hull;
    /// Whether every triangle's plane has all the mesh's vertices on one side (to 1e-2 of its reach); shapes are.
    /// Only convex elements are measured along their hulls' gap direction: elsewhere the direction leaves too
    /// many triangles, and finding that out would cost more than it saves.
    bool convex = true;
  };
  struct Link
  {
    bool has_mesh = false;
    std::vector<Shape> shapes;
    fcl::Vector3<S> center = fcl::Vector3<S>::Zero();  ///< bounding sphere in the link frame
    S radius = 0;
    RS<S> bound;  ///< every element in one RS volume, in the link frame (RS checks test it after the spheres)
    /// bound's frame for the pair test, made once: a check only moves it (BoxedFrame::move), the parts that do
    /// not depend on the motion (box, diagonal slabs) are kept.
    detail::BoxedFrame<S> bound_frame;
    std::vector<Element> elements;  ///< the mesh first, then the shapes
  };

  /// A link's bounding sphere in the root frame (detail::placeBall).
  using WorldSphere = detail::WorldSphere<S>;
  /// What a check computes once per configuration: the links' spheres at the link poses (a link takes part in
  /// several pairs). The poses are the caller's, one per link, and outlive the check.
  struct Placement
  {
    const Tf<S>* poses = nullptr;
    const WorldSphere* spheres = nullptr;  ///< per link: placed's, or the caller's (queryPlaced)
    std::vector<WorldSphere> placed;
    std::vector<int> near;  ///< the pairs whose spheres overlap: the first near_count entries (nearPairs)
    int near_count = 0;
  };

  Impl(const RobotModel& robot, BVType bv_type) : bv(bv_type), kinematics(robot) {}

  /// The placement of queryPoses and queryPlaced, per thread, so that a query allocates nothing once its thread has
  /// run one (a planner makes millions).
  static Placement& threadPlacement()
  {
    static thread_local Placement placement;
    return placement;
  }

  /// Places p.placed's spheres at p.poses for the links of the pair list (the others' are left as they were) and
  /// points p.spheres at them.
  void placeSpheres(Placement& p) const
  {
    p.placed.resize(links.size());
    for (int i : paired_links) p.placed[i] = detail::placeBall(p.poses[i], links[i].center, links[i].radius);
    p.spheres = p.placed.data();
  }

  /// detail::spheresApart of links a's and b's placed spheres.
  static bool spheresApart(const Placement& p, int a, int b)
  {
    return detail::spheresApart(p.spheres[a], p.spheres[b]);
  }

  /// Whether the links' RS volumes (Link::bound) may overlap at their poses.
  bool boundsOverlap(const Placement& p, int a, int b) const
  {
    const Tf<S>& ta = p.poses[a];
    const Tf<S>& tb = p.poses[b];
    const fcl::Matrix3<S> R = ta.linear().transpose() * tb.linear();
    const fcl::Vector3<S> T = ta.linear().transpose() * (tb.translation() - ta.translation());
    detail::BoxedFrame<S> moved = links[b].bound_frame;
    moved.move(R, T, links[b].bound, worldOffsets(ta, tb));
    return detail::overlap(moved, links[a].bound, links[b].bound, kDefaultOverlapTest);
  }

  /// A lower bound on the distance between RS volumes a and b of the link frames posed by ta and tb.
  static S boundsDistance(const Tf<S>& ta, const RS<S>& a, const Tf<S>& tb, const RS<S>& b)
  {
    const fcl::Matrix3<S> R = ta.linear().transpose() * tb.linear();
    const fcl::Vector3<S> T = ta.linear().transpose() * (tb.translation() - ta.translation());
    // The relative pose carries the world frame's rounding: a few ulps of the poses' offsets.
    return distance(R, T, a, b) - 8 * std::numeric_limits<S>::epsilon() * worldOffsets(ta, tb);
  }

  /// A lower bound on the distance between hulls a and b of bodies posed by ta and tb: the distance of their
  /// points' hulls as GJK certifies it, less both hull radii and a margin of 1024 ulps of S on the poses' offsets
  /// and the hulls' reaches, which covers the rounding of the exact distance measured (in S, in the links' relative
  /// frame) and of the bound. GJK stops once the bound exceeds `enough`, the best distance so far (the pair is
  /// skipped then, whatever its bound). direction: world frame, from a's hull towards b's.
  static S hullDistance(const Tf<S>& ta, const BodyHull<S>& a, const Tf<S>& tb, const BodyHull<S>& b, S enough,
                        fcl::Vector3d& direction, double relative_gap = triangle_shape::kIterativeRelativeGap)
  {
    const Eigen::Isometry3d pa = ta.template cast<double>(), pb = tb.template cast<double>();
    const double margin = 1024 * double(std::numeric_limits<S>::epsilon()) *
                          (pa.translation().lpNorm<1>() + pb.translation().lpNorm<1>() + a.reach + b.reach);
    const double shrink = a.radius + b.radius + margin;
    const fcl::Vector3d start = pa * a.center.template cast<double>() - pb * b.center.template cast<double>();
    const double bound =
        triangle_shape::hullsLowerBound(a.points, pa, b.points, pb, start, double(enough) + shrink, &direction,
                                        relative_gap) -
        shrink;
    return roundedDown<S>(bound);
  }

  /// Whether links a and b collide, for links whose spheres overlap (spheresApart is the caller's: most pairs end
  /// there, and the test costs about as much as the call).
  bool collides(const Placement& placement, int a, int b, QueryStats* stats) const
  {
    // The spheres of links that are near each other overlap in most configurations; their RS volumes are far
    // tighter and one test is cheaper than setting up the element queries it usually rules out.
    if (bv == BVType::kRS && !boundsOverlap(placement, a, b)) return false;
    const Link& la = links[a];
    const Link& lb = links[b];
    const Tf<S>& ta = placement.poses[a];
    const Tf<S>& tb = placement.poses[b];

    if (la.has_mesh && lb.has_mesh && trees->meshMesh(a, ta, b, tb, request, stats)) return true;
    if (la.has_mesh)
      for (const Shape& s : lb.shapes)
        if (trees->meshShape(a, ta, s, tb * s.origin, request)) return true;
    if (lb.has_mesh)
      for (const Shape& s : la.shapes)
        if (trees->meshShape(b, tb, s, ta * s.origin, request)) return true;
    for (const Shape& sa : la.shapes)
      for (const Shape& sb : lb.shapes)
      {
        fcl::CollisionResult<S> result;
        if (fcl_rs::collide(sa.geometry.get(), ta * sa.origin, sb.geometry.get(), tb * sb.origin, request, result))
          return true;
      }
    return false;
  }

  /// Tests the pair list at placement's poses and spheres.
  std::vector<LinkPair> testPairs(Placement& placement, QueryStats* stats, bool stop_at_first) const
  {
    trees->setPoses(placement.poses);
    nearPairs(placement);
    std::vector<LinkPair> colliding;
    if (stop_at_first)
    {
      // Consecutive checks of a planner are near each other, so the pair that collided last often collides
      // again: it goes first.
      const int hint = last_hit.load(std::memory_order_relaxed);
      if (hint >= 0 && !spheresApart(placement, pairs[hint].first, pairs[hint].second) &&
          collides(placement, pairs[hint].first, pairs[hint].second, stats))
        return {pairs[hint]};
      for (int k = 0; k < placement.near_count; ++k)
        if (const int i = placement.near[std::size_t(k)];
            i != hint && collides(placement, pairs[i].first, pairs[i].second, stats))
        {
          last_hit.store(i, std::memory_order_relaxed);
          return {pairs[i]};
        }
      return colliding;
    }
    for (int k = 0; k < placement.near_count; ++k)
      if (const int i = placement.near[std::size_t(k)]; collides(placement, pairs[i].first, pairs[i].second, stats))
        colliding.push_back(pairs[i]);
    return colliding;
  }

  /// Throws what queryPoses throws for its arguments.
  void checkQuery(const std::vector<Tf<S>>& poses, const SelfCheckRequest& request) const
  {
    if (bv == BVType::kKDOP18)
      throw std::invalid_argument("fcl_rs::SelfCollision::query: KDOP18 trees are refitted in place per check, so "
                                  "they cannot be shared; use check() or a BV type with local-frame trees");
    if (request.minimum_distance && bv == BVType::kOBB)
      throw std::invalid_argument("fcl_rs::SelfCollision::query: FCL has no distance query for OBB trees; "
                                  "use RS, OBBRSS or RSS for minimum distances");
    if (poses.size() != links.size())
      throw std::invalid_argument("fcl_rs::SelfCollision::queryPoses: " + std::to_string(poses.size()) +
                                  " poses for " + std::to_string(links.size()) + " links");
  }

  /// queryPoses's answer at placement's poses and spheres.
  SelfCheckResult<S> query(Placement& placement, const SelfCheckRequest& request) const
  {
    SelfCheckResult<S> result;
    result.pairs = testPairs(placement, nullptr, /*stop_at_first=*/!request.colliding_pairs);
    result.colliding = !result.pairs.empty();
    if (!request.colliding_pairs) result.pairs.clear();
    if (request.minimum_distance) result.minimum_distance = result.colliding ? S(0) : minimumDistance(placement);
    return result;
  }

  /// Sets p.near to the pairs whose spheres overlap, in list order, in one pass without a branch per pair: which
  /// pairs overlap changes from one configuration to the next, so such a branch is often mispredicted. p.near
  /// keeps its length (sizing it per check cost as much as the pass).
  void nearPairs(Placement& p) const
  {
    if (p.near.size() < pairs.size()) p.near.resize(pairs.size());
    int count = 0;
    for (int i = 0; i < int(pairs.size()); ++i)
    {
      p.near[std::size_t(count)] = i;
      count += !spheresApart(p, pairs[i].first, pairs[i].second);
    }
    p.near_count = count;
  }

  /// A candidate of the minimum-distance search: a link pair, or one element pair of it, with a lower bound on
  /// its distance and the tightest bound computed so far.
  enum class Stage { kLinkSpheres, kLinkVolumes, kElementSpheres, kElementHulls };
  struct Candidate
  {
    S bound;
    int pair;  ///< index in pairs
    int element_a, element_b;
    Stage stage;
    /// After kElementHulls: the hulls' gap direction (world frame, from element_a towards element_b), which lets
    /// the measurement skip the tree descent (detail::distanceAlong).
    fcl::Vector3d direction = fcl::Vector3d::Zero();
  };

  /// Minimum distance over the pair list of a collision-free configuration, best first: every link pair waits
  /// with its spheres' gap, a lower bound on its distance. The candidate of smallest bound is tightened one
  /// stage at a time (with RS the links' volumes, then per element pair the elements' balls and their hulls'
  /// distance, which is the elements' own for convex ones) and measured exactly once no bound is left to
  /// tighten; each measurement starts at the best distance so far, so it skips what cannot beat it, and with RS
  /// it measures along the hulls' gap direction (detail::distanceAlong) where that leaves few triangles.
  /// (An RS volume bound per element pair as well cost more than the hull bounds it saved.) Once the smallest bound waiting reaches the best
  /// distance, no candidate can lower it. Only pairs whose bounds stay below the answer are measured, nearest
  /// first, so the nearest pairs set a small minimum early. The order depends on the configuration only, so the
  /// result does too.
  S minimumDistance(const Placement& placement) const
  {
    std::vector<Candidate> waiting;
    waiting.reserve(2 * pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i)
      waiting.push_back({detail::sphereGap(placement.spheres[pairs[i].first], placement.spheres[pairs[i].second]),
                         int(i), 0, 0, Stage::kLinkSpheres});
    return nearest(placement.poses, std::move(waiting), std::numeric_limits<S>::infinity(), /*measure=*/true);
  }

  /// A lower bound on the distance of pairs[pair] at the poses, by the same search started at `enough`.
  S pairDistanceBound(const Tf<S>* poses, int pair, S enough, bool measure) const
  {
    const int a = pairs[pair].first, b = pairs[pair].second;
    const S gap = detail::sphereGap(detail::placeBall(poses[a], links[a].center, links[a].radius),
                                    detail::placeBall(poses[b], links[b].center, links[b].radius));
    return nearest(poses, {{gap, pair, 0, 0, Stage::kLinkSpheres}}, enough, measure);
  }

  /// The search of minimumDistance over the candidates `seeds` (any order), with `best` the distance that is
  /// enough: the answer is the smallest distance below it, else `best`. Without `measure` no element pair is
  /// measured: its hulls' distance is its bound (for convex elements the distance less the margin of hullDistance).
  S nearest(const Tf<S>* poses, std::vector<Candidate> seeds, S best, bool measure) const
  {
    const auto farther = [](const Candidate& x, const Candidate& y) { return x.bound > y.bound; };
    std::vector<Candidate> waiting = std::move(seeds);  // a min-heap on bound
    waiting.erase(std::remove_if(waiting.begin(), waiting.end(), [&](const Candidate& c) { return !(c.bound < best); }),
                  waiting.end());
    std::make_heap(waiting.begin(), waiting.end(), farther);
    const auto wait = [&](const Candidate& c) {
      if (!(c.bound < best)) return;
      waiting.push_back(c);
      std::push_heap(waiting.begin(), waiting.end(), farther);
    };
    const fcl::DistanceRequest<S> request;
    while (!waiting.empty())
    {
      std::pop_heap(waiting.begin(), waiting.end(), farther);
      Candidate c = waiting.back();
      waiting.pop_back();
      if (!(c.bound < best)) break;  // nor can any candidate still waiting
      // A candidate goes on while its bound stays the smallest, else it waits again.
      bool done = false;
      while (!done && c.bound < best && (waiting.empty() || !(waiting.front().bound < c.bound)))
      {
        const int a = pairs[c.pair].first, b = pairs[c.pair].second;
        const Tf<S>& ta = poses[a];
        const Tf<S>& tb = poses[b];
        const Link& la = links[a];
        const Link& lb = links[b];
        if (c.stage == Stage::kLinkSpheres)
        {
          c.stage = Stage::kLinkVolumes;
          if (bv == BVType::kRS) c.bound = std::max(c.bound, boundsDistance(ta, la.bound, tb, lb.bound));
        }
        else if (c.stage == Stage::kLinkVolumes)
        {
          // A link of one element: the link's bounds are its element's.
          c.stage = Stage::kElementSpheres;
          if (la.elements.size() == 1 && lb.elements.size() == 1) continue;
          for (int i = 0; i < int(la.elements.size()); ++i)
            for (int j = 0; j < int(lb.elements.size()); ++j)
            {
              const Element& ea = la.elements[i];
              const Element& eb = lb.elements[j];
              const S gap = detail::sphereGap(detail::placeBall(ta, ea.center, ea.radius),
                                              detail::placeBall(tb, eb.center, eb.radius));
              wait({std::max(c.bound, gap), c.pair, i, j, Stage::kElementSpheres});
            }
          done = true;
        }
        else if (c.stage == Stage::kElementSpheres)
        {
          c.stage = Stage::kElementHulls;
          // A bound that is not measured further needs no more than kUnmeasuredHullGap of the distance.
          c.bound = std::max(c.bound, hullDistance(ta, la.elements[c.element_a].hull, tb, lb.elements[c.element_b].hull,
                                                   best, c.direction,
                                                   measure ? triangle_shape::kIterativeRelativeGap : kUnmeasuredHullGap));
        }
        else
        {
          const Element& ea = la.elements[c.element_a];
          const Element& eb = lb.elements[c.element_b];
          done = true;
          if (!measure)
          {
            best = std::min(best, c.bound);
            continue;
          }
          const Tf<S> pose_a = ta * ea.origin, pose_b = tb * eb.origin;
          fcl::DistanceResult<S> result;
          result.min_distance = best;
          if (bv != BVType::kRS || !ea.convex || !eb.convex ||
              !detail::distanceAlong(ea.geometry, pose_a, eb.geometry, pose_b, c.direction, request, result))
            fcl_rs::distance(ea.geometry, pose_a, eb.geometry, pose_b, request, result);
          best = std::min(best, result.min_distance);
        }
      }
      if (!done) wait(c);
    }
    return best;
  }

  BVType bv;
  Kinematics<S> kinematics;
  std::vector<std::string> names;
  std::vector<Link> links;
  std::vector<LinkPair> pairs;
  std::vector<int> paired_links;  ///< the links of pairs, ascending: the only spheres a check places
  std::unique_ptr<MeshTrees<S>> trees;
  std::vector<Tf<S>> poses;  ///< scratch of the non-const checks
  Placement placement;       ///< their placement, of poses
  /// The index in pairs of the pair a first-contact check found last, -1 before any: a hint only, so threads
  /// sharing the checker may overwrite each other's (any value in range gives the same answers).
  mutable std::atomic<int> last_hit{-1};
  fcl::CollisionRequest<S> request{/*num_max_contacts=*/1, /*enable_contact=*/false};
};

template <typename S>
SelfCollision<S>::SelfCollision(const RobotModel& robot, BVType bv, const std::vector<DisabledCollision>& disabled)
  : impl_(std::make_unique<Impl>(robot, bv))
{
  const int n = int(robot.links.size());
  std::vector<TriangleMesh<S>> meshes(n);
  impl_->links.resize(n);
  for (int i = 0; i < n; ++i)
  {
    const RobotLink& src = robot.links[i];
    typename Impl::Link& link = impl_->links[i];
    impl_->names.push_back(src.name);
    link.has_mesh = !src.mesh.triangles.empty();
    if (link.has_mesh)
    {
      for (const auto& v : src.mesh.vertices) meshes[i].vertices.push_back(v.template cast<S>());
      meshes[i].triangles = src.mesh.triangles;
    }
    // Bounding sphere (in double): centre of the geometry's box, radius to the farthest point.
    fcl::Vector3d lo = fcl::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& v : src.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const fcl::Vector3d mesh_lo = lo, mesh_hi = hi;
    for (const Primitive& p : src.primitives)
    {
      const double r = primitiveRadius(p);
      lo = lo.cwiseMin(p.origin.translation() - fcl::Vector3d::Constant(r));
      hi = hi.cwiseMax(p.origin.translation() + fcl::Vector3d::Constant(r));
      link.shapes.push_back(makeShape<S>(p));
    }
    if (!src.hasGeometry()) continue;
    const fcl::Vector3d c = 0.5 * (lo + hi);
    double radius = 0;
    for (const auto& v : src.mesh.vertices) radius = std::max(radius, (v - c).norm());
    for (const Primitive& p : src.primitives)
      radius = std::max(radius, (p.origin.translation() - c).norm() + primitiveRadius(p));
    link.center = c.cast<S>();
    link.radius = S(radius * (1 + 1e-6));
    if (link.has_mesh)
    {
      link.bound = fitPoints(meshes[i].vertices.data(), int(meshes[i].vertices.size()));
      const fcl::Vector3d mesh_centre = 0.5 * (mesh_lo + mesh_hi);
      double mesh_radius = 0;
      for (const auto& v : src.mesh.vertices) mesh_radius = std::max(mesh_radius, (v - mesh_centre).norm());
      typename Impl::Element mesh;
      mesh.center = mesh_centre.cast<S>();
      mesh.radius = S(mesh_radius * (1 + 1e-6));
      mesh.hull = meshHull(meshes[i], &mesh.convex);
      mesh.hull.center = mesh.center;
      link.elements.push_back(mesh);  // its geometry, the tree, is set below
    }
    for (std::size_t k = 0; k < link.shapes.size(); ++k)
    {
      const RS<S> placed = placeShapeRS(link.shapes[k].bv, link.shapes[k].origin);
      if (link.has_mesh || k > 0) link.bound += placed;
      else link.bound = placed;
      typename Impl::Element shape;
      shape.geometry = link.shapes[k].geometry.get();
      shape.origin = link.shapes[k].origin;
      shape.center = link.shapes[k].origin.translation();
      shape.radius = S(primitiveRadius(src.primitives[k]) * (1 + 1e-6));
      std::vector<fcl::Vector3d> corners;
      for (const fcl::Vector3d& corner : primitiveHullPoints(src.primitives[k], shape.hull.radius))
        corners.push_back(src.primitives[k].origin * corner);
      shape.hull.points = triangle_shape::HullPoints(std::move(corners));
      shape.hull.center = shape.center;
      shape.hull.reach = detail::hullReach(shape.hull);
      link.elements.push_back(shape);
    }
    link.bound_frame = detail::BoxedFrame<S>(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero(), link.bound);
  }
  impl_->trees = makeTrees<S>(bv, meshes);
  for (int i = 0; i < n; ++i)
    if (impl_->links[i].has_mesh) impl_->links[i].elements.front().geometry = impl_->trees->localModel(i);

  std::set<LinkPair> skip;
  auto ordered = [](int a, int b) { return a < b ? LinkPair(a, b) : LinkPair(b, a); };
  for (const DisabledCollision& d : disabled)
  {
    const int a = robot.linkIndex(d.link1), b = robot.linkIndex(d.link2);
    if (a < 0 || b < 0)
      throw std::invalid_argument("fcl_rs::SelfCollision: disabled pair (" + d.link1 + ", " + d.link2 + ")" +
                                  (d.source.empty() ? "" : " from " + d.source) + " names no link of robot '" +
                                  robot.name + "': '" + (a < 0 ? d.link1 : d.link2) + "'");
    skip.insert(ordered(a, b));
  }
  // Adjacent: a link and its nearest ancestor with geometry.
  for (int i = 0; i < n; ++i)
  {
    if (!robot.links[i].hasGeometry()) continue;
    for (int j = robot.links[i].parent_joint; j >= 0;)
    {
      const int parent = robot.joints[j].parent_link;
      if (robot.links[parent].hasGeometry())
      {
        skip.insert(ordered(i, parent));
        break;
      }
      j = robot.links[parent].parent_joint;
    }
  }
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (robot.links[a].hasGeometry() && robot.links[b].hasGeometry() && !skip.count({a, b}))
        impl_->pairs.emplace_back(a, b);
  for (int i = 0; i < n; ++i)
    if (std::any_of(impl_->pairs.begin(), impl_->pairs.end(),
                    [i](const LinkPair& p) { return p.first == i || p.second == i; }))
      impl_->paired_links.push_back(i);
}

template <typename S>
SelfCollision<S>::~SelfCollision() = default;
template <typename S>
SelfCollision<S>::SelfCollision(SelfCollision&&) noexcept = default;
template <typename S>
SelfCollision<S>& SelfCollision<S>::operator=(SelfCollision&&) noexcept = default;

template <typename S>
BVType SelfCollision<S>::bvType() const
{
  return impl_->bv;
}

template <typename S>
const Kinematics<S>& SelfCollision<S>::kinematics() const
{
  return impl_->kinematics;
}

template <typename S>
const std::vector<std::string>& SelfCollision<S>::linkNames() const
{
  return impl_->names;
}

template <typename S>
const std::vector<LinkPair>& SelfCollision<S>::pairs() const
{
  return impl_->pairs;
}

template <typename S>
std::vector<LinkPair> SelfCollision<S>::check(const fcl::VectorX<S>& q, QueryStats* stats)
{
  impl_->kinematics.linkPoses(q, impl_->poses);
  impl_->placement.poses = impl_->poses.data();
  impl_->placeSpheres(impl_->placement);
  return impl_->testPairs(impl_->placement, stats, /*stop_at_first=*/false);
}

template <typename S>
std::vector<LinkPair> SelfCollision<S>::checkPoses(const std::vector<fcl::Transform3<S>>& poses, QueryStats* stats)
{
  if (poses.size() != impl_->links.size())
    throw std::invalid_argument("fcl_rs::SelfCollision: " + std::to_string(poses.size()) + " poses for " +
                                std::to_string(impl_->links.size()) + " links");
  requireRigidTransforms(poses, "fcl_rs::SelfCollision::checkPoses", "poses");
  impl_->placement.poses = poses.data();
  impl_->placeSpheres(impl_->placement);
  return impl_->testPairs(impl_->placement, stats, /*stop_at_first=*/false);
}

template <typename S>
bool SelfCollision<S>::inCollision(const fcl::VectorX<S>& q)
{
  impl_->kinematics.linkPoses(q, impl_->poses);
  impl_->placement.poses = impl_->poses.data();
  impl_->placeSpheres(impl_->placement);
  return !impl_->testPairs(impl_->placement, nullptr, /*stop_at_first=*/true).empty();
}

template <typename S>
SelfCheckResult<S> SelfCollision<S>::query(const fcl::VectorX<S>& q, const SelfCheckRequest& request) const
{
  static thread_local std::vector<fcl::Transform3<S>> poses;  // per thread, as queryPoses's placement
  impl_->kinematics.linkPoses(q, poses);
  return queryPoses(poses, request);
}

template <typename S>
SelfCheckResult<S> SelfCollision<S>::queryPoses(const std::vector<fcl::Transform3<S>>& poses,
                                                const SelfCheckRequest& request) const
{
  typename Impl::Placement& placement = Impl::threadPlacement();
  impl_->checkQuery(poses, request);
  placement.poses = poses.data();
  impl_->placeSpheres(placement);
  return impl_->query(placement, request);
}

template <typename S>
SelfCheckResult<S> detail::SelfCollisionInternals<S>::queryPlaced(const SelfCollision<S>& self,
                                                                  const std::vector<fcl::Transform3<S>>& poses,
                                                                  const std::vector<WorldSphere<S>>& spheres,
                                                                  const SelfCheckRequest& request)
{
  typename SelfCollision<S>::Impl::Placement& placement = SelfCollision<S>::Impl::threadPlacement();
  self.impl_->checkQuery(poses, request);
  placement.poses = poses.data();
  placement.spheres = spheres.data();
  return self.impl_->query(placement, request);
}

template <typename S>
S SelfCollision<S>::pairDistanceBound(const std::vector<fcl::Transform3<S>>& poses, int pair, S enough,
                                      bool measure) const
{
  if (impl_->bv == BVType::kKDOP18 || impl_->bv == BVType::kOBB)
    throw std::invalid_argument(std::string("fcl_rs::SelfCollision::pairDistanceBound: no distances for ") +
                                bvTypeName(impl_->bv) + " trees; use RS, OBBRSS or RSS");
  if (pair < 0 || pair >= int(impl_->pairs.size()))
    throw std::invalid_argument("fcl_rs::SelfCollision::pairDistanceBound: pair " + std::to_string(pair) +
                                " out of range [0, " + std::to_string(impl_->pairs.size()) + ")");
  if (poses.size() != impl_->links.size())
    throw std::invalid_argument("fcl_rs::SelfCollision::pairDistanceBound: " + std::to_string(poses.size()) +
                                " poses for " + std::to_string(impl_->links.size()) + " links");
  return impl_->pairDistanceBound(poses.data(), pair, enough, measure);
}

template <typename S>
S SelfCollision<S>::hullDistanceBound(int link, const fcl::Transform3<S>& pose, const BodyHull<S>& body,
                                      const fcl::Transform3<S>& body_pose, S enough) const
{
  if (link < 0 || link >= int(impl_->links.size()))
    throw std::invalid_argument("fcl_rs::SelfCollision::hullDistanceBound: link " + std::to_string(link) +
                                " out of range [0, " + std::to_string(impl_->links.size()) + ")");
  S best = enough;
  fcl::Vector3d direction;
  for (const typename Impl::Element& e : impl_->links[link].elements)
  {
    best = std::min(best, Impl::hullDistance(pose, e.hull, body_pose, body, best, direction, kUnmeasuredHullGap));
  }
  return best;
}

template <typename S>
S SelfCollision<S>::lowestAlong(int link, const fcl::Transform3<S>& pose, const fcl::Vector3<S>& n) const
{
  if (link < 0 || link >= int(impl_->links.size()))
    throw std::invalid_argument("fcl_rs::SelfCollision::lowestAlong: link " + std::to_string(link) + " out of range [0, " +
                                std::to_string(impl_->links.size()) + ")");
  const Eigen::Isometry3d p = pose.template cast<double>();
  const fcl::Vector3d u = n.template cast<double>();
  const fcl::Vector3d d = p.linear().transpose() * u;  // n in the link frame
  const double offset = u.dot(p.translation());
  double lowest = std::numeric_limits<double>::infinity();
  for (const typename Impl::Element& e : impl_->links[link].elements)
  {
    const triangle_shape::HullPoints& points = e.hull.points;
    // The walk's point, certified the lowest by the clusters' scan (as GJK's last support point is).
    const std::size_t i =
        points.walks() ? points.lowestBelow(d, points.walk(d, triangle_shape::HullPoints::kNoPoint)) : points.lowest(d);
    // hullDistance's margin, for one hull.
    const double margin =
        1024 * double(std::numeric_limits<S>::epsilon()) * (p.translation().template lpNorm<1>() + e.hull.reach);
    lowest = std::min(lowest, points.points()[i].dot(d) + offset - e.hull.radius - margin);
  }
  return roundedDown<S>(lowest);
}

template <typename S>
std::vector<LinkElement<S>> SelfCollision<S>::linkElements(int link) const
{
  if (link < 0 || link >= int(impl_->links.size()))
    throw std::invalid_argument("fcl_rs::SelfCollision::linkElements: link " + std::to_string(link) +
                                " out of range [0, " + std::to_string(impl_->links.size()) + ")");
  const typename Impl::Link& l = impl_->links[link];
  std::vector<LinkElement<S>> elements;
  if (l.has_mesh)
  {
    const fcl::CollisionGeometry<S>* model = impl_->trees->localModel(link);
    if (!model)
      throw std::invalid_argument("fcl_rs::SelfCollision::linkElements: KDOP18 trees live in the world frame; "
                                  "use a BV type with local-frame trees");
    elements.push_back({model, fcl::Transform3<S>::Identity()});
  }
  for (const typename Impl::Shape& s : l.shapes) elements.push_back({s.geometry.get(), s.origin});
  return elements;
}

template <typename S>
LinkSphere<S> SelfCollision<S>::linkSphere(int link) const
{
  if (link < 0 || link >= int(impl_->links.size()))
    throw std::invalid_argument("fcl_rs::SelfCollision::linkSphere: link " + std::to_string(link) +
                                " out of range [0, " + std::to_string(impl_->links.size()) + ")");
  return {impl_->links[link].center, impl_->links[link].radius};
}

#define FCL_RS_INSTANTIATE_SELF_COLLISION(S)        \
  template class SelfCollision<S>;                  \
  template struct detail::SelfCollisionInternals<S>; \
  template BodyHull<S> meshHull(const TriangleMesh<S>&, bool*);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_SELF_COLLISION)
#undef FCL_RS_INSTANTIATE_SELF_COLLISION

}  // namespace fcl_rs
