// Exact oracle for triangle pairs (CGAL exact predicates and constructions), in one translation unit so that no
// other test compiles CGAL. Triangles are the double vertices as computed (floats convert exactly); any of them
// may be degenerate (collinear vertices, a segment, a point), and all are closed sets.
#ifndef FCL_RS_TESTS_EXACT_ORACLE_H
#define FCL_RS_TESTS_EXACT_ORACLE_H

#include <array>
#include <vector>

#include <Eigen/Core>

namespace fcl_rs {
namespace test {

using ExactTriangle = std::array<Eigen::Vector3d, 3>;

/// Whether the closed triangles share a point, decided exactly.
bool exactlyIntersect(const ExactTriangle& a, const ExactTriangle& b);

/// Their distance: exact squared distance, rounded once to double, then its square root.
double exactDistance(const ExactTriangle& a, const ExactTriangle& b);

/// A primitive at a pose: the image of the shape in its own frame under x -> R x + t, computed exactly from the
/// double entries as given (so a rotation that is orthonormal only to rounding maps the shape exactly as written).
struct ExactPose
{
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
};

/// A triangle (world frame) against a primitive: whether they share a point (exact) and their distance (0 when
/// they meet; else the exact squared distance rounded once to double, its square root, minus a radius if any).
struct ExactShapeAnswer
{
  bool meets;
  double distance;
};

/// Sphere of the radius centred at pose.t.
ExactShapeAnswer exactSphere(const ExactTriangle& a, const ExactPose& pose, double radius);
/// Capsule: the points within the radius of the segment from R (0, 0, -half_length) + t to R (0, 0, half_length) + t.
ExactShapeAnswer exactCapsule(const ExactTriangle& a, const ExactPose& pose, double radius, double half_length);
/// Convex polytope given by its vertices (shape frame) and its boundary as triangles of vertex indices (each face
/// fanned); the polytope is the union of the tetrahedra from the vertices' mean to each boundary triangle.
ExactShapeAnswer exactPolytope(const ExactTriangle& a, const ExactPose& pose, const std::vector<Eigen::Vector3d>& vertices,
                               const std::vector<std::array<int, 3>>& boundary);
/// Plane n . x = d (shape frame; n as given, not assumed unit) and halfspace n . x <= d: the triangle's vertices
/// are mapped back to the shape's frame exactly (R^-1 by its adjugate), so the distance is measured there.
ExactShapeAnswer exactPlane(const ExactTriangle& a, const ExactPose& pose, const Eigen::Vector3d& n, double d);
ExactShapeAnswer exactHalfspace(const ExactTriangle& a, const ExactPose& pose, const Eigen::Vector3d& n, double d);

}  // namespace test
}  // namespace fcl_rs

#endif
