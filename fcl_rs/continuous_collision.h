// Drop-in fcl_rs::continuousCollide: FCL's naive (sampling) continuous collision with fcl_rs::collide at each sample.
#ifndef FCL_RS_CONTINUOUS_COLLISION_H
#define FCL_RS_CONTINUOUS_COLLISION_H

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <fcl/math/motion/interp_motion.h>
#include <fcl/narrowphase/continuous_collision.h>

#include "fcl_rs/collide.h"
#include "fcl_rs/bv/rs.h"
#include "fcl_rs/detail/relative_poses.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {

/// Same overloads and meaning as fcl::continuousCollide. Pairs without an RS mesh are passed to
/// fcl::continuousCollide, except in naive mode and for conservative advancement against a Plane or Halfspace,
/// which FCL crashes on (std::invalid_argument). Every pose FCL sees is shifted by the first object's start
/// translation (fcl_rs/detail/relative_poses.h: FCL's libccd GJK asserts on shapes far from the origin): the
/// transform and object overloads shift the four transforms before making the motions, the motion overload hands
/// FCL's advancement the caller's motions seen shifted. Pairs with an RS mesh (against an RS mesh or a
/// primitive shape, either order) support two modes:
///  * CCDC_NAIVE (the default, run here for every pair): the motions are sampled at n = min(num_max_iterations, ceil(1 / toc_err))
///    evenly spaced times (at least the two ends; FCL divides by zero for n = 1) and the first sample where
///    fcl_rs::collide finds a contact is the time of contact. Unlike FCL's naive mode, request.gjk_solver_type
///    is passed on.
///  * CCDC_CONSERVATIVE_ADVANCEMENT, for FCL's translation, linear interpolation, screw and spline motions:
///    from t = 0, the exact distance d (fcl_rs::distance; a vertex scan against planes and halfspaces) and an
///    upper bound v on the speed of every point of either object (over the whole motion: linear speed of the
///    object's bounding-ball centre plus angular speed times its radius) allow a step of d / v with no
///    contact possible before it; each step is shortened by toc_err / 2 to absorb the distance's own error
///    (GJK's tolerance for shapes). It stops with a contact once d <= v * toc_err: the time of contact is
///    never later than the true first contact, and a contact is reported only when the objects are within
///    v * toc_err of each other (toc_err times the largest distance a point can travel), so a free motion
///    with more clearance than that is reported free. num_max_iterations is not used (FCL's advancement has
///    no limit either); at most 2 / toc_err steps are taken.
///    FCL's own advancement (RSS and OBBRSS) can be late or miss a contact (FCL issues 120 and 555):
///    tests/test_continuous_collision.cpp counts where, on the same motions.
/// The transform overloads need S = double with linear and screw motions: FCL 0.7's InterpMotion and
/// ScrewMotion declare integrate(double), so for float they are abstract classes and do not compile. They
/// throw for CCDM_SPLINE: FCL 0.7's SplineMotion(tf1, tf2) leaves its control points uninitialized.
/// Poses (the transforms, or the motions' ends) must be rigid and the request valid (fcl_rs/validate.h), else
/// std::invalid_argument names the argument. For RS meshes the other modes throw std::invalid_argument, since
/// FCL cannot run them on RS (and on plain FCL they
/// report "no collision" for RS meshes, silently):
///  * CCDC_POLYNOMIAL_SOLVER switches over FCL's own BV types only; its traversal also tests the models'
///    BVs as if they were in the world frame (the poses are ignored) and overwrites the caller's vertices.
///  * CCDC_RAY_SHOOTING is not implemented in FCL 0.7 for any pair.
template <typename S>
S continuousCollide(const fcl::CollisionGeometry<S>* o1, const fcl::MotionBase<S>* motion1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::MotionBase<S>* motion2,
                    const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result);

namespace detail {
/// CCDC_CONSERVATIVE_ADVANCEMENT for a pair with an RS mesh (src/conservative_advancement.cpp).
template <typename S>
S conservativeAdvancement(const fcl::CollisionGeometry<S>* o1, const fcl::MotionBase<S>* motion1,
                          const fcl::CollisionGeometry<S>* o2, const fcl::MotionBase<S>* motion2,
                          const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result);
#define FCL_RS_DECLARE_CONSERVATIVE_ADVANCEMENT(S)                                                             \
  extern template S conservativeAdvancement<S>(const fcl::CollisionGeometry<S>*, const fcl::MotionBase<S>*,    \
                                               const fcl::CollisionGeometry<S>*, const fcl::MotionBase<S>*,    \
                                               const fcl::ContinuousCollisionRequest<S>&,                       \
                                               fcl::ContinuousCollisionResult<S>&);
FCL_RS_DECLARE_CONSERVATIVE_ADVANCEMENT(float)
FCL_RS_DECLARE_CONSERVATIVE_ADVANCEMENT(double)
#undef FCL_RS_DECLARE_CONSERVATIVE_ADVANCEMENT
}  // namespace detail

namespace detail {
/// fcl::getMotionBase, except that a linear motion gets its reference point (the object's origin): FCL 0.7's
/// InterpMotion(tf1, tf2), which getMotionBase builds, leaves it uninitialized, so the path depended on stale memory.
template <typename S>
fcl::MotionBasePtr<S> motionBetween(const fcl::Transform3<S>& beg, const fcl::Transform3<S>& end,
                                    fcl::CCDMotionType type)
{
  if (type == fcl::CCDM_LINEAR)
    return std::make_shared<fcl::InterpMotion<S>>(beg.linear(), beg.translation(), end.linear(), end.translation(),
                                                  fcl::Vector3<S>::Zero());
  return fcl::getMotionBase(beg, end, type);
}
}  // namespace detail

template <typename S>
S continuousCollide(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1_beg,
                    const fcl::Transform3<S>& tf1_end, const fcl::CollisionGeometry<S>* o2,
                    const fcl::Transform3<S>& tf2_beg, const fcl::Transform3<S>& tf2_end,
                    const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result)
{
  constexpr const char* api = "fcl_rs::continuousCollide";
  requireRigidTransform(tf1_beg, api, "tf1_beg");
  requireRigidTransform(tf1_end, api, "tf1_end");
  requireRigidTransform(tf2_beg, api, "tf2_beg");
  requireRigidTransform(tf2_end, api, "tf2_end");
  requireValidRequest(request, api);
  if (request.ccd_motion_type == fcl::CCDM_SPLINE)
    throw std::invalid_argument(
        "fcl_rs::continuousCollide: FCL 0.7 cannot make a spline motion from two transforms (SplineMotion(tf1, "
        "tf2) leaves its control points uninitialized); pass fcl::SplineMotion objects built from control points");
  // The motions are made between transforms shifted by -tf1_beg's translation (fcl_rs/detail/relative_poses.h), so
  // that they interpolate the relative placement too (far away a motion's absolute positions round); the contact
  // transforms are shifted back. Translation, linear and screw motions commute with the shift.
  const fcl::Vector3<S> shift = tf1_beg.translation();
  const fcl::MotionBasePtr<S> motion1 = detail::motionBetween(detail::shifted(tf1_beg, shift),
                                                              detail::shifted(tf1_end, shift), request.ccd_motion_type);
  const fcl::MotionBasePtr<S> motion2 = detail::motionBetween(detail::shifted(tf2_beg, shift),
                                                              detail::shifted(tf2_end, shift), request.ccd_motion_type);
  const S time_of_contact = fcl_rs::continuousCollide(o1, motion1.get(), o2, motion2.get(), request, result);
  if (result.is_collide)
  {
    result.contact_tf1.translation() += shift;
    result.contact_tf2.translation() += shift;
  }
  return time_of_contact;
}

/// The objects move from their current transforms to tf1_end and tf2_end.
template <typename S>
S continuousCollide(const fcl::CollisionObject<S>* o1, const fcl::Transform3<S>& tf1_end,
                    const fcl::CollisionObject<S>* o2, const fcl::Transform3<S>& tf2_end,
                    const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result)
{
  constexpr const char* api = "fcl_rs::continuousCollide";
  if (!o1 || !o2) throw std::invalid_argument("fcl_rs::continuousCollide: null collision object");
  requireRigidTransform(o1->getTransform(), api, "o1->getTransform()");
  requireRigidTransform(o2->getTransform(), api, "o2->getTransform()");
  return fcl_rs::continuousCollide(o1->collisionGeometry().get(), o1->getTransform(), tf1_end,
                                   o2->collisionGeometry().get(), o2->getTransform(), tf2_end, request, result);
}

template <typename S>
S continuousCollide(const fcl::CollisionGeometry<S>* o1, const fcl::MotionBase<S>* motion1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::MotionBase<S>* motion2,
                    const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result)
{
  constexpr const char* api = "fcl_rs::continuousCollide";
  if (!o1 || !o2) throw std::invalid_argument("fcl_rs::continuousCollide: null collision geometry");
  if (!motion1 || !motion2)
    throw std::invalid_argument("fcl_rs::continuousCollide: null motion (unknown request.ccd_motion_type?)");
  requireValidShape(o1, api, "o1");
  requireValidShape(o2, api, "o2");
  requireValidRequest(request, api);
  // A motion between two rigid transforms stays rigid in between (FCL interpolates rotations as quaternions).
  fcl::Transform3<S> tf1, tf2, start1;
  for (const S t : {S(0), S(1)})
  {
    motion1->integrate(t);
    motion2->integrate(t);
    motion1->getCurrentTransform(tf1);
    motion2->getCurrentTransform(tf2);
    requireRigidTransform(tf1, api, t == 0 ? "motion1's start" : "motion1's end");
    requireRigidTransform(tf2, api, t == 0 ? "motion2's start" : "motion2's end");
    if (t == 0) start1 = tf1;
  }
  const bool has_rs = dynamic_cast<const fcl::BVHModel<RS<S>>*>(o1) || dynamic_cast<const fcl::BVHModel<RS<S>>*>(o2);
  // Naive mode runs here for every pair: FCL's own loop divides 0 by 0 for num_max_iterations 1 (and samples a NaN
  // pose) and converts 1 / toc_err to std::size_t unchecked.
  if (!has_rs && request.ccd_solver_type == fcl::CCDC_CONSERVATIVE_ADVANCEMENT)
  {
    // FCL's advancement measures distances, and its GJK has no support function for planes and halfspaces: it
    // crashed on every shape-plane pair tried (as fcl_rs::distance refuses those pairs).
    for (const fcl::CollisionGeometry<S>* o : {o1, o2})
      if (o->getNodeType() == fcl::GEOM_PLANE || o->getNodeType() == fcl::GEOM_HALFSPACE)
        throw std::invalid_argument(
            "fcl_rs::continuousCollide: FCL's conservative advancement crashes on a plane or halfspace (its GJK has no "
            "support function for them); use CCDC_NAIVE, or an RS mesh");
    // FCL sees both motions shifted by -motion1's start (fcl_rs/detail/relative_poses.h); the contact transforms
    // are shifted back. (fcl_rs's own paths, naive sampling and RS advancement, shift in collide and distance.)
    const fcl::Vector3<S> shift = start1.translation();
    const detail::ShiftedMotion<S> near1(*motion1, shift), near2(*motion2, shift);
    const S time_of_contact = fcl::continuousCollide(o1, &near1, o2, &near2, request, result);
    if (result.is_collide)
    {
      result.contact_tf1.translation() += shift;
      result.contact_tf2.translation() += shift;
    }
    return time_of_contact;
  }
  // FCL's polynomial solver casts the motions to TranslationMotion (they are passed as they are) and its ray
  // shooting is empty.
  if (!has_rs && request.ccd_solver_type != fcl::CCDC_NAIVE)
    return fcl::continuousCollide(o1, motion1, o2, motion2, request, result);
  switch (request.ccd_solver_type)
  {
    case fcl::CCDC_NAIVE: break;
    case fcl::CCDC_CONSERVATIVE_ADVANCEMENT:
      return detail::conservativeAdvancement(o1, motion1, o2, motion2, request, result);
    case fcl::CCDC_POLYNOMIAL_SOLVER:
      throw std::invalid_argument(
          "fcl_rs::continuousCollide: the polynomial solver is not supported for RS meshes (FCL's switch has no RS "
          "case, and its traversal ignores the poses and overwrites the models' vertices); use CCDC_NAIVE");
    case fcl::CCDC_RAY_SHOOTING:
      throw std::invalid_argument(
          "fcl_rs::continuousCollide: ray shooting is not implemented in FCL 0.7; use CCDC_NAIVE");
    default:
      throw std::invalid_argument("fcl_rs::continuousCollide: unknown request.ccd_solver_type " +
                                  std::to_string(int(request.ccd_solver_type)));
  }
  // Compared before the conversion: 1 / toc_err may exceed every std::size_t.
  const std::size_t samples = std::max<std::size_t>(
      2, S(request.num_max_iterations) <= std::ceil(1 / request.toc_err) ? request.num_max_iterations
                                                                         : std::size_t(std::ceil(1 / request.toc_err)));
  fcl::CollisionRequest<S> collision_request;
  collision_request.gjk_solver_type = request.gjk_solver_type;
  for (std::size_t i = 0; i < samples; ++i)
  {
    const S t = S(i) / S(samples - 1);
    motion1->integrate(t);
    motion2->integrate(t);
    motion1->getCurrentTransform(tf1);
    motion2->getCurrentTransform(tf2);
    fcl::CollisionResult<S> collision_result;
    if (fcl_rs::collide(o1, tf1, o2, tf2, collision_request, collision_result))
    {
      result.is_collide = true;
      result.time_of_contact = t;
      result.contact_tf1 = tf1;
      result.contact_tf2 = tf2;
      return t;
    }
  }
  result.is_collide = false;
  result.time_of_contact = 1;
  return result.time_of_contact;
}

}  // namespace fcl_rs

#endif
