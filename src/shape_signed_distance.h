// Signed distance of two primitive shapes (src/distance.cpp), for either gjk_solver_type: closed forms where they
// exist, libccd's GJK and EPA with a bounded expansion for every other pair.
//
// Why: FCL's libccd signed distance runs EPA without an iteration limit to distance_tolerance. When a whole circle or
// sphere of directions is (nearly) deepest, as for concentric spheres, a sphere centred on a cylinder's axis or two
// coaxial cylinders, EPA must tile that set to the tolerance and does not finish (> 10 s; each expansion costs time
// linear in the polytope). GJKSolver_indep's EPA, for its part, reports depths of curved shapes that are far off
// (cone-cone: 0.0098 for 0.5264), so both solvers take this path.
//
// Closed forms: a sphere is its centre, a capsule its axis segment, each grown by its radius: two of them are apart
// by the distance of those cores less both radii, in both signs (the cores' Minkowski difference has no interior, so
// the depth is the radii less the cores' distance). A sphere against any convex X is apart by the signed distance of
// its centre to X less its radius (box, cylinder and cone below). Nearest points follow libccd's: p1 on o1, p2 on
// o2, and moving o1 by p2 - p1 makes the shapes touch.
//
// Every other pair: libccd's GJK, then its EPA for at most kMaxEpaExpansions expansions. Converged on its own
// bounds (within distance_tolerance), the answer is FCL's. EPA's lower bound creeps up slowly where a circle of
// directions is deepest, so a second one joins it: the balls inscribed about the shapes' origins (inscribedBall;
// exact for concentric and coaxial pairs). Once EPA's upper bound (the smallest support value of a direction it
// tried: moving o1 that far along it separates the shapes) is within distance_tolerance of the larger lower bound,
// or after kMaxEpaExpansions within kEpaRelativeGap of it, the depth is that lower bound (FCL's EPA too answers its
// lower bound) and p1, p2 the support points of that direction (on the surfaces; moving o1 by p2 - p1 makes the
// shapes touch, though |p2 - p1| may exceed the depth). Otherwise std::runtime_error names the pair and both bounds.
#ifndef FCL_RS_SRC_SHAPE_SIGNED_DISTANCE_H
#define FCL_RS_SRC_SHAPE_SIGNED_DISTANCE_H

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/convexity_based_algorithm/gjk_libccd.h>
#include <fcl/narrowphase/detail/failed_at_this_configuration.h>

#include "fcl_rs/detail/relative_poses.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/shape_switch.h"

namespace fcl_rs {
namespace detail {
namespace shape_signed_distance {

using Vec = Eigen::Vector3d;

/// A signed distance with p1 on the first shape and p2 on the second.
struct Signed
{
  double distance;
  Vec p1, p2;
};

/// A sphere (an ellipsoid with equal radii is one) or a capsule: its core, the segment [a, b] (a = b for a
/// sphere), grown by radius. Coordinates relative to `origin`.
struct RoundedCore
{
  Vec a, b;
  double radius;
};

/// A point's signed distance to a shape (negative inside), the boundary point nearest to it and the shape's
/// outward unit normal there (the point lies at boundary + distance * normal).
struct PointToBoundary
{
  double distance;
  Vec boundary, normal;
};

/// A unit vector along v, or fallback when v has no direction (zero, or too small to normalise).
inline Vec unitOr(const Vec& v, const Vec& fallback)
{
  const double n = v.norm();
  return n > std::numeric_limits<double>::min() && std::isfinite(n) ? Vec(v / n) : fallback;
}

template <typename S>
std::optional<RoundedCore> roundedCore(const fcl::CollisionGeometry<S>& g, const fcl::Transform3<S>& tf,
                                       const Vec& origin)
{
  const Vec c = tf.translation().template cast<double>() - origin;
  return withShape(
      g,
      [&](const auto& shape) -> std::optional<RoundedCore> {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Sphere<S>>)
          return RoundedCore{c, c, double(shape.radius)};
        else if constexpr (std::is_same_v<Shape, fcl::Ellipsoid<S>>)
        {
          if (shape.radii.x() == shape.radii.y() && shape.radii.y() == shape.radii.z())
            return RoundedCore{c, c, double(shape.radii.x())};
          return std::nullopt;
        }
        else if constexpr (std::is_same_v<Shape, fcl::Capsule<S>>)
        {
          const Vec half = tf.linear().col(2).template cast<double>() * (double(shape.lz) / 2);
          return RoundedCore{c - half, c + half, double(shape.radius)};
        }
        else
          return std::nullopt;
      },
      [] { return std::optional<RoundedCore>(); });
}

/// Two rounded cores: the cores' distance less both radii. Where the cores meet, the shapes separate fastest
/// across both cores (along the cross product of their axes, or any direction across a lone axis).
inline Signed roundedCores(const RoundedCore& r1, const RoundedCore& r2)
{
  triangle_shape::Closest cores;
  triangle_shape::segmentSegment(r1.a, r1.b, r2.a, r2.b, cores);
  const Vec &q1 = cores.on_triangle, &q2 = cores.on_shape;
  const Vec axis1 = r1.b - r1.a, axis2 = r2.b - r2.a;
  const Vec axis = axis1.squaredNorm() > 0 ? axis1 : axis2;
  const Vec across = axis.squaredNorm() > 0 ? unitOr(axis1.cross(axis2), axis.unitOrthogonal()) : Vec::UnitX();
  const Vec n = unitOr(q2 - q1, across);
  return {cores.distance - r1.radius - r2.radius, q1 + r1.radius * n, q2 - r2.radius * n};
}

/// Point p (in the box's frame) against a box of half extents h.
inline PointToBoundary pointBox(const Vec& p, const Vec& h)
{
  const Vec q = p.cwiseMax(-h).cwiseMin(h);
  if (q != p) return {(p - q).norm(), q, unitOr(p - q, Vec::UnitX())};
  int face = 0;
  (h - p.cwiseAbs()).minCoeff(&face);
  const double side = p[face] < 0 ? -1 : 1;
  Vec boundary = p;
  boundary[face] = side * h[face];
  return {-(h[face] - std::abs(p[face])), boundary, side * Vec::Unit(face)};
}

/// Point p against a solid of revolution about z whose half-plane section (rho >= 0, z) is the polygon `section`
/// (its edges on the axis rho = 0 excluded from the boundary): the 2D problem, turned back about the axis.
/// A point on the axis takes the half-plane of +x (every one is nearest).
template <typename Section>
PointToBoundary pointRevolved(const Vec& p, Section&& section)
{
  const double rho = std::hypot(p.x(), p.y());
  const Vec radial = rho > 0 ? Vec(p.x() / rho, p.y() / rho, 0) : Vec::UnitX();
  const auto [distance, boundary2, normal2] = section(rho, p.z());
  return {distance, boundary2.x() * radial + boundary2.y() * Vec::UnitZ(),
          normal2.x() * radial + normal2.y() * Vec::UnitZ()};
}

struct Boundary2
{
  double distance;
  Eigen::Vector2d boundary, normal;
};

/// Point p against a cylinder of radius r and half length h about z.
inline PointToBoundary pointCylinder(const Vec& p, double r, double h)
{
  return pointRevolved(p, [r, h](double rho, double z) -> Boundary2 {
    const Eigen::Vector2d x(rho, z), q(std::min(rho, r), std::clamp(z, -h, h));
    if (q != x) return {(x - q).norm(), q, (x - q).normalized()};
    const double side_depth = r - rho, cap_depth = h - std::abs(z), cap = z < 0 ? -1 : 1;
    if (side_depth < cap_depth) return {-side_depth, {r, z}, {1, 0}};
    return {-cap_depth, {rho, cap * h}, {0, cap}};
  });
}

/// Point p against a cone of base radius r and half length h about z (base at z = -h, apex at z = h).
inline PointToBoundary pointCone(const Vec& p, double r, double h)
{
  return pointRevolved(p, [r, h](double rho, double z) -> Boundary2 {
    const Eigen::Vector2d x(rho, z), base_rim(r, -h), apex(0, h);
    const Eigen::Vector2d side_normal = Eigen::Vector2d(2 * h, r).normalized();
    const double side_offset = side_normal.dot(x - base_rim), base_depth = z + h;
    if (base_depth >= 0 && side_offset <= 0)
    {
      // Inside: the nearer of base and side (the right angle at the base centre puts the foot on the side).
      if (-side_offset < base_depth) return {side_offset, x - side_offset * side_normal, side_normal};
      return {-base_depth, {rho, -h}, {0, -1}};
    }
    // Outside: the nearest point of the section triangle (base centre, base rim, apex).
    const triangle_shape::Vec t[3] = {{0, -h, 0}, {r, -h, 0}, {0, h, 0}};
    const Vec q3 = triangle_shape::closestOnTriangle(t, Vec(rho, z, 0));
    const Eigen::Vector2d q(q3.x(), q3.y());
    return {(x - q).norm(), q, (x - q).normalized()};
  });
}

/// A sphere's centre c (in shape g's frame) against g, if g is a box, cylinder or cone.
template <typename S>
std::optional<PointToBoundary> pointToShape(const fcl::CollisionGeometry<S>& g, const Vec& c)
{
  return withShape(
      g,
      [&](const auto& shape) -> std::optional<PointToBoundary> {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Box<S>>)
          return pointBox(c, shape.side.template cast<double>() / 2);
        else if constexpr (std::is_same_v<Shape, fcl::Cylinder<S>>)
          return pointCylinder(c, double(shape.radius), double(shape.lz) / 2);
        else if constexpr (std::is_same_v<Shape, fcl::Cone<S>>)
          return pointCone(c, double(shape.radius), double(shape.lz) / 2);
        else
          return std::nullopt;
      },
      [] { return std::optional<PointToBoundary>(); });
}

/// A sphere (core `sphere`, a = b) against shape g at tf (relative to the same origin), if g has a closed form:
/// p1 on the sphere, p2 on g.
template <typename S>
std::optional<Signed> sphereShape(const RoundedCore& sphere, const fcl::CollisionGeometry<S>& g,
                                  const fcl::Transform3<S>& tf, const Vec& origin)
{
  const Eigen::Matrix3d rotation = tf.linear().template cast<double>();
  const Vec translation = tf.translation().template cast<double>() - origin;
  const auto point = pointToShape(g, Vec(rotation.transpose() * (sphere.a - translation)));
  if (!point) return std::nullopt;
  const Vec normal = rotation * point->normal, boundary = rotation * point->boundary + translation;
  return Signed{point->distance - sphere.radius, sphere.a - sphere.radius * normal, boundary};
}

/// EPA's expansions before the bounded path gives its upper bound (each costs time linear in the polytope: 1000 take
/// milliseconds, where FCL's unbounded loop ran for minutes).
constexpr unsigned long kMaxEpaExpansions = 1000;
/// ... if that upper bound is within this fraction of EPA's lower bound.
constexpr double kEpaRelativeGap = 1e-3;

/// A shape as libccd sees it: FCL's GJK object (owned) and support function.
struct CcdShape
{
  void* object = nullptr;
  ccd_support_fn support = nullptr;
  void (*destroy)(void*) = nullptr;
  CcdShape() = default;
  CcdShape(const CcdShape&) = delete;
  CcdShape& operator=(const CcdShape&) = delete;
  ~CcdShape()
  {
    if (object) destroy(object);
  }
};

/// g at tf as a libccd shape, false for shapes libccd has no support function for (TriangleP, Plane, Halfspace).
template <typename S>
bool asCcdShape(const fcl::CollisionGeometry<S>& g, const fcl::Transform3<S>& tf, CcdShape& out)
{
  return withShape(
      g,
      [&](const auto& shape) {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Box<S>> || std::is_same_v<Shape, fcl::Sphere<S>> ||
                      std::is_same_v<Shape, fcl::Ellipsoid<S>> || std::is_same_v<Shape, fcl::Capsule<S>> ||
                      std::is_same_v<Shape, fcl::Cone<S>> || std::is_same_v<Shape, fcl::Cylinder<S>> ||
                      std::is_same_v<Shape, fcl::Convex<S>>)
        {
          using Initializer = fcl::detail::GJKInitializer<S, Shape>;
          out.object = Initializer::createGJKObject(shape, tf);
          out.support = Initializer::getSupportFunction();
          out.destroy = &Initializer::deleteGJKObject;
          return true;
        }
        else
          return false;
      },
      [] { return false; });
}

/// The radius of a ball about g's origin inside g (0 where none is known: Convex). Two shapes whose origins are d
/// apart contain such balls whose Minkowski difference is a ball of radius ball1 + ball2 about a point d from the
/// origin: their penetration depth is at least ball1 + ball2 - d, the lower bound that settles concentric pairs.
template <typename S>
double inscribedBall(const fcl::CollisionGeometry<S>& g)
{
  return withShape(
      g,
      [](const auto& shape) -> double {
        using Shape = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<Shape, fcl::Sphere<S>> || std::is_same_v<Shape, fcl::Capsule<S>>)
          return shape.radius;
        else if constexpr (std::is_same_v<Shape, fcl::Ellipsoid<S>>)
          return shape.radii.minCoeff();
        else if constexpr (std::is_same_v<Shape, fcl::Box<S>>)
          return shape.side.minCoeff() / 2;
        else if constexpr (std::is_same_v<Shape, fcl::Cylinder<S>>)
          return std::min(double(shape.radius), double(shape.lz) / 2);
        else if constexpr (std::is_same_v<Shape, fcl::Cone<S>>)
          return -pointCone(Vec::Zero(), shape.radius, double(shape.lz) / 2).distance;
        else
          return 0;
      },
      [] { return 0.0; });
}

/// libccd's signed distance (FCL's libccd_extension::ccdGJKSignedDist) with EPA's loop bounded (see the top).
/// known_depth: a lower bound on the penetration depth known beforehand (inscribedBall).
inline double boundedCcdSignedDistance(const CcdShape& shape1, const CcdShape& shape2, unsigned int max_iterations,
                                       double tolerance, double known_depth, Vec& p1, Vec& p2)
{
  namespace ccd = fcl::detail::libccd_extension;
  ccd_t config;
  CCD_INIT(&config);
  config.support1 = shape1.support;
  config.support2 = shape2.support;
  config.max_iterations = max_iterations;
  config.dist_tolerance = tolerance;
  config.epa_tolerance = tolerance;
  const auto out = [&p1, &p2](const ccd_vec3_t& a, const ccd_vec3_t& b) {
    p1 = Vec(ccdVec3X(&a), ccdVec3Y(&a), ccdVec3Z(&a));
    p2 = Vec(ccdVec3X(&b), ccdVec3Y(&b), ccdVec3Z(&b));
  };
  ccd_vec3_t a, b;
  ccdVec3Set(&a, 0, 0, 0);
  ccdVec3Set(&b, 0, 0, 0);
  ccd_simplex_t simplex;
  if (ccd::__ccdGJK(shape1.object, shape2.object, &config, &simplex) != 0)
  {
    const double distance = ccd::_ccdDist(shape1.object, shape2.object, &config, &simplex, &a, &b);
    out(a, b);
    return distance;
  }
  struct Polytope
  {
    ccd_pt_t pt;
    Polytope() { ccdPtInit(&pt); }
    ~Polytope() { ccdPtDestroy(&pt); }
  } polytope;
  ccd_pt_el_t* nearest = nullptr;
  const int size = ccdSimplexSize(&simplex);
  int status = size == 4   ? ccd::simplexToPolytope4(shape1.object, shape2.object, &config, &simplex, &polytope.pt,
                                                     &nearest)
               : size == 3 ? ccd::convert2SimplexToTetrahedron(shape1.object, shape2.object, &config, &simplex,
                                                               &polytope.pt, &nearest)
                           : ccd::simplexToPolytope2(shape1.object, shape2.object, &config, &simplex, &polytope.pt,
                                                     &nearest);
  if (status == -2) throw std::bad_alloc();
  if (status == -1)  // touching (FCL's __ccdEPA returns without a polytope loop)
  {
    if (!nearest) return -1;  // as FCL's ccdGJKSignedDist
    ccd::penEPAPosClosest(nearest, &a, &b);
    out(a, b);
    return -std::sqrt(nearest->dist);
  }
  double upper = std::numeric_limits<double>::infinity();
  ccd_support_t upper_support{};
  for (unsigned long expansions = 0;; ++expansions)
  {
    nearest = ccdPtNearest(&polytope.pt);
    if (polytope.pt.nearest_type == CCD_PT_EDGE)
    {
      ccd::validateNearestFeatureOfPolytopeBeingEdge(&polytope.pt);
      nearest = ccdPtNearest(&polytope.pt);
    }
    ccd_support_t support;
    if (ccd::nextSupport(&polytope.pt, shape1.object, shape2.object, &config, nearest, &support) != 0) break;
    const ccd_vec3_t direction = ccd::supportEPADirection(&polytope.pt, nearest);
    const double bound = ccdVec3Dot(&support.v, &direction);
    if (bound < upper) upper = bound, upper_support = support;
    const double lower = std::max(std::sqrt(double(nearest->dist)), known_depth);
    if (upper - lower <= tolerance || expansions == kMaxEpaExpansions)
    {
      if (upper - lower > std::max(tolerance, kEpaRelativeGap * upper))
        throw std::runtime_error("EPA did not bound the penetration depth within " +
                                 std::to_string(kEpaRelativeGap) + " relative in " +
                                 std::to_string(kMaxEpaExpansions) + " expansions: it lies in [" +
                                 std::to_string(lower) + ", " + std::to_string(upper) + "]");
      out(upper_support.v1, upper_support.v2);
      return -lower;
    }
    if (ccd::expandPolytope(&polytope.pt, nearest, &support) != 0) throw std::bad_alloc();
  }
  ccd::penEPAPosClosest(nearest, &a, &b);
  out(a, b);
  return -std::sqrt(nearest->dist);
}

/// The signed distance of shapes o1 at tf1 and o2 at tf2 (see the top), computed relative to tf1's translation
/// (fcl_rs/detail/relative_poses.h) with p1 and p2 moved back; nullopt for pairs libccd cannot take (TriangleP).
/// libccd's GJK takes max_iterations and tolerance (FCL's max_distance_iterations and distance_tolerance).
template <typename S>
std::optional<Signed> signedDistance(const fcl::CollisionGeometry<S>& o1, const fcl::Transform3<S>& tf1,
                                     const fcl::CollisionGeometry<S>& o2, const fcl::Transform3<S>& tf2,
                                     unsigned int max_iterations, double tolerance, const char* api)
{
  const Vec origin = tf1.translation().template cast<double>();
  const auto core1 = roundedCore(o1, tf1, origin), core2 = roundedCore(o2, tf2, origin);
  std::optional<Signed> signed_distance;
  if (core1 && core2)
    signed_distance = roundedCores(*core1, *core2);
  else if (core1 && core1->a == core1->b)
    signed_distance = sphereShape(*core1, o2, tf2, origin);
  else if (core2 && core2->a == core2->b)
  {
    signed_distance = sphereShape(*core2, o1, tf1, origin);
    if (signed_distance) std::swap(signed_distance->p1, signed_distance->p2);
  }
  if (!signed_distance)
  {
    const double known_depth =
        inscribedBall(o1) + inscribedBall(o2) - (tf2.translation() - tf1.translation()).template cast<double>().norm();
    const auto failure = [&](const char* what) {
      return std::runtime_error(std::string(api) + ": signed distance of node types " +
                                std::to_string(int(o1.getNodeType())) + " and " +
                                std::to_string(int(o2.getNodeType())) + " (fcl::NODE_TYPE): " + what);
    };
    // Built without NDEBUG (the sanitizer stage, a Debug build), FCL's EPA throws FailedAtThisConfiguration when its
    // polytope gets a zero-area face (parallel cones one beside the other, say); with NDEBUG it goes on. Such a face
    // comes from the coordinates, the depth does not: the pair is measured again with both shapes turned by the same
    // rotation, and the nearest points turned back.
    const Eigen::Matrix3d turns[] = {
        Eigen::Matrix3d::Identity(), Eigen::AngleAxisd(1, Vec(1, 2, 3).normalized()).toRotationMatrix(),
        Eigen::AngleAxisd(2, Vec(-3, 1, 2).normalized()).toRotationMatrix()};
    for (std::size_t k = 0; !signed_distance; ++k)
    {
      fcl::Transform3<S> turn_s = fcl::Transform3<S>::Identity();
      turn_s.linear() = turns[k].template cast<S>();
      CcdShape shape1, shape2;
      if (!asCcdShape(o1, fcl::Transform3<S>(turn_s * shifted(tf1, tf1.translation())), shape1) ||
          !asCcdShape(o2, fcl::Transform3<S>(turn_s * shifted(tf2, tf1.translation())), shape2))
        return std::nullopt;
      Signed bounded{0, Vec::Zero(), Vec::Zero()};
      try
      {
        bounded.distance =
            boundedCcdSignedDistance(shape1, shape2, max_iterations, tolerance, known_depth, bounded.p1, bounded.p2);
      }
      catch (const std::runtime_error& e)
      {
        throw failure(e.what());
      }
      catch (const fcl::detail::FailedAtThisConfiguration& e)
      {
        if (k + 1 == std::size(turns)) throw failure(e.what());
        continue;
      }
      const Eigen::Matrix3d back = turn_s.linear().transpose().template cast<double>();
      signed_distance = Signed{bounded.distance, back * bounded.p1, back * bounded.p2};
    }
  }
  signed_distance->p1 += origin;
  signed_distance->p2 += origin;
  return signed_distance;
}

}  // namespace shape_signed_distance
}  // namespace detail
}  // namespace fcl_rs

#endif
