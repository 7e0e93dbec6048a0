// Triangle meshes: loading files with assimp, validating input, building BVHModel trees of any BV type.
#ifndef FCL_RS_MESH_IO_H
#define FCL_RS_MESH_IO_H

#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

namespace fcl_rs {

/// Vertices and triangles of a mesh, in the file's own coordinates.
template <typename S>
struct TriangleMesh
{
  std::vector<fcl::Vector3<S>> vertices;
  std::vector<fcl::Triangle> triangles;
};

/// Loads every mesh of a file (any format assimp reads: OBJ, STL, PLY, DAE, OFF, ...) into one
/// triangle mesh, with node transforms applied, polygons triangulated and identical vertices joined.
/// Throws std::runtime_error naming the file when it cannot be read or holds no triangles.
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

/// Throws std::invalid_argument when the mesh is empty, has a non-finite vertex or a triangle
/// index out of range; the message names the offending vertex or triangle.
template <typename S>
void validateMesh(const std::vector<fcl::Vector3<S>>& vertices, const std::vector<fcl::Triangle>& triangles)
{
  if (vertices.empty() || triangles.empty())
    throw std::invalid_argument("fcl_rs: empty mesh (" + std::to_string(vertices.size()) + " vertices, " +
                                std::to_string(triangles.size()) + " triangles)");
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!vertices[i].allFinite())
    {
      std::ostringstream msg;
      msg << "fcl_rs: vertex " << i << " has a non-finite coordinate (" << vertices[i].transpose() << ")";
      throw std::invalid_argument(msg.str());
    }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      if (triangles[t][c] >= vertices.size())
        throw std::invalid_argument("fcl_rs: triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(triangles[t][c]) + " but the mesh has " +
                                    std::to_string(vertices.size()) + " vertices");
}

/// A built BVHModel<BV> of the mesh (any BV type: RS or FCL's). Validates the input first.
template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                                              const std::vector<fcl::Triangle>& triangles,
                                              fcl::detail::SplitMethodType split = fcl::detail::SPLIT_METHOD_MEAN)
{
  validateMesh(vertices, triangles);
  auto model = std::make_shared<fcl::BVHModel<BV>>();
  model->bv_splitter.reset(new fcl::detail::BVSplitter<BV>(split));
  if (model->beginModel(int(triangles.size()), int(vertices.size())) != fcl::BVH_OK ||
      model->addSubModel(vertices, triangles) != fcl::BVH_OK || model->endModel() != fcl::BVH_OK)
    throw std::runtime_error("fcl_rs: FCL refused to build the BVH model");
  return model;
}

template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const TriangleMesh<typename BV::S>& mesh,
                                              fcl::detail::SplitMethodType split = fcl::detail::SPLIT_METHOD_MEAN)
{
  return buildModel<BV>(mesh.vertices, mesh.triangles, split);
}

}  // namespace fcl_rs

#endif
