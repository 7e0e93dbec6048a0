// fcl_rs::collide: dispatch of RS mesh pairs to the local-frame RS traversal, everything else to FCL.
#include "rs_pairs.h"
#include "scalars.h"
#include "validated_entries.h"
#include "fcl_rs/collide.h"

#include <algorithm>
#include <limits>
#include <sstream>
#include <vector>
#include <stdexcept>

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/collision_func_matrix.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include "fcl_rs/detail/relative_poses.h"
#include "fcl_rs/fcl_float.h"
#include "fcl_rs/traversal/collision_traversal.h"
#include "fcl_rs/traversal/octree_traversal.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {
namespace {

using detail::asRSMesh;

constexpr const char* kApi = "fcl_rs::collide";

/// FCL's approximate cost of a mesh against another geometry: the box of the mesh's root (with the mesh's cost
/// density and thresholds) against it, for cost sources only (collide_box(box, box_tf, only_cost_request)).
template <typename S, typename CollideBox>
void addApproximateCost(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh,
                        const fcl::CollisionRequest<S>& request, const fcl::CollisionResult<S>& result,
                        CollideBox collide_box)
{
  fcl::Box<S> box;
  fcl::Transform3<S> box_tf;
  constructBox(model.getBV(0).bv, tf_mesh, box, box_tf);
  box.cost_density = model.cost_density;
  box.threshold_occupied = model.threshold_occupied;
  box.threshold_free = model.threshold_free;
  const fcl::CollisionRequest<S> only_cost_request(result.numContacts(), false, request.num_max_cost_sources, true,
                                                   false);
  collide_box(box, box_tf, only_cost_request);
}

template <typename S>
std::size_t meshMesh(const fcl::BVHModel<RS<S>>& m1, const fcl::Transform3<S>& tf1, const fcl::BVHModel<RS<S>>& m2,
                     const fcl::Transform3<S>& tf2, const fcl::CollisionRequest<S>& request,
                     fcl::CollisionResult<S>& result)
{
  if (request.isSatisfied(result)) return result.numContacts();
  MeshCollisionTraversalNodeRS<S> node;
  initialize(node, m1, tf1, m2, tf2, request, result);
  collideTrees(node);
  return result.numContacts();
}

template <typename Shape, typename S, typename Solver>
std::size_t meshShape(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh, const Shape& shape,
                      const fcl::Transform3<S>& tf_shape, const Solver* solver, const fcl::CollisionRequest<S>& request,
                      fcl::CollisionResult<S>& result)
{
  // FCL's driver (fcl::detail::orientedBVHShapeCollide, approximate-cost branch included) with our local-frame
  // node and our traversal loop.
  if (request.isSatisfied(result)) return result.numContacts();
  const bool approximate_cost = request.enable_cost && request.use_approximate_cost;
  fcl::CollisionRequest<S> mesh_request(request);
  mesh_request.enable_cost = request.enable_cost && !approximate_cost;
  MeshShapeCollisionTraversalNodeRS<Shape, Solver> node;
  initialize(node, model, tf_mesh, shape, tf_shape, solver, mesh_request, result);
  collideMeshShape(node);
  if (approximate_cost)
    addApproximateCost(model, tf_mesh, request, result, [&](const fcl::Box<S>& box, const fcl::Transform3<S>& box_tf,
                                                            const fcl::CollisionRequest<S>& only_cost_request) {
      fcl::detail::ShapeShapeCollide<fcl::Box<S>, Shape>(&box, box_tf, &shape, tf_shape, solver, only_cost_request,
                                                         result);
    });
  return result.numContacts();
}

/// A TriangleP: the triangle as a one-triangle mesh (no solver); its contacts then name it as FCL names a shape
/// (o2, b2 = NONE).
template <typename S, typename Solver>
std::size_t meshShape(const fcl::BVHModel<RS<S>>& mesh, const fcl::Transform3<S>& tf_mesh,
                      const fcl::TriangleP<S>& triangle, const fcl::Transform3<S>& tf_triangle, const Solver*,
                      const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  const std::size_t before = result.numContacts();
  const auto triangle_mesh = detail::triangleAsMesh(triangle);
  meshMesh(mesh, tf_mesh, *triangle_mesh, tf_triangle, request, result);
  if (result.numContacts() == before) return before;
  std::vector<fcl::Contact<S>> contacts;
  result.getContacts(contacts);
  std::vector<fcl::CostSource<S>> costs;
  result.getCostSources(costs);
  result.clear();
  for (std::size_t i = 0; i < contacts.size(); ++i)
  {
    if (i >= before)
    {
      contacts[i].o2 = &triangle;
      contacts[i].b2 = fcl::Contact<S>::NONE;
    }
    result.addContact(contacts[i]);
  }
  for (const auto& cost : costs) result.addCostSource(cost, std::numeric_limits<std::size_t>::max());
  return result.numContacts();
}

#if FCL_HAVE_OCTOMAP
/// FCL's drivers of a mesh and an octree (fcl::detail::OcTreeBVHCollide, BVHOcTreeCollide, approximate-cost
/// branch included) with the RS traversal. Contacts name the octree first in either order, as FCL's do.
template <typename S, typename Solver>
std::size_t meshOcTree(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh,
                       const fcl::CollisionGeometry<S>* octree, const fcl::Transform3<S>& tf_octree, bool mesh_first,
                       const Solver* solver, const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  if (request.isSatisfied(result)) return result.numContacts();
  const bool approximate_cost = request.enable_cost && request.use_approximate_cost;
  fcl::CollisionRequest<S> tree_request(request);
  tree_request.enable_cost = request.enable_cost && !approximate_cost;
  collideOcTreeMesh(static_cast<const fcl::OcTree<S>&>(*octree), tf_octree, model, tf_mesh, *solver, tree_request,
                    result);
  if (approximate_cost)
    addApproximateCost(model, tf_mesh, request, result, [&](const fcl::Box<S>& box, const fcl::Transform3<S>& box_tf,
                                                            const fcl::CollisionRequest<S>& only_cost_request) {
      if (mesh_first)
        fcl::detail::ShapeOcTreeCollide<fcl::Box<S>, Solver>(&box, box_tf, octree, tf_octree, solver,
                                                              only_cost_request, result);
      else
        fcl::detail::OcTreeShapeCollide<fcl::Box<S>, Solver>(octree, tf_octree, &box, box_tf, solver,
                                                              only_cost_request, result);
    });
  return result.numContacts();
}
#endif

template <typename S, typename Solver>
std::size_t meshShapeDispatch(const fcl::BVHModel<RS<S>>& model, const fcl::Transform3<S>& tf_mesh,
                              const fcl::CollisionGeometry<S>* shape, const fcl::Transform3<S>& tf_shape,
                              const Solver* solver, const fcl::CollisionRequest<S>& request,
                              fcl::CollisionResult<S>& result)
{
  return detail::withShape(
      *shape,
      [&](const auto& geometry) { return meshShape(model, tf_mesh, geometry, tf_shape, solver, request, result); },
      [&]() -> std::size_t {
        detail::unsupportedPair(kApi, model.getNodeType(), shape->getNodeType(),
                                "FCL has no mesh test for this shape");
      });
}

/// fcl::collide with both poses moved by -tf1's translation (fcl_rs/detail/relative_poses.h: FCL then sees the
/// pair's relative placement). Contacts and cost sources are moved back; the caller's result is filled as
/// fcl::collide fills it.
template <typename S>
std::size_t fclCollideRelative(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                               const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                               const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  if (request.isSatisfied(result)) return result.numContacts();
  const fcl::Vector3<S> shift = tf1.translation();
  const fcl::Transform3<S> near1 = detail::shifted(tf1, shift), near2 = detail::shifted(tf2, shift);
  const std::size_t before = result.numContacts();
  if (!request.enable_cost)
  {
    fcl::collide(o1, near1, o2, near2, request, result);
    // FCL hands its contacts out as const, but they are the caller's own: moved back in place (no copy).
    for (std::size_t i = before; i < result.numContacts(); ++i)
      const_cast<fcl::Contact<S>&>(result.getContact(i)).pos += shift;
    return result.numContacts();
  }
  // Cost sources are kept sorted and cannot be told apart afterwards: a fresh result with the room the caller's has
  // left (FCL counts the contacts already there), merged back.
  const std::size_t room = request.num_max_contacts > before ? request.num_max_contacts - before : 0;
  fcl::CollisionRequest<S> local_request(request);
  local_request.num_max_contacts = std::max<std::size_t>(room, 1);
  fcl::CollisionResult<S> local;
  fcl::collide(o1, near1, o2, near2, local_request, local);
  for (std::size_t i = 0; i < std::min(room, local.numContacts()); ++i)
  {
    fcl::Contact<S> contact = local.getContact(i);
    contact.pos += shift;
    result.addContact(contact);
  }
  std::vector<fcl::CostSource<S>> costs;
  local.getCostSources(costs);
  for (fcl::CostSource<S> cost : costs)
  {
    cost.aabb_min += shift;
    cost.aabb_max += shift;
    result.addCostSource(cost, request.num_max_cost_sources);
  }
  return result.numContacts();
}

/// m1, m2: o1 and o2 as RS meshes (asRSMesh), at least one of them.
template <typename S, typename Solver>
std::size_t collideRS(const fcl::CollisionGeometry<S>* o1, const fcl::BVHModel<RS<S>>* m1, const fcl::Transform3<S>& tf1,
                      const fcl::CollisionGeometry<S>* o2, const fcl::BVHModel<RS<S>>* m2, const fcl::Transform3<S>& tf2,
                      const Solver* solver, const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  if (m1) detail::requireBuiltTriangles(kApi, *m1);
  if (m2) detail::requireBuiltTriangles(kApi, *m2);
  if (m1 && m2) return meshMesh(*m1, tf1, *m2, tf2, request, result);
  const auto pair = detail::meshBeforeOther(o1, m1, tf1, o2, m2, tf2);
#if FCL_HAVE_OCTOMAP
  if (pair.other->getNodeType() == fcl::GEOM_OCTREE)
    return meshOcTree(pair.mesh, pair.tf_mesh, pair.other, pair.tf_other, pair.mesh_first, solver, request, result);
#endif
  if (pair.other->getObjectType() != fcl::OT_GEOM)
    detail::unsupportedPair(kApi, o1->getNodeType(), o2->getNodeType(),
                            "an RS mesh collides with RS meshes, octrees and primitive shapes only");
  return meshShapeDispatch(pair.mesh, pair.tf_mesh, pair.other, pair.tf_other, solver, request, result);
}

}  // namespace

namespace detail {

template <typename S>
std::size_t collideValidated(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                             const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                             const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  if (!o1 || !o2) throw std::invalid_argument("fcl_rs::collide: null collision geometry");
  const auto* m1 = asRSMesh(o1);
  const auto* m2 = asRSMesh(o2);
  if (!m1 && !m2) return fclCollideRelative(o1, tf1, o2, tf2, request, result);
  switch (request.gjk_solver_type)
  {
    case fcl::GST_LIBCCD:
    {
      fcl::detail::GJKSolver_libccd<S> solver;
      solver.collision_tolerance = request.gjk_tolerance;
      return collideRS(o1, m1, tf1, o2, m2, tf2, &solver, request, result);
    }
    case fcl::GST_INDEP:
    {
      fcl::detail::GJKSolver_indep<S> solver;
      solver.gjk_tolerance = request.gjk_tolerance;
      solver.epa_tolerance = request.gjk_tolerance;
      return collideRS(o1, m1, tf1, o2, m2, tf2, &solver, request, result);
    }
  }
  throw std::invalid_argument("fcl_rs::collide: unknown request.gjk_solver_type");
}

}  // namespace detail

template <typename S>
std::size_t collide(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1,
                    const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2,
                    const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  requireRigidTransform(tf1, kApi, "tf1");
  requireRigidTransform(tf2, kApi, "tf2");
  requireValidShape(o1, kApi, "o1");
  requireValidShape(o2, kApi, "o2");
  requireValidRequest(request, kApi);
  return detail::collideValidated(o1, tf1, o2, tf2, request, result);
}

template <typename S>
std::size_t collide(const fcl::CollisionObject<S>* o1, const fcl::CollisionObject<S>* o2,
                    const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  if (!o1 || !o2) throw std::invalid_argument("fcl_rs::collide: null collision object");
  requireRigidTransform(o1->getTransform(), kApi, "o1->getTransform()");
  requireRigidTransform(o2->getTransform(), kApi, "o2->getTransform()");
  requireValidShape(o1->collisionGeometry().get(), kApi, "o1->collisionGeometry()");
  requireValidShape(o2->collisionGeometry().get(), kApi, "o2->collisionGeometry()");
  requireValidRequest(request, kApi);
  return detail::collideValidated(o1->collisionGeometry().get(), o1->getTransform(), o2->collisionGeometry().get(),
                                  o2->getTransform(), request, result);
}

#define FCL_RS_INSTANTIATE_COLLIDE(S)                                                                          \
  template std::size_t detail::collideValidated<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,  \
                                                   const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,  \
                                                   const fcl::CollisionRequest<S>&, fcl::CollisionResult<S>&);   \
  template std::size_t collide<S>(const fcl::CollisionObject<S>*, const fcl::CollisionObject<S>*,               \
                                  const fcl::CollisionRequest<S>&, fcl::CollisionResult<S>&);                    \
  template std::size_t collide<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,                   \
                                  const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,                   \
                                  const fcl::CollisionRequest<S>&, fcl::CollisionResult<S>&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_COLLIDE)
#undef FCL_RS_INSTANTIATE_COLLIDE

}  // namespace fcl_rs
