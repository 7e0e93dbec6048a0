// Exact oracle for triangle pairs (CGAL exact predicates and constructions), in one translation unit so that no
// other test compiles CGAL. Triangles are the double vertices as computed (floats convert exactly); any of them
// may be degenerate (collinear vertices, a segment, a point), and all are closed sets.
#ifndef FCL_RS_TESTS_EXACT_ORACLE_H
#define FCL_RS_TESTS_EXACT_ORACLE_H

#include <array>

#include <Eigen/Core>

namespace fcl_rs {
namespace test {

using ExactTriangle = std::array<Eigen::Vector3d, 3>;

/// Whether the closed triangles share a point, decided exactly.
bool exactlyIntersect(const ExactTriangle& a, const ExactTriangle& b);

/// Their distance: exact squared distance, rounded once to double, then its square root.
double exactDistance(const ExactTriangle& a, const ExactTriangle& b);

}  // namespace test
}  // namespace fcl_rs

#endif
