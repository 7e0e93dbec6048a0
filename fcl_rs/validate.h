// Validation of what every public entry point takes: poses (rigid transforms) and request fields. One message
// format, "<api>: <argument> ...", thrown as std::invalid_argument, so that bad input never reaches FCL or
// libccd (whose assertions abort on NaN) and is never answered.
#ifndef FCL_RS_VALIDATE_H
#define FCL_RS_VALIDATE_H

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/common/types.h>
#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/continuous_collision_request.h>
#include <fcl/narrowphase/distance_request.h>

namespace fcl_rs {

/// The largest |R^T R - I| entry a pose's rotation R may have: 256 eps(S). Honest rotations stay far below it:
/// one built from a normalized quaternion departs by about 8 eps, a product of 100 such rotations (a kinematic
/// chain deeper than any robot's) by under 80 eps, in float and in double. Beyond it lies a scale, a shear or
/// an integrated rotation that drifted (for double a scale of 1 + 6e-14 already is), which is refused rather
/// than answered for a transform that is not rigid.
template <typename S>
constexpr S rigidTransformTolerance()
{
  return 256 * std::numeric_limits<S>::epsilon();
}

/// Whether tf is a rigid transform: every entry finite, the last row of its matrix [0, 0, 0, 1], the rotation
/// orthonormal within `tolerance` (per entry of R^T R - I) and proper (det R > 0, no reflection).
template <typename S>
bool isRigidTransform(const fcl::Transform3<S>& tf, S tolerance = rigidTransformTolerance<S>())
{
  const auto& m = tf.matrix();
  if (!(m(3, 0) == 0 && m(3, 1) == 0 && m(3, 2) == 0 && m(3, 3) == 1)) return false;
  if (!(std::isfinite(m(0, 3)) && std::isfinite(m(1, 3)) && std::isfinite(m(2, 3)))) return false;
  // Written so that a NaN fails every comparison; an infinite entry makes a product infinite or NaN.
  const auto R = tf.linear();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j)
      if (!(std::abs(R.col(i).dot(R.col(j)) - S(i == j)) <= tolerance)) return false;
  return R.col(0).cross(R.col(1)).dot(R.col(2)) > 0;
}

namespace detail {

/// "<api>: <argument> is not a rigid transform: <the first defect found>", for a tf isRigidTransform refuses.
template <typename S>
std::string notRigidMessage(const fcl::Transform3<S>& tf, S tolerance, const char* api, const std::string& argument)
{
  std::ostringstream msg;
  msg.precision(std::numeric_limits<S>::max_digits10);
  msg << api << ": " << argument << " is not a rigid transform: ";
  const auto& m = tf.matrix();
  const auto R = tf.linear();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m(i, j)))
      {
        msg << "entry (" << i << ", " << j << ") is " << m(i, j);
        return msg.str();
      }
  if (!(m(3, 0) == 0 && m(3, 1) == 0 && m(3, 2) == 0 && m(3, 3) == 1))
  {
    msg << "its last row is [" << m(3, 0) << ", " << m(3, 1) << ", " << m(3, 2) << ", " << m(3, 3)
        << "], not [0, 0, 0, 1]";
    return msg.str();
  }
  S departure = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) departure = std::max(departure, std::abs(R.col(i).dot(R.col(j)) - S(i == j)));
  if (!(departure <= tolerance))
    msg << "its rotation is not orthonormal (largest entry of |R^T R - I| is " << departure << ", at most "
        << tolerance << " is accepted; a scaled or sheared matrix is not a pose)";
  else
    msg << "its rotation is a reflection (det R = " << R.determinant() << ")";
  return msg.str();
}

}  // namespace detail

/// Throws std::invalid_argument "<api>: <argument> is not a rigid transform: <why>" unless isRigidTransform(tf).
template <typename S>
void requireRigidTransform(const fcl::Transform3<S>& tf, const char* api, const char* argument,
                           S tolerance = rigidTransformTolerance<S>())
{
  if (!isRigidTransform(tf, tolerance))
    throw std::invalid_argument(detail::notRigidMessage(tf, tolerance, api, argument));
}

/// requireRigidTransform for every element, named "<argument>[i]" (the batches validate each array once).
template <typename S>
void requireRigidTransforms(const std::vector<fcl::Transform3<S>>& tfs, const char* api, const char* argument)
{
  for (std::size_t i = 0; i < tfs.size(); ++i)
    if (!isRigidTransform(tfs[i]))
      throw std::invalid_argument(detail::notRigidMessage(tfs[i], rigidTransformTolerance<S>(), api,
                                                          std::string(argument) + "[" + std::to_string(i) + "]"));
}

/// Throws std::invalid_argument "<api>: <argument> is an fcl::<Shape> with <what is wrong>" unless geometry, if it
/// is one of FCL's primitive shapes (the ones detail::withShape dispatches), has sizes fcl_rs can answer for: Box
/// sides, Sphere radius, Ellipsoid radii, Capsule, Cone and Cylinder radius and lz positive and finite; a Convex with
/// finite vertices and a face list whose faces have at least 3 vertices, with indices in range; a Plane or Halfspace
/// with a unit normal (within rigidTransformTolerance on |n|^2) and a finite offset; a TriangleP with finite
/// vertices (a zero-area one, a segment or a point, is valid: mesh-TriangleP pairs run the mesh-mesh triangle
/// test, which answers degenerate triangles exactly). Other geometries (meshes, octrees) and null pass; the entries
/// check null themselves. Constant time, but linear in a Convex's
/// size, as its leaf set-up is (src/validate.cpp).
template <typename S>
void requireValidShape(const fcl::CollisionGeometry<S>* geometry, const char* api, const char* argument);

namespace detail {

[[noreturn]] inline void badRequestField(const char* api, const char* field, const std::string& what)
{
  throw std::invalid_argument(std::string(api) + ": request." + field + " " + what);
}

template <typename S>
std::string valueText(S value)
{
  std::ostringstream text;
  text.precision(std::numeric_limits<S>::max_digits10);
  text << value;
  return text.str();
}

template <typename S>
void requirePositive(const char* api, const char* field, S value)
{
  if (!(value > 0 && std::isfinite(value)))
    badRequestField(api, field, "must be positive and finite, got " + valueText(value));
}

template <typename S>
void requireNonNegative(const char* api, const char* field, S value)
{
  if (!(value >= 0 && std::isfinite(value)))
    badRequestField(api, field, "must be non-negative and finite, got " + valueText(value));
}

}  // namespace detail

// The enum fields (solver and motion types) are not checked: a value outside an enum's enumerators cannot be
// stored in it without undefined behaviour.

/// Throws std::invalid_argument naming the field: num_max_contacts 0 (a request for nothing, which FCL answers
/// "no collision" whatever the objects do), gjk_tolerance not positive and finite, a non-finite
/// cached_gjk_guess in use.
template <typename S>
void requireValidRequest(const fcl::CollisionRequest<S>& request, const char* api)
{
  if (request.num_max_contacts == 0) detail::badRequestField(api, "num_max_contacts", "must be at least 1, got 0");
  detail::requirePositive(api, "gjk_tolerance", request.gjk_tolerance);
  if (request.enable_cached_gjk_guess && !request.cached_gjk_guess.allFinite())
    detail::badRequestField(api, "cached_gjk_guess", "must be finite when enable_cached_gjk_guess is set");
}

/// Throws std::invalid_argument naming the field: rel_err or abs_err negative or not finite, distance_tolerance
/// not positive and finite.
template <typename S>
void requireValidRequest(const fcl::DistanceRequest<S>& request, const char* api)
{
  detail::requireNonNegative(api, "rel_err", request.rel_err);
  detail::requireNonNegative(api, "abs_err", request.abs_err);
  detail::requirePositive(api, "distance_tolerance", request.distance_tolerance);
}

/// Throws std::invalid_argument naming the field: num_max_iterations 0, toc_err not positive and finite.
template <typename S>
void requireValidRequest(const fcl::ContinuousCollisionRequest<S>& request, const char* api)
{
  if (request.num_max_iterations == 0) detail::badRequestField(api, "num_max_iterations", "must be at least 1, got 0");
  detail::requirePositive(api, "toc_err", request.toc_err);
}

}  // namespace fcl_rs

#endif
