// Mesh file loading through assimp.
#include "fcl_rs/mesh_io.h"

#include <cmath>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace fcl_rs {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem)
{
  throw std::runtime_error("fcl_rs: mesh file '" + path + "': " + problem);
}

/// Non-finite coordinates are rejected before post-processing: joining identical vertices silently merges a NaN
/// vertex into another one, and a node transform turns one Inf coordinate into NaNs in the others.
void checkFinite(const aiScene& scene, const std::string& path)
{
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
  {
    const aiMesh& mesh = *scene.mMeshes[m];
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    {
      const aiVector3D& p = mesh.mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      {
        std::ostringstream msg;
        msg << "vertex " << v << " of mesh " << m << " has a non-finite coordinate (" << p.x << ' ' << p.y << ' ' << p.z
            << ')';
        fail(path, msg.str());
      }
    }
  }
}

struct Counts
{
  unsigned points = 0, lines = 0;
};

void appendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, TriangleMesh<double>& out,
                Counts& dropped)
{
  const aiMatrix4x4 tf = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m)
  {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const auto base = unsigned(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    {
      const aiVector3D p = tf * mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f)
    {
      const aiFace& face = mesh.mFaces[f];
      // Triangulation leaves only points and lines with other counts: they carry no surface.
      if (face.mNumIndices == 3)
        out.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
      else
        ++(face.mNumIndices < 2 ? dropped.points : dropped.lines);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) appendNode(scene, *node.mChildren[c], tf, out, dropped);
}

}  // namespace

TriangleMesh<double> loadMeshFile(const std::string& path)
{
  Assimp::Importer importer;
  // Validation alone first (assimp checks face indices against the vertex count), then our own check of the raw
  // coordinates, then the post-processing.
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw std::runtime_error("fcl_rs: cannot read mesh file '" + path + "': " + importer.GetErrorString());
  checkFinite(*scene, path);
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene) throw std::runtime_error("fcl_rs: cannot process mesh file '" + path + "': " + importer.GetErrorString());
  TriangleMesh<double> mesh;
  Counts dropped;
  appendNode(*scene, *scene->mRootNode, aiMatrix4x4(), mesh, dropped);
  if (mesh.triangles.empty())
    fail(path, "contains no triangles (" + std::to_string(dropped.points) + " point and " +
                   std::to_string(dropped.lines) + " line primitives; a collision mesh needs faces)");
  try
  {
    validateMesh(mesh.vertices, mesh.triangles);  // e.g. a node transform that overflows a coordinate
  }
  catch (const std::invalid_argument& e)
  {
    fail(path, e.what());
  }
  return mesh;
}

}  // namespace fcl_rs
