// Triangle meshes: loading files with assimp, validating input, building and refitting BVHModel trees of any BV type.
#ifndef FCL_RS_MESH_IO_H
#define FCL_RS_MESH_IO_H

#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/rs_split.h"

namespace fcl_rs {

/// Vertices and triangles of a mesh, in the file's own coordinates.
template <typename S>
struct TriangleMesh
{
  std::vector<fcl::Vector3<S>> vertices;
  std::vector<fcl::Triangle> triangles;
};

/// Loads every mesh of a file (any format assimp reads: OBJ, STL, PLY, DAE, OFF, ...) into one
/// triangle mesh, with node transforms applied, polygons triangulated and identical vertices joined;
/// point and line primitives are dropped. The result passes validateMesh. Throws std::runtime_error
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

/// The splitter buildModel uses unless told otherwise: SurfaceAreaSplitter for RS (fewer BV tests per query
/// for a little build time, measured in docs/tradeoff.md), FCL's mean split for FCL's own types.
template <typename BV>
std::shared_ptr<fcl::detail::BVSplitterBase<BV>> defaultSplitter()
{
  if constexpr (std::is_same<BV, RS<typename BV::S>>::value)
    return std::make_shared<SurfaceAreaSplitter<typename BV::S>>();
  else
    return std::make_shared<fcl::detail::BVSplitter<BV>>(fcl::detail::SPLIT_METHOD_MEAN);
}

/// A built BVHModel<BV> of the mesh (any BV type: RS or FCL's), split by splitter. Validates the input first.
template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                                              const std::vector<fcl::Triangle>& triangles,
                                              std::shared_ptr<fcl::detail::BVSplitterBase<BV>> splitter = defaultSplitter<BV>())
{
  validateMesh(vertices, triangles);
  auto model = std::make_shared<fcl::BVHModel<BV>>();
  model->bv_splitter = std::move(splitter);
  if (model->beginModel(int(triangles.size()), int(vertices.size())) != fcl::BVH_OK ||
      model->addSubModel(vertices, triangles) != fcl::BVH_OK || model->endModel() != fcl::BVH_OK)
    throw std::runtime_error("fcl_rs: FCL refused to build the BVH model");
  return model;
}

/// The same with FCL's splitter and the given split rule (SPLIT_METHOD_MEAN: FCL's default).
template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                                              const std::vector<fcl::Triangle>& triangles,
                                              fcl::detail::SplitMethodType split)
{
  return buildModel<BV>(vertices, triangles, std::make_shared<fcl::detail::BVSplitter<BV>>(split));
}

/// Either of the above for a TriangleMesh (rule: nothing, a splitter or a SplitMethodType).
template <typename BV, typename... Rule>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const TriangleMesh<typename BV::S>& mesh, Rule&&... rule)
{
  return buildModel<BV>(mesh.vertices, mesh.triangles, std::forward<Rule>(rule)...);
}

/// Moves the vertices of a built model (same triangles, same tree structure) and refits its volumes,
/// bottom-up or top-down: FCL's beginReplaceModel / replaceSubModel / endReplaceModel(refit) with a strong
/// guarantee. Wrong vertex count, a non-finite vertex or an unbuilt model throw std::invalid_argument
/// before anything is touched (FCL's replaceSubModel would write past the vertex array, and the RS fitter
/// would throw halfway through the refit, leaving a model that fcl_rs::collide refuses). If the refit
/// throws anyway, the vertices, volumes and state are restored, so the model answers queries as before.
template <typename BV>
void refitModel(fcl::BVHModel<BV>& model, const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                bool bottomup = true)
{
  using S = typename BV::S;
  if (model.build_state != fcl::BVH_BUILD_STATE_PROCESSED)
    throw std::invalid_argument("fcl_rs::refitModel: the model is not in FCL's built state (build_state " +
                                std::to_string(int(model.build_state)) + "); finish it with endModel() first");
  if (vertices.size() != std::size_t(model.num_vertices))
    throw std::invalid_argument("fcl_rs::refitModel: " + std::to_string(vertices.size()) +
                                " vertices given for a model of " + std::to_string(model.num_vertices));
  validateVertices(vertices);

  const std::vector<fcl::Vector3<S>> old_vertices(model.vertices, model.vertices + model.num_vertices);
  std::vector<fcl::Vector3<S>> old_prev;
  if (model.prev_vertices) old_prev.assign(model.prev_vertices, model.prev_vertices + model.num_vertices);
  std::vector<fcl::BVNode<BV>> old_bvs;
  old_bvs.reserve(std::size_t(model.getNumBVs()));
  for (int i = 0; i < model.getNumBVs(); ++i) old_bvs.push_back(model.getBV(i));
  try
  {
    if (model.beginReplaceModel() != fcl::BVH_OK || model.replaceSubModel(vertices) != fcl::BVH_OK ||
        model.endReplaceModel(true, bottomup) != fcl::BVH_OK)
      throw std::runtime_error("fcl_rs::refitModel: FCL refused to refit the model");
  }
  catch (...)
  {
    std::copy(old_vertices.begin(), old_vertices.end(), model.vertices);
    if (!old_prev.empty())  // beginReplaceModel deleted them
    {
      delete[] model.prev_vertices;
      model.prev_vertices = new fcl::Vector3<S>[old_prev.size()];
      std::copy(old_prev.begin(), old_prev.end(), model.prev_vertices);
    }
    for (int i = 0; i < model.getNumBVs(); ++i) model.getBV(i) = old_bvs[std::size_t(i)];
    model.build_state = fcl::BVH_BUILD_STATE_PROCESSED;
    throw;
  }
  model.computeLocalAABB();
}

}  // namespace fcl_rs

#endif
