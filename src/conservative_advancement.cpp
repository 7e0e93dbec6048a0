// Conservative advancement for pairs with an RS mesh (fcl_rs::continuousCollide, CCDC_CONSERVATIVE_ADVANCEMENT):
// exact distances from fcl_rs::distance and a bound on how fast any point of either object can move.
#include "rs_pairs.h"
#include "scalars.h"
#include "fcl_rs/continuous_collision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/utility.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/motion/interp_motion.h>
#include <fcl/math/motion/screw_motion.h>
#include <fcl/math/motion/spline_motion.h>
#include <fcl/math/motion/translation_motion.h>

#include "fcl_rs/distance.h"
#include "fcl_rs/traversal/shape_switch.h"

namespace fcl_rs {
namespace detail {
namespace {

constexpr const char* kApi = "fcl_rs::continuousCollide";

/// SplineMotion keeps its control points protected and without accessors; a derived class may name them.
template <typename S>
struct SplineControlPoints : fcl::SplineMotion<S>
{
  static const fcl::Vector3<S>* translation(const fcl::SplineMotion<S>& m) { return m.*(&SplineControlPoints::Td); }
  static const fcl::Vector3<S>* rotation(const fcl::SplineMotion<S>& m) { return m.*(&SplineControlPoints::Rd); }
};

/// The largest step between consecutive control points: FCL's spline is one uniform cubic B-spline segment, whose
/// derivative is a quadratic B-spline (non-negative weights summing to 1) of these differences.
template <typename S>
S maxControlStep(const fcl::Vector3<S>* points)
{
  S step = 0;
  for (int i = 0; i < 3; ++i) step = std::max(step, (points[i + 1] - points[i]).norm());
  return step;
}

/// Upper bounds, over the whole motion (time in [0, 1]), on the speed of the body point `centre` (in the object's
/// frame) and on the angular speed: every point within `radius` of the centre then moves no faster than
/// centre_speed + angular_speed * radius.
template <typename S>
struct SpeedBound
{
  S centre_speed = 0;
  S angular_speed = 0;
};

template <typename S>
SpeedBound<S> speedBound(const fcl::MotionBase<S>& motion, const fcl::Vector3<S>& centre)
{
  SpeedBound<S> b;
  if (const auto* m = dynamic_cast<const fcl::TranslationMotion<S>*>(&motion))
  {
    b.centre_speed = m->getVelocity().norm();  // x(t) = R p + T0 + t v
    return b;
  }
  if (const auto* m = dynamic_cast<const fcl::InterpMotion<S>*>(&motion))
  {
    // x(t) = t v + tf1 ref + R(t) (p - ref), R(t) turning at a constant rate about a fixed axis.
    b.angular_speed = std::abs(m->getAngularVelocity());
    b.centre_speed = m->getLinearVelocity().norm() + b.angular_speed * (centre - m->getReferencePoint()).norm();
    return b;
  }
  if (const auto* m = dynamic_cast<const fcl::ScrewMotion<S>*>(&motion))
  {
    // x(t) = o + t v axis + Rot(axis, t w) (tf1 p - o). FCL leaves the axis unnormalised for a pure translation.
    motion.integrate(0);
    fcl::Transform3<S> start;
    motion.getCurrentTransform(start);
    b.angular_speed = std::abs(m->getAngularVelocity());
    b.centre_speed = std::abs(m->getLinearVelocity()) * m->getAxis().norm() +
                     b.angular_speed * (start * centre - m->getAxisOrigin()).norm();
    return b;
  }
  if (const auto* m = dynamic_cast<const fcl::SplineMotion<S>*>(&motion))
  {
    // x(t) = exp(r(t)) p + T(t): |T'| and |r'| are bounded by the control steps, and the exponential map's
    // derivative never lengthens a vector, so the angular speed is at most |r'|.
    b.angular_speed = maxControlStep(SplineControlPoints<S>::rotation(*m));
    b.centre_speed = maxControlStep(SplineControlPoints<S>::translation(*m)) + b.angular_speed * centre.norm();
    return b;
  }
  throw std::invalid_argument(std::string(kApi) +
                              ": conservative advancement knows FCL's translation, linear interpolation, screw and "
                              "spline motions only");
}

template <typename S>
bool isUnbounded(const fcl::CollisionGeometry<S>& g)
{
  return g.getNodeType() == fcl::GEOM_PLANE || g.getNodeType() == fcl::GEOM_HALFSPACE;
}

/// A ball (in the object's frame) holding the object, or for a plane or halfspace the origin with radius 0 (the
/// caller widens it to the region the other object can reach).
template <typename S>
struct Ball
{
  fcl::Vector3<S> centre = fcl::Vector3<S>::Zero();
  S radius = 0;
};

template <typename S>
Ball<S> boundingBall(const fcl::CollisionGeometry<S>& g)
{
  Ball<S> ball;
  if (const auto* mesh = asRSMesh(&g))
  {
    fcl::AABB<S> box;
    for (int i = 0; i < mesh->num_vertices; ++i) box += mesh->vertices[i];
    ball.centre = box.center();
    for (int i = 0; i < mesh->num_vertices; ++i)
      ball.radius = std::max(ball.radius, (mesh->vertices[i] - ball.centre).norm());
    return ball;
  }
  if (isUnbounded(g)) return ball;
  if (g.getObjectType() != fcl::OT_GEOM)
    unsupportedPair(kApi, g.getNodeType(), g.getNodeType(),
                    "conservative advancement moves RS meshes and primitive shapes only");
  // The shape's local box (computeLocalAABB would write the caller's geometry).
  fcl::AABB<S> box;
  withShape(
      g, [&box](const auto& shape) { fcl::computeBV(shape, fcl::Transform3<S>::Identity(), box); },
      [&g] { unsupportedPair(kApi, g.getNodeType(), g.getNodeType(), "no bounding box for this shape"); });
  ball.centre = box.center();
  ball.radius = (box.max_ - box.min_).norm() / 2;
  return ball;
}

/// Exact distance between a mesh and a plane or halfspace, both placed: a linear function's extreme over a mesh
/// is at a vertex. Negative (or 0 for a plane crossed by the mesh) when they touch.
template <typename S>
S meshUnboundedDistance(const fcl::BVHModel<RS<S>>& mesh, const fcl::Transform3<S>& tf_mesh,
                        const fcl::CollisionGeometry<S>& other, const fcl::Transform3<S>& tf_other)
{
  const bool plane = other.getNodeType() == fcl::GEOM_PLANE;
  fcl::Vector3<S> n;
  S offset;
  if (plane)
  {
    const auto p = fcl::transform(static_cast<const fcl::Plane<S>&>(other), tf_other);
    n = p.n;
    offset = p.d;
  }
  else
  {
    const auto h = fcl::transform(static_cast<const fcl::Halfspace<S>&>(other), tf_other);
    n = h.n;
    offset = h.d;
  }
  S lo = std::numeric_limits<S>::max(), hi = std::numeric_limits<S>::lowest();
  for (int i = 0; i < mesh.num_vertices; ++i)
  {
    const S s = n.dot(tf_mesh * mesh.vertices[i]) - offset;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  if (!plane) return lo;
  if (lo > 0) return lo;
  if (hi < 0) return -hi;
  return 0;
}

template <typename S>
S pairDistance(const fcl::BVHModel<RS<S>>& mesh1, const fcl::Transform3<S>& tf1, const fcl::CollisionGeometry<S>* o2,
               const fcl::Transform3<S>& tf2, const fcl::DistanceRequest<S>& request)
{
  if (isUnbounded(*o2)) return meshUnboundedDistance(mesh1, tf1, *o2, tf2);
  fcl::DistanceResult<S> result;
  return fcl_rs::distance(&mesh1, tf1, o2, tf2, request, result);
}

}  // namespace

template <typename S>
S conservativeAdvancement(const fcl::CollisionGeometry<S>* o1, const fcl::MotionBase<S>* motion1,
                          const fcl::CollisionGeometry<S>* o2, const fcl::MotionBase<S>* motion2,
                          const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result)
{
  // The advancement is symmetric in its two objects: a shape given first is swapped behind the mesh, so that
  // below the first object is always an RS mesh.
  const auto* mesh1 = asRSMesh(o1);
  if (!mesh1)
  {
    if (!asRSMesh(o2))
      unsupportedPair(kApi, o1->getNodeType(), o2->getNodeType(), "conservative advancement needs an RS mesh");
    conservativeAdvancement(o2, motion2, o1, motion1, request, result);
    if (result.is_collide) std::swap(result.contact_tf1, result.contact_tf2);
    return result.time_of_contact;
  }
  // requireValidRequest has checked toc_err > 0, so each step below is at least toc_err / 2.
  const Ball<S> ball1 = boundingBall(*o1), ball2 = boundingBall(*o2);
  const SpeedBound<S> v1 = speedBound(*motion1, ball1.centre), v2 = speedBound(*motion2, ball2.centre);
  const S radius1 = ball1.radius;
  S radius2 = ball2.radius;
  fcl::Transform3<S> tf1, tf2;
  motion1->integrate(0);
  motion2->integrate(0);
  motion1->getCurrentTransform(tf1);
  motion2->getCurrentTransform(tf2);
  // A plane or halfspace: only its points within reach of the mesh's ball over the motion matter (the nearest
  // point to any point of the mesh is no farther from the plane's origin than that point).
  if (isUnbounded(*o2))
    radius2 = (tf1 * ball1.centre - tf2 * ball2.centre).norm() + v1.centre_speed + v2.centre_speed + radius1;
  // No point of either object moves faster than this, so the distance shrinks no faster.
  const S speed = v1.centre_speed + v1.angular_speed * radius1 + v2.centre_speed + v2.angular_speed * radius2;
  // Stop once the objects may touch within toc_err of the motion; a step is shortened by half that, which
  // covers the distance's own error (GJK's tolerance for shapes) without letting steps shrink to nothing.
  const S stop_distance = speed * request.toc_err;
  fcl::DistanceRequest<S> distance_request;
  distance_request.gjk_solver_type = request.gjk_solver_type;
  S t = 0;
  bool contact = false;
  while (true)
  {
    const S d = pairDistance(*mesh1, tf1, o2, tf2, distance_request);
    if (d <= stop_distance)
    {
      contact = true;
      break;
    }
    t += d / speed - request.toc_err / 2;
    if (t >= 1) break;
    motion1->integrate(t);
    motion2->integrate(t);
    motion1->getCurrentTransform(tf1);
    motion2->getCurrentTransform(tf2);
  }
  result.is_collide = contact;
  result.time_of_contact = contact ? t : S(1);
  if (contact)
  {
    result.contact_tf1 = tf1;
    result.contact_tf2 = tf2;
  }
  return result.time_of_contact;
}

#define FCL_RS_INSTANTIATE_CONSERVATIVE_ADVANCEMENT(S)                                                   \
  template S conservativeAdvancement<S>(const fcl::CollisionGeometry<S>*, const fcl::MotionBase<S>*,       \
                                        const fcl::CollisionGeometry<S>*, const fcl::MotionBase<S>*,       \
                                        const fcl::ContinuousCollisionRequest<S>&,                         \
                                        fcl::ContinuousCollisionResult<S>&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_CONSERVATIVE_ADVANCEMENT)
#undef FCL_RS_INSTANTIATE_CONSERVATIVE_ADVANCEMENT

}  // namespace detail
}  // namespace fcl_rs
