// Drop-in fcl_rs::distance: RS mesh pairs take the local-frame RS path, every other pair goes to fcl::distance.
#ifndef FCL_RS_DISTANCE_H
#define FCL_RS_DISTANCE_H

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

/// Same overloads and meaning as fcl::distance. Pairs with a BVHModel<RS<S>> (mesh-mesh, and mesh
/// against Box, Sphere, Ellipsoid, Capsule, Cone, Cylinder, Convex, Plane, Halfspace, TriangleP or an fcl::OcTree
/// in either order) are handled here (Plane, Halfspace and TriangleP beyond FCL, whose mesh-plane and
/// mesh-halfspace distance crashes and which has no mesh-TriangleP entry);
/// every other pair is passed to fcl::distance unchanged, except that a pair of shapes with a Plane or a Halfspace
/// throws std::invalid_argument: FCL's own distance for them calls a null support function (a crash), and the signed
/// distance of two shapes is computed here for either gjk_solver_type (FCL's libccd EPA ran for minutes on concentric
/// and coaxial pairs, GJKSolver_indep's depths of curved shapes are far off): in closed form for a sphere or capsule
/// against a sphere or capsule and for a sphere against a box, cylinder or cone, else by libccd's GJK and EPA with
/// EPA bounded to 1000 expansions (milliseconds); a depth then within distance_tolerance, or 1e-3 relative where EPA
/// converges slowly, else std::runtime_error naming both bounds; where EPA's polytope gets a zero-area face (built
/// without NDEBUG, FCL throws fcl::detail::FailedAtThisConfiguration) the pair is measured again in a turned frame
/// (src/shape_signed_distance.h).
///
/// As in FCL: a shape given first is swapped behind the mesh, so result.o1, b1 and nearest_points[0]
/// then refer to the mesh; nearest points are in the world frame; a colliding pair reports what FCL's
/// OBBRSS reports for it (mesh-mesh, mesh-sphere and mesh-TriangleP 0, mesh and any
/// other shape -1; docs/distance.md), and
/// with enable_signed_distance a negative distance is replaced by minus the deepest contact's
/// penetration (found by fcl_rs::collide). Unlike FCL's oriented trees, request.rel_err and abs_err
/// are honoured: the result is within (1 + rel_err) times and abs_err of the true distance.
/// fcl::distance cannot reach RS (its dispatch table is hidden inside libfcl.so) and would return
/// max(); this function never does. An RS mesh against anything it cannot handle (another BV type's
/// mesh) throws std::invalid_argument naming the pair. So does bad
/// input, for every pair, before any test (fcl_rs/validate.h): a pose that is not a rigid transform, naming the
/// argument; an invalid request field (rel_err, abs_err, distance_tolerance), naming the field.
template <typename S>
S distance(const fcl::CollisionObject<S>* o1, const fcl::CollisionObject<S>* o2,
           const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result);

template <typename S>
S distance(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1, const fcl::CollisionGeometry<S>* o2,
           const fcl::Transform3<S>& tf2, const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result);

#define FCL_RS_DECLARE_DISTANCE(S)                                                                            \
  extern template S distance<S>(const fcl::CollisionObject<S>*, const fcl::CollisionObject<S>*,              \
                                const fcl::DistanceRequest<S>&, fcl::DistanceResult<S>&);                    \
  extern template S distance<S>(const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,                 \
                                const fcl::CollisionGeometry<S>*, const fcl::Transform3<S>&,                 \
                                const fcl::DistanceRequest<S>&, fcl::DistanceResult<S>&);
FCL_RS_DECLARE_DISTANCE(float)
FCL_RS_DECLARE_DISTANCE(double)
#undef FCL_RS_DECLARE_DISTANCE

}  // namespace fcl_rs

#endif
