// Triangle meshes as vertex and index arrays, and the validation every entry point applies to them.
#ifndef FCL_RS_MESH_TRIANGLE_MESH_H
#define FCL_RS_MESH_TRIANGLE_MESH_H

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/common/types.h>
#include <fcl/math/triangle.h>


namespace fcl_rs {

/// Vertices and triangles of a mesh, in the file's own coordinates.
template <typename S>
struct TriangleMesh
{
  std::vector<fcl::Vector3<S>> vertices;
  std::vector<fcl::Triangle> triangles;
};

/// Throws std::invalid_argument naming the first vertex with a NaN or Inf coordinate.
template <typename S>
void validateVertices(const std::vector<fcl::Vector3<S>>& vertices)
{
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!vertices[i].allFinite())
    {
      std::ostringstream msg;
      msg << "fcl_rs: vertex " << i << " has a non-finite coordinate (" << vertices[i].transpose() << ")";
      throw std::invalid_argument(msg.str());
    }
}

/// Throws std::invalid_argument when the mesh is empty, has a non-finite vertex or a triangle
/// index out of range; the message names the offending vertex or triangle.
template <typename S>
void validateMesh(const std::vector<fcl::Vector3<S>>& vertices, const std::vector<fcl::Triangle>& triangles)
{
  if (vertices.empty() || triangles.empty())
    throw std::invalid_argument("fcl_rs: empty mesh (" + std::to_string(vertices.size()) + " vertices, " +
                                std::to_string(triangles.size()) + " triangles)");
  validateVertices(vertices);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      if (triangles[t][c] >= vertices.size())
        throw std::invalid_argument("fcl_rs: triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(triangles[t][c]) + " but the mesh has " +
                                    std::to_string(vertices.size()) + " vertices");
}

}  // namespace fcl_rs

#endif
