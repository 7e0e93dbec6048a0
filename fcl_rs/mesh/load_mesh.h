// Loading triangle meshes from files with assimp.
#ifndef FCL_RS_MESH_LOAD_MESH_H
#define FCL_RS_MESH_LOAD_MESH_H

#include <string>
#include <utility>

#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// Loads every mesh of a file (any format assimp reads: OBJ, STL, PLY, DAE, OFF, ...) into one
/// triangle mesh, with node transforms applied, polygons triangulated and identical vertices joined;
/// point and line primitives are dropped. Collada files keep their own axes (no turn of a Z_UP file to Y up, as
/// ROS reads them) and their <unit> scale. The result passes validateMesh. Throws std::runtime_error
/// naming the file and the problem when it cannot be read or parsed, a face index is out of range, a
/// coordinate is not finite (naming the vertex), or it holds no triangles (points or lines only).
TriangleMesh<double> loadMeshFile(const std::string& path);

template <typename S>
TriangleMesh<S> loadMesh(const std::string& path)
{
  TriangleMesh<double> m = loadMeshFile(path);
  TriangleMesh<S> out;
  out.vertices.reserve(m.vertices.size());
  for (const auto& v : m.vertices) out.vertices.push_back(v.cast<S>());
  out.triangles = std::move(m.triangles);
  return out;
}

}  // namespace fcl_rs

#endif
