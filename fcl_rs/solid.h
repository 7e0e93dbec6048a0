// Solid meshes (opt-in, beyond FCL): closed RS meshes whose interior counts. One mesh inside the other collides,
// and colliding pairs can report a "vertex penetration depth". FCL (and fcl_rs::collide) treat meshes as surfaces.
// docs/solid.md states what the queries are and are not.
#ifndef FCL_RS_SOLID_H
#define FCL_RS_SOLID_H

#include <cstddef>
#include <memory>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

/// Where a point lies with respect to a closed mesh.
enum class SolidSide
{
  kOutside,
  kInside,
  kOnSurface,  ///< within rounding of the surface: every ray of the fixed direction sequence had an uncertain sign
};

/// A built RS mesh known to be closed: every undirected edge is used by exactly two triangles, which run it in
/// opposite directions (a consistently oriented 2-manifold edge set; the orientation itself, outward or inward,
/// does not matter). The mesh may have several components; nested components count by parity (a hollow shell
/// is a solid with a cavity). Self-intersecting meshes are not detected and have no meaningful inside.
template <typename S>
class SolidMesh
{
public:
  using Model = fcl::BVHModel<RS<S>>;

  /// Checks closedness in O(n log n) for n triangles. Throws std::invalid_argument for a null or empty (unbuilt)
  /// model, a triangle repeating a vertex, and the first bad edge (by vertex indices) otherwise: a boundary edge
  /// (one triangle), an edge shared by k > 2 triangles, or two triangles running the edge the same way
  /// (inconsistent orientation). The model is shared, not copied; it must not be modified afterwards.
  explicit SolidMesh(std::shared_ptr<const Model> model);

  const Model& model() const { return *model_; }
  const std::shared_ptr<const Model>& modelPtr() const { return model_; }
  /// The vertices some triangle uses (indices into model().vertices), each once.
  const std::vector<std::size_t>& usedVertices() const { return used_vertices_; }
  /// One vertex of each connected component of the surface (containment tests one per component).
  const std::vector<std::size_t>& componentVertices() const { return component_vertices_; }

  /// Point p (model coordinates) against the solid: ray parity through the tree. A ray crossing is decided from
  /// the signs of triple products, each with the leaf test's filtered error bound (detail::CertainAxis). A ray
  /// whose sign is uncertain anywhere (it grazes an edge or a vertex, or p is on a triangle's plane inside it) is
  /// dropped for the next of a fixed sequence of directions (the x axis first, then 32 golden-spiral directions);
  /// kOnSurface when every direction was uncertain, i.e. p is within rounding of the surface. Cost: a tree walk
  /// per direction tried. A NaN or infinite coordinate throws std::invalid_argument (so does distanceToSurface).
  SolidSide classify(const fcl::Vector3<S>& p) const;
  /// Whether p is in the closed solid: inside, or on its surface within rounding (kOnSurface counts as inside).
  bool contains(const fcl::Vector3<S>& p) const { return classify(p) != SolidSide::kOutside; }
  /// Distance from p (model coordinates) to the surface (the nearest triangle), through the tree; *nearest, if
  /// given, receives the nearest point. Closest points on triangles are the mesh-shape leaf's
  /// (triangle_shape::closestOnTriangle, in double).
  S distanceToSurface(const fcl::Vector3<S>& p, fcl::Vector3<S>* nearest = nullptr) const;

private:
  std::shared_ptr<const Model> model_;
  std::vector<std::size_t> used_vertices_;
  std::vector<std::size_t> component_vertices_;
};

struct SolidCollisionRequest
{
  /// One mesh entirely inside the other counts as a collision. Off: the answer is exactly fcl_rs::collide's.
  bool containment = true;
  /// Compute the vertex penetration depth of a colliding pair (docs/solid.md); costs a point test and a
  /// point-surface distance per vertex that may lie inside the other mesh.
  bool penetration_depth = false;
};

enum class SolidContact
{
  kNone,
  kSurfacesIntersect,  ///< the surfaces meet (fcl_rs::collide)
  kFirstInsideSecond,  ///< surfaces apart, the first mesh inside the second solid
  kSecondInsideFirst,  ///< surfaces apart, the second mesh inside the first solid
};

template <typename S>
struct SolidCollisionResult
{
  bool collision = false;
  SolidContact contact = SolidContact::kNone;
  /// Whether the depth fields below were computed (request.penetration_depth and a collision).
  bool has_penetration_depth = false;
  /// The vertex penetration depth: the largest distance from a vertex of either mesh inside the other solid to the
  /// other's surface; 0 when no vertex is inside the other (two boxes crossing edge through edge). A lower bound on
  /// the minimum translation distance, not that distance (docs/solid.md).
  S penetration_depth = 0;
  /// Which mesh the deepest vertex belongs to: 0 the first, 1 the second, -1 none (depth 0 or not computed).
  int deepest_mesh = -1;
  /// The deepest vertex and its nearest point on the other mesh's surface, world coordinates.
  fcl::Vector3<S> deepest_vertex = fcl::Vector3<S>::Zero();
  fcl::Vector3<S> nearest_on_other = fcl::Vector3<S>::Zero();
};

/// Collision of two solids at poses tfa, tfb. Surfaces first (fcl_rs::collide, first contact); then, with
/// request.containment, one vertex of each connected component of each mesh tested inside the other solid (with the
/// surfaces apart, one vertex decides for its whole component). Throws std::invalid_argument naming tfa or tfb when a pose is not a rigid
/// transform (fcl_rs/validate.h).
template <typename S>
SolidCollisionResult<S> collideSolids(const SolidMesh<S>& a, const fcl::Transform3<S>& tfa, const SolidMesh<S>& b,
                                      const fcl::Transform3<S>& tfb, const SolidCollisionRequest& request = {});

extern template class SolidMesh<float>;
extern template class SolidMesh<double>;
extern template SolidCollisionResult<float> collideSolids<float>(const SolidMesh<float>&, const fcl::Transform3<float>&,
                                                                 const SolidMesh<float>&, const fcl::Transform3<float>&,
                                                                 const SolidCollisionRequest&);
extern template SolidCollisionResult<double> collideSolids<double>(const SolidMesh<double>&,
                                                                   const fcl::Transform3<double>&,
                                                                   const SolidMesh<double>&,
                                                                   const fcl::Transform3<double>&,
                                                                   const SolidCollisionRequest&);

}  // namespace fcl_rs

#endif
