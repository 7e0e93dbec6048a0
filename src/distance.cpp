// fcl_rs::distance: dispatch of RS mesh pairs to the local-frame RS traversal, everything else to FCL.
#include "rs_pairs.h"
#include "scalars.h"
#include "shape_signed_distance.h"
#include "validated_entries.h"
#include "fcl_rs/distance.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include <fcl/narrowphase/distance.h>
#include <fcl/narrowphase/detail/distance_func_matrix.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include "fcl_rs/collide.h"
#include "fcl_rs/detail/relative_poses.h"
#include "fcl_rs/fcl_float.h"
#include "fcl_rs/traversal/distance_traversal.h"
#include "fcl_rs/traversal/octree_traversal.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {
namespace {

using detail::asRSMesh;

constexpr const char* kApi = "fcl_rs::distance";

/// fcl::detail::orientedMeshDistance, with the descent of distanceTrees.
template <typename S>
S meshMesh(const fcl::BVHModel<RS<S>>& m1, const fcl::Transform3<S>& tf1, const fcl::BVHModel<RS<S>>& m2,
           const fcl::Transform3<S>& tf2, const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  if (!request.isSatisfied(result))
  {
    MeshDistanceTraversalNodeRS<S> node;
    initialize(node, m1, tf1, m2, tf2, request, result);
    distanceTrees(node);
  }
  return result.min_distance;
}

template <typename Shape, typename S, typename Solver>
S meshShape(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh, const Shape& shape,
            const fcl::Transform3<S>& tf_shape, const Solver* solver, const fcl::DistanceRequest<S>& request,
            fcl::DistanceResult<S>& result)
{
  // FCL's driver (fcl::detail::orientedBVHShapeDistance) with our local-frame node and descent.
  if (request.isSatisfied(result)) return result.min_distance;
  MeshShapeDistanceTraversalNodeRS<Shape, Solver> node;
  initialize(node, model, tf_mesh, shape, tf_shape, solver, request, result);
  distanceMeshShape(node);
  return result.min_distance;
}

/// A TriangleP: the triangle as a one-triangle mesh (no solver), named in the result as FCL names a shape (o2,
/// b2 = NONE).
template <typename S, typename Solver>
S meshShape(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh, const fcl::TriangleP<S>& triangle,
            const fcl::Transform3<S>& tf_triangle, const Solver*, const fcl::DistanceRequest<S>& request,
            fcl::DistanceResult<S>& result)
{
  const auto triangle_mesh = detail::triangleAsMesh(triangle);
  const S res = meshMesh(model, tf_mesh, *triangle_mesh, tf_triangle, request, result);
  if (result.o2 == triangle_mesh.get())
  {
    result.o2 = &triangle;
    result.b2 = fcl::DistanceResult<S>::NONE;
  }
  return res;
}

template <typename S, typename Solver>
S meshShapeDispatch(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh,
                    const fcl::CollisionGeometry<S>* shape, const fcl::Transform3<S>& tf_shape, const Solver* solver,
                    const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  return detail::withShape(
      *shape,
      [&](const auto& geometry) -> S { return meshShape(model, tf_mesh, geometry, tf_shape, solver, request, result); },
      [&]() -> S {
        detail::unsupportedPair(kApi, model.getNodeType(), shape->getNodeType(),
                                "FCL has no mesh distance for this shape");
      });
}

/// FCL's signed-distance fallback for meshes (distance-inl.h): a negative distance becomes minus the deepest
/// contact's penetration depth, both nearest points that contact's position (not on the surfaces). Two faults of
/// FCL's version are avoided: it asks collide() for one contact only, so its "deepest" contact is whichever the
/// BV type's traversal meets first; and FCL's sphere-triangle test and GJKSolver_indep's triangle tests report
/// depths as negative numbers, which FCL's search never selects (it then reads past the contact list). Here
/// every contact is searched, by depth magnitude. Without any contact (the distance and collision tests disagree at their tolerances) the two
/// objects touch as far as either test can tell: the distance becomes 0.
template <typename S>
void signedDistanceFromContacts(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                                const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                                const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  fcl::CollisionRequest<S> collision_request(std::numeric_limits<std::size_t>::max(), /*enable_contact=*/true);
  collision_request.gjk_solver_type = request.gjk_solver_type;
  fcl::CollisionResult<S> collision_result;
  detail::collideValidated(o1, tf1, o2, tf2, collision_request, collision_result);
  if (collision_result.numContacts() == 0)
  {
    result.min_distance = 0;
    return;
  }
  std::size_t index = 0;
  for (std::size_t i = 1; i < collision_result.numContacts(); ++i)
    if (std::abs(collision_result.getContact(i).penetration_depth) >
        std::abs(collision_result.getContact(index).penetration_depth))
      index = i;
  const fcl::Contact<S>& deepest = collision_result.getContact(index);
  result.min_distance = -std::abs(deepest.penetration_depth);
  if (request.enable_nearest_points)
  {
    result.nearest_points[0] = deepest.pos;
    result.nearest_points[1] = deepest.pos;
  }
}

/// fcl::distance with both poses moved by -tf1's translation (fcl_rs/detail/relative_poses.h); nearest points this
/// query sets are moved back.
template <typename S>
S fclDistanceRelative(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                      const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                      const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  const fcl::Vector3<S> shift = tf1.translation();
  const fcl::Transform3<S> near1 = detail::shifted(tf1, shift), near2 = detail::shifted(tf2, shift);
  const S before = result.min_distance;
  const S res = fcl::distance(o1, near1, o2, near2, request, result);
  // FCL's DistanceResult::update writes the nearest points with a strictly smaller distance only.
  if (request.enable_nearest_points && result.min_distance < before)
  {
    result.nearest_points[0] += shift;
    result.nearest_points[1] += shift;
  }
  return res;
}

template <typename S, typename Solver>
S distanceRS(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1, const fcl::CollisionGeometry<S>* o2,
             const fcl::Transform3<S>& tf2, const Solver* solver, const fcl::DistanceRequest<S>& request,
             fcl::DistanceResult<S>& result)
{
  const auto* m1 = asRSMesh(o1);
  const auto* m2 = asRSMesh(o2);
  if (m1) detail::requireBuiltTriangles(kApi, *m1);
  if (m2) detail::requireBuiltTriangles(kApi, *m2);
  const S start_distance = result.min_distance;
  S res;
  if (m1 && m2)
    res = meshMesh(*m1, tf1, *m2, tf2, request, result);
  else
  {
    // The result is not swapped back, as in fcl::distance.
    const auto pair = detail::meshBeforeOther(o1, m1, tf1, o2, m2, tf2);
#if FCL_HAVE_OCTOMAP
    if (pair.other->getNodeType() == fcl::GEOM_OCTREE)
    {
      // fcl::detail::OcTreeBVHDistance and BVHOcTreeDistance with the RS traversal: the result names the octree
      // first in either order, as FCL's does.
      if (!request.isSatisfied(result))
        distanceOcTreeMesh(static_cast<const fcl::OcTree<S>&>(*pair.other), pair.tf_other, pair.mesh, pair.tf_mesh,
                           *solver, request, result);
      res = result.min_distance;
    }
    else
#endif
    {
      if (pair.other->getObjectType() != fcl::OT_GEOM)
        detail::unsupportedPair(kApi, o1->getNodeType(), o2->getNodeType(),
                                "an RS mesh measures distance to RS meshes, octrees and primitive shapes only");
      res = meshShapeDispatch(pair.mesh, pair.tf_mesh, pair.other, pair.tf_other, solver, request, result);
    }
  }
  // Only when this query made the distance negative: a result shared by several queries (the broadphase
  // callbacks) may hold an earlier pair's negative distance.
  if (request.enable_signed_distance && result.min_distance < 0 && result.min_distance < start_distance)
    signedDistanceFromContacts(o1, tf1, o2, tf2, request, result);
  return res;  // fcl::distance also returns the traversal's value, not the signed replacement
}

}  // namespace

namespace detail {

template <typename S>
S distanceValidated(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                    const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  if (!o1 || !o2) throw std::invalid_argument("fcl_rs::distance: null collision geometry");
  if (!asRSMesh(o1) && !asRSMesh(o2))
  {
    // FCL's GJK (both solvers) has no support function for planes and halfspaces: fcl::distance on a shape pair
    // with one calls a null function (found by fuzz_api), as it does for meshes (meshShapeDispatch).
    for (const fcl::NODE_TYPE type : {o1->getNodeType(), o2->getNodeType()})
      if (type == fcl::GEOM_PLANE || type == fcl::GEOM_HALFSPACE)
        detail::unsupportedPair(kApi, o1->getNodeType(), o2->getNodeType(),
                                "FCL has no distance to a plane or halfspace (its GJK calls a null support function)");
    if (!request.enable_signed_distance) return fclDistanceRelative(o1, tf1, o2, tf2, request, result);
    // Two shapes: closed forms, else libccd's GJK and a bounded EPA, whichever the solver (shape_signed_distance.h:
    // FCL's libccd EPA can run for minutes, GJKSolver_indep's depths of curved shapes are far off).
    if (o1->getObjectType() == fcl::OT_GEOM && o2->getObjectType() == fcl::OT_GEOM)
    {
      if (request.isSatisfied(result)) return result.min_distance;
      const auto signed_distance = detail::shape_signed_distance::signedDistance(
          *o1, tf1, *o2, tf2, fcl::detail::GJKSolver_libccd<S>().max_distance_iterations,
          double(request.distance_tolerance), kApi);
      if (signed_distance)
      {
        // As FCL's shape-shape node: both nearest points are written, whatever enable_nearest_points says.
        result.update(S(signed_distance->distance), o1, o2, fcl::DistanceResult<S>::NONE,
                      fcl::DistanceResult<S>::NONE, signed_distance->p1.template cast<S>(),
                      signed_distance->p2.template cast<S>());
        return result.min_distance;
      }
    }
    // FCL's fallback for every other pair asserts (or reads before its contact list) when no contact has a positive
    // depth, as GJKSolver_indep's are (found by fuzz_api): fcl_rs's fallback, as for RS meshes, runs instead.
    fcl::DistanceRequest<S> unsigned_request(request);
    unsigned_request.enable_signed_distance = false;
    const S start_distance = result.min_distance;
    const S res = fclDistanceRelative(o1, tf1, o2, tf2, unsigned_request, result);
    if (result.min_distance < 0 && result.min_distance < start_distance)
      signedDistanceFromContacts(o1, tf1, o2, tf2, request, result);
    return res;
  }
  // The same solver set-up as fcl::distance.
  switch (request.gjk_solver_type)
  {
    case fcl::GST_LIBCCD:
    {
      fcl::detail::GJKSolver_libccd<S> solver;
      solver.distance_tolerance = request.distance_tolerance;
      return distanceRS(o1, tf1, o2, tf2, &solver, request, result);
    }
    case fcl::GST_INDEP:
    {
      fcl::detail::GJKSolver_indep<S> solver;
      solver.gjk_tolerance = request.distance_tolerance;
      return distanceRS(o1, tf1, o2, tf2, &solver, request, result);
    }
  }
  throw std::invalid_argument("fcl_rs::distance: unknown request.gjk_solver_type");
}

template <typename S>
bool distanceAlong(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                   const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                   const fcl::Vector3<double>& direction, const fcl::DistanceRequest<S>& request,
                   fcl::DistanceResult<S>& result)
{
  // Exact unsigned distances only (the traversals' error bounds and the signed fallback are theirs).
  if (request.rel_err != 0 || request.abs_err != 0 || request.enable_signed_distance) return false;
  const auto* m1 = asRSMesh(o1);
  const auto* m2 = asRSMesh(o2);
  if (m1) detail::requireBuiltTriangles(kApi, *m1);
  if (m2) detail::requireBuiltTriangles(kApi, *m2);
  if (m1 && m2)
  {
    if (request.isSatisfied(result)) return true;
    MeshDistanceTraversalNodeRS<S> node;
    initialize(node, *m1, tf1, *m2, tf2, request, result);
    if (!fcl_rs::distanceAlong(node, Eigen::Vector3d(tf1.linear().template cast<double>().transpose() * direction)))
      return false;
    node.MeshDistanceTraversalNodeRS<S>::postprocess();
    return true;
  }
  if (!m1 && !m2) return false;
  // The direction then points from the mesh to the shape.
  const auto pair = detail::meshBeforeOther(o1, m1, tf1, o2, m2, tf2);
  const Eigen::Vector3d towards_shape = pair.mesh_first ? direction : Eigen::Vector3d(-direction);
  return withShape(
      *pair.other,
      [&](const auto& geometry) -> bool {
        using Shape = std::decay_t<decltype(geometry)>;
        if constexpr (std::is_same_v<Shape, fcl::Box<S>> || std::is_same_v<Shape, fcl::Sphere<S>> ||
                      std::is_same_v<Shape, fcl::Cylinder<S>> || std::is_same_v<Shape, fcl::Capsule<S>>)
        {
          if (request.isSatisfied(result)) return true;
          fcl::detail::GJKSolver_libccd<S> solver;  // the node asks for one; the RS leaves do not use it
          MeshShapeDistanceTraversalNodeRS<Shape, fcl::detail::GJKSolver_libccd<S>> node;
          initialize(node, pair.mesh, pair.tf_mesh, geometry, pair.tf_other, &solver, request, result);
          return fcl_rs::distanceAlong(
              node, Eigen::Vector3d(pair.tf_other.linear().template cast<double>().transpose() * towards_shape));
        }
        else
          return false;
      },
      []() { return false; });
}

}  // namespace detail

template <typename S>
S distance(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1, const fcl::CollisionGeometry<S>* o2,
           const fcl::Transform3<S>& tf2, const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  requireRigidTransform(tf1, kApi, "tf1");
  requireRigidTransform(tf2, kApi, "tf2");
  requireValidShape(o1, kApi, "o1");
  requireValidShape(o2, kApi, "o2");
  requireValidRequest(request, kApi);
  return detail::distanceValidated(o1, tf1, o2, tf2, request, result);
}

template <typename S>
S distance(const fcl::CollisionObject<S>* o1, const fcl::CollisionObject<S>* o2,
           const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  if (!o1 || !o2) throw std::invalid_argument("fcl_rs::distance: null collision object");
  requireRigidTransform(o1->getTransform(), kApi, "o1->getTransform()");
  requireRigidTransform(o2->getTransform(), kApi, "o2->getTransform()");
  requireValidShape(o1->collisionGeometry().get(), kApi, "o1->collisionGeometry()");
  requireValidShape(o2->collisionGeometry().get(), kApi, "o2->collisionGeometry()");
  requireValidRequest(request, kApi);
  return detail::distanceValidated(o1->collisionGeometry().get(), o1->getTransform(), o2->collisionGeometry().get(),
                                   o2->getTransform(), request, result);
}

#define FCL_RS_INSTANTIATE_DISTANCE(S)                                                                        \
  template S detail::distanceValidated<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,        \
                                          const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,        \
                                          const fcl::DistanceRequest<S>&, fcl::DistanceResult<S>&);          \
  template bool detail::distanceAlong<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,        \
                                         const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,        \
                                         const fcl::Vector3<double>&, const fcl::DistanceRequest<S>&,       \
                                         fcl::DistanceResult<S>&);                                           \
  template S distance<S>(const fcl::CollisionObject<S>*, const fcl::CollisionObject<S>*,                     \
                         const fcl::DistanceRequest<S>&, fcl::DistanceResult<S>&);                           \
  template S distance<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,                        \
                         const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,                        \
                         const fcl::DistanceRequest<S>&, fcl::DistanceResult<S>&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_DISTANCE)
#undef FCL_RS_INSTANTIATE_DISTANCE

}  // namespace fcl_rs
