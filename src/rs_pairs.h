// Shared by the drop-in entry points (src/collide.cpp, src/distance.cpp): recognising RS meshes and the
// errors for pairs they cannot answer. `api` names the entry point in messages ("fcl_rs::collide").
#ifndef FCL_RS_SRC_RS_PAIRS_H
#define FCL_RS_SRC_RS_PAIRS_H

#include <sstream>
#include <stdexcept>
#include <string>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/triangle_p.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/build_model.h"

namespace fcl_rs {
namespace detail {

/// g as an RS mesh, or nullptr. A shape or octree is told by its object type, without the dynamic_cast, which
/// costs a small query about what its traversal's set-up does.
template <typename S>
const fcl::BVHModel<RS<S>>* asRSMesh(const fcl::CollisionGeometry<S>* g)
{
  if (g->getObjectType() != fcl::OT_BVH) return nullptr;
  return dynamic_cast<const fcl::BVHModel<RS<S>>*>(g);
}

[[noreturn]] inline void unsupportedPair(const char* api, int node_type1, int node_type2, const char* why)
{
  std::ostringstream msg;
  msg << api << ": pair of node types " << node_type1 << " and " << node_type2
      << " (fcl::NODE_TYPE; an RS mesh reports 0, BV_UNKNOWN) is not supported: " << why;
  throw std::invalid_argument(msg.str());
}

template <typename S>
void requireBuiltTriangles(const char* api, const fcl::BVHModel<RS<S>>& m)
{
  if (m.getModelType() != fcl::BVH_MODEL_TRIANGLES)
    throw std::invalid_argument(std::string(api) + ": an RS model must be a triangle mesh (BVH_MODEL_TRIANGLES)");
  if (m.build_state != fcl::BVH_BUILD_STATE_PROCESSED && m.build_state != fcl::BVH_BUILD_STATE_UPDATED)
    throw std::invalid_argument(std::string(api) + ": an RS model's tree is not built (call endModel() first)");
}

/// An RS mesh and the geometry it meets, in the order the RS traversals take them: as in fcl::collide and
/// fcl::distance, a shape or octree given first goes behind the mesh.
template <typename S>
struct MeshAndOther
{
  const fcl::BVHModel<RS<S>>& mesh;
  const fcl::Transform3<S>& tf_mesh;
  const fcl::CollisionGeometry<S>* other;
  const fcl::Transform3<S>& tf_other;
  bool mesh_first;  ///< whether the caller gave the mesh first
};

/// m1 and m2 are o1 and o2 as RS meshes (asRSMesh); at least one is not null. With two meshes, the first leads.
template <typename S>
MeshAndOther<S> meshBeforeOther(const fcl::CollisionGeometry<S>* o1, const fcl::BVHModel<RS<S>>* m1,
                                const fcl::Transform3<S>& tf1, const fcl::CollisionGeometry<S>* o2,
                                const fcl::BVHModel<RS<S>>* m2, const fcl::Transform3<S>& tf2)
{
  if (m1) return {*m1, tf1, o2, tf2, true};
  return {*m2, tf2, o1, tf1, false};
}

/// A TriangleP as a one-triangle RS mesh in the triangle's own frame: mesh-TriangleP pairs run the mesh-mesh
/// triangle tests (FCL's libccd solver has no TriangleP support function, and FCL no mesh-TriangleP entry).
template <typename S>
std::shared_ptr<fcl::BVHModel<RS<S>>> triangleAsMesh(const fcl::TriangleP<S>& triangle)
{
  return buildModel<RS<S>>({triangle.a, triangle.b, triangle.c}, {fcl::Triangle(0, 1, 2)});
}

}  // namespace detail
}  // namespace fcl_rs

#endif
